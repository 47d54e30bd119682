// Local map cost per LiDAR revolution (goal: 3 ms on one core): a ray-cast
// VLP-16 revolution (16 rings x 1800 azimuths = 28,800 beams, the 8 upward
// rings hitting obstacles only) over ground, cylinders and a box, with the
// robot driving, through crop + motion-compensated binning + hole filling +
// the obstacle layer; and the same with the whole message path of the core.
#include <benchmark/benchmark.h>

#include "bus/memory_bus.h"
#include "mapping/elevation_map.h"
#include "mapping/elevation_map_core.h"
#include "mapping/synthetic_scan.h"

namespace evade::mapping {
namespace {

SynthWorld busy_world() {
  SynthWorld w;
  // a ring of obstacles all around, so the upward beams return too
  for (int k = 0; k < 24; ++k) {
    const double a = 2.0 * M_PI * k / 24.0, r = 2.0 + (k % 4);
    w.cylinders.push_back({r * std::cos(a), r * std::sin(a), 0.25 + 0.05 * (k % 2), 0.5 + 1.2 * (k % 2)});
  }
  w.boxes.push_back({3.0, -3.0, 0.3, 1.0, 2.0, 1.0});
  // walls 6 m away catch every upward beam: a full 28,800-point revolution
  w.boxes.push_back({6.0, 0.0, 0.0, 0.2, 12.2, 4.0});
  w.boxes.push_back({-6.0, 0.0, 0.0, 0.2, 12.2, 4.0});
  w.boxes.push_back({0.0, 6.0, 0.0, 12.2, 0.2, 4.0});
  w.boxes.push_back({0.0, -6.0, 0.0, 12.2, 0.2, 4.0});
  return w;
}

SynthScanOptions moving() {
  SynthScanOptions o;
  o.v = 1.0;
  o.omega = 0.3;
  o.range_noise_std_m = 0.01;
  return o;
}

void BM_BuildElevationMap(benchmark::State& state) {
  const SynthCloud c = synth_vlp16(busy_world(), moving());
  PoseBuffer poses(2'000'000);
  for (int64_t t = 0; t <= 400'000; t += 20'000) {
    const Pose2 p = integrate_unicycle({}, 1.0, 0.3, (t - 100'000) * 1e-6);
    poses.add({t, p, 1.0, 0.3});
  }
  const CloudView v = view_of(c, 100'000, 0.5);
  // the argument: the side of the square map, m (the paper's 10 m; config elevation_map.size_x_m)
  ElevationMapParams params;
  params.size_x_m = params.size_y_m = static_cast<double>(state.range(0));
  ElevationMapBuilder b{params};
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  for (auto _ : state) {
    b.build(v, poses, &L, &robot, &st);
    benchmark::DoNotOptimize(L.obstacle.data());
  }
  state.counters["points"] = double(st.points_in);
  state.counters["binned"] = double(st.points_binned);
}
BENCHMARK(BM_BuildElevationMap)->Arg(10)->Arg(16)->Arg(24)->Unit(benchmark::kMillisecond);

void BM_ObstacleLayerOnly(benchmark::State& state) {
  ElevationLayers L;
  L.reset(0, 0, 0.1, 100, 100);
  for (size_t i = 0; i < L.z_max.size(); ++i) L.z_max[i] = L.z_min[i] = float((i * 7919) % 13) * 0.01f;
  const ElevationMapParams p;
  for (auto _ : state) {
    compute_obstacle_layer(p, &L);
    benchmark::DoNotOptimize(L.obstacle.data());
  }
}
BENCHMARK(BM_ObstacleLayerOnly)->Unit(benchmark::kMillisecond);

// decode LIDAR_POINTS + build + encode ELEVATION_MAP, as the process does
void BM_CoreWithMessages(benchmark::State& state) {
  const SynthCloud c = synth_vlp16(busy_world(), moving());
  evade::pointcloud_t m;
  m.utime = 100'000;
  m.sensor_model = "vlp16";
  m.mount = {};
  m.mount.z = 0.5;
  m.packets = 0;
  m.n = int32_t(c.x.size());
  m.x = c.x;
  m.y = c.y;
  m.z = c.z;
  m.intensity.assign(c.x.size(), 0.0f);
  m.ring.assign(c.x.size(), 0);
  m.time_offset = c.time_offset;
  const auto bytes = bus::encode(m);
  bus::MemoryBus bus;
  ElevationMapCore core{ElevationMapParams{}};
  core.set_measure_latency(false);
  bus.add(core);
  for (int64_t t = 0; t <= 400'000; t += 20'000) {
    evade::odometry_t o{};
    o.utime = t;
    o.x = 0.001 * t * 1e-3;
    o.v = 1.0;
    bus.inject("ODOMETRY", o, t);
  }
  for (auto _ : state) {
    bus.inject("LIDAR_POINTS", bytes, 400'000);
    bus.clear();
  }
  state.counters["cloud_bytes"] = double(bytes.size());
}
BENCHMARK(BM_CoreWithMessages)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace evade::mapping

BENCHMARK_MAIN();
