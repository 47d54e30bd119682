// Cost of one OBSTACLES frame through the predictor: per-track KF update plus
// the N = 25 step inflated prediction. Goal: under 0.5 ms per frame for 20 tracks.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "config/config.h"
#include "prediction/inflation.h"
#include "prediction/predictor.h"

namespace {

using namespace evade::prediction;

PredictorParams params() {
  const auto root = evade::config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  return PredictorParams::from_config(root.section("predictor"));
}

// Frames of n obstacles moving on straight lines with MBE noise, 10 Hz.
std::vector<evade::obstacle_list_t> make_frames(int n, int count) {
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.04);
  std::vector<evade::obstacle_list_t> frames;
  for (int f = 0; f < count; ++f) {
    evade::obstacle_list_t l;
    l.utime = 1'000'000 + f * 100'000;
    for (int i = 0; i < n; ++i) {
      evade::obstacle_t o{};
      o.id = i + 1;
      const double t = 0.1 * f;
      o.x = -5.0 + 0.5 * i + std::cos(i) * t + noise(rng);
      o.y = 3.0 - 0.3 * i + std::sin(i) * t + noise(rng);
      o.a = 0.4 + 0.5 * std::fabs(noise(rng));
      o.b = 0.25 + 0.5 * std::fabs(noise(rng));
      o.theta = 0.3 * i + noise(rng);
      l.obstacles.push_back(o);
    }
    l.num_obstacles = n;
    frames.push_back(std::move(l));
  }
  return frames;
}

void BM_PredictorFrame(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto frames = make_frames(n, 1000);
  Predictor p(params());
  evade::prediction_list_t out;
  size_t i = 0;
  // warm the filters up so that every frame is an update, not a birth
  for (; i < 20; ++i) p.process(frames[i], &out, nullptr);
  for (auto _ : state) {
    if (i == frames.size()) {  // restart the stream with fresh tracks (rare)
      state.PauseTiming();
      p = Predictor(params());
      i = 0;
      p.process(frames[i++], &out, nullptr);
      state.ResumeTiming();
    }
    p.process(frames[i++], &out, nullptr);
    benchmark::DoNotOptimize(out.tracks.data());
  }
  state.counters["tracks"] = n;
}
BENCHMARK(BM_PredictorFrame)->Arg(1)->Arg(5)->Arg(20)->Arg(50)->Unit(benchmark::kMicrosecond);

void BM_SolveInflation(benchmark::State& state) {
  double r = 0.01;
  for (auto _ : state) {
    benchmark::DoNotOptimize(solve_inflation(0.6, 0.2, r, 1e-9));
    r = r > 1.0 ? 0.01 : r * 1.01;
  }
}
BENCHMARK(BM_SolveInflation);

}  // namespace

BENCHMARK_MAIN();
