// Tracker cost per map (goal: 1 ms on one core): DBSCAN + MBE + Kuhn-Munkres
// on the obstacle layer the local map builds from a ray-cast VLP-16
// revolution (the bench_mapping world), and on a denser synthetic layer.
#include <benchmark/benchmark.h>

#include <random>

#include "mapping/elevation_map.h"
#include "mapping/synthetic_scan.h"
#include "tracking/tracker.h"

namespace evade::tracking {
namespace {

struct Layer {
  mapping::ElevationLayers L;
};

Layer layer_from_scan() {
  using namespace mapping;
  SynthWorld w;
  for (int k = 0; k < 24; ++k) {
    const double a = 2.0 * M_PI * k / 24.0, r = 2.0 + (k % 4);
    w.cylinders.push_back({r * std::cos(a), r * std::sin(a), 0.25 + 0.05 * (k % 2), 0.5 + 1.2 * (k % 2)});
  }
  w.boxes.push_back({3.0, -3.0, 0.3, 1.0, 2.0, 1.0});
  SynthScanOptions o;
  o.range_noise_std_m = 0.01;
  const SynthCloud c = synth_vlp16(w, o);
  PoseBuffer poses(2'000'000);
  poses.add({0, {}, 0, 0});
  const CloudView v = view_of(c, 0, 0.5);
  Layer out;
  Pose2 robot;
  CloudStats st;
  ElevationMapBuilder{ElevationMapParams{}}.build(v, poses, &out.L, &robot, &st);
  return out;
}

GridView view(const mapping::ElevationLayers& L, int64_t utime) {
  GridView g;
  g.utime = utime;
  g.origin_x = L.origin_x;
  g.origin_y = L.origin_y;
  g.resolution = L.resolution;
  g.width = L.width;
  g.height = L.height;
  g.obstacle = L.obstacle.data();
  return g;
}

void BM_TrackerOnScanLayer(benchmark::State& state) {
  const Layer layer = layer_from_scan();
  Tracker t{TrackerParams{}};
  int64_t utime = 0;
  size_t obstacles = 0;
  for (auto _ : state) {
    obstacles = t.update(view(layer.L, utime += 100'000)).size();
  }
  int cells = 0;
  for (auto o : layer.L.obstacle) cells += o;
  state.counters["obstacle_cells"] = cells;
  state.counters["obstacles"] = double(obstacles);
}
BENCHMARK(BM_TrackerOnScanLayer)->Unit(benchmark::kMillisecond);

// 40 filled discs and speckle: far more obstacle cells than a real scan
void BM_TrackerDenseLayer(benchmark::State& state) {
  mapping::ElevationLayers L;
  L.reset(-5, -5, 0.1, 100, 100);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> pos(-4.5, 4.5);
  for (int k = 0; k < 40; ++k) {
    const double x = pos(rng), y = pos(rng), r = 0.2 + 0.1 * (k % 4);
    for (int row = 0; row < 100; ++row)
      for (int c = 0; c < 100; ++c)
        if (std::hypot(-5 + (c + 0.5) * 0.1 - x, -5 + (row + 0.5) * 0.1 - y) <= r) L.obstacle[row * 100 + c] = 1;
  }
  for (int k = 0; k < 200; ++k) L.obstacle[rng() % L.obstacle.size()] = 1;
  Tracker t{TrackerParams{}};
  int64_t utime = 0;
  size_t obstacles = 0;
  for (auto _ : state) obstacles = t.update(view(L, utime += 100'000)).size();
  int cells = 0;
  for (auto o : L.obstacle) cells += o;
  state.counters["obstacle_cells"] = cells;
  state.counters["obstacles"] = double(obstacles);
}
BENCHMARK(BM_TrackerDenseLayer)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace evade::tracking

BENCHMARK_MAIN();
