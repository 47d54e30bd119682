// How fast the simulator casts and encodes VLP-16 and RS-Helios packets
// against the paper scene, compared with the sensors' real 753.5 and
// 1499.9 packets/s. The sim
// must stay well above 1x to run in real time (and leave the CPU to the
// stack); the figure also bounds what --speed can reach.
#include <benchmark/benchmark.h>

#include <string>

#include "sim/lidar_sim.h"
#include "sim/motion.h"
#include "sim/rs_helios_sim.h"
#include "sim/scenario.h"

namespace {
using namespace evade::sim;

// paper_sim's scene with the robot driving along x at 1 m/s.
WorldAt paper_world(const Scenario& sc, int64_t start) {
  return [sc, start](int64_t t, WorldSnapshot* out) {
    double ts = (t - start) * 1e-6;
    out->robot = Pose2{sc.start.x + 1.0 * ts, sc.start.y, 0.0};
    out->solids.resize(sc.obstacles.size());
    for (size_t i = 0; i < sc.obstacles.size(); ++i) {
      const ObstacleSpec& o = sc.obstacles[i];
      ObstacleState st = obstacle_state(o, ts);
      out->solids[i] = Solid{o.shape, st.x, st.y, o.yaw, o.radius, o.length, o.width, o.height};
    }
  };
}

LidarSimParams paper_params(const Scenario& sc) {
  LidarSimParams p;
  p.rate_hz = sc.lidar.rate_hz;
  p.range_noise_std_m = sc.lidar.range_noise_std;
  p.mount_height_m = sc.lidar.height;
  return p;
}

void BM_PaperScenePackets(benchmark::State& state) {
  Scenario sc = load_scenario(std::string(EVADE_SOURCE_DIR) + "/config/scenarios/paper_sim.yaml");
  const int64_t start = 1'700'000'000'000'000;
  Vlp16Simulator sim(paper_params(sc), start);
  WorldAt world = paper_world(sc, start);
  for (auto _ : state) {
    Packet pk = sim.make_packet(world);
    benchmark::DoNotOptimize(pk);
  }
  state.SetItemsProcessed(state.iterations());
  // x real time: packets per second over the sensor's 753.5 per second.
  state.counters["x_real_time"] =
      benchmark::Counter(static_cast<double>(state.iterations()) / 753.5, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PaperScenePackets);

// The same scene through the RS-Helios (MSOP only; a DIFOP a second costs nothing).
void BM_PaperSceneHeliosPackets(benchmark::State& state) {
  Scenario sc = load_scenario(std::string(EVADE_SOURCE_DIR) + "/config/scenarios/paper_sim.yaml");
  const int64_t start = 1'700'000'000'000'000;
  RsHeliosSimulator sim(paper_params(sc), start);
  WorldAt world = paper_world(sc, start);
  for (auto _ : state) {
    Packet pk = sim.make_packet(world);
    benchmark::DoNotOptimize(pk);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["x_real_time"] =
      benchmark::Counter(static_cast<double>(state.iterations()) / 1499.9, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PaperSceneHeliosPackets);

}  // namespace

BENCHMARK_MAIN();
