// Ceres (warm-started augmented Lagrangian, the planner's solver) against
// IPOPT (exact Hessian, cold from zeros, as the paper's code) on the same
// fixed MPC problems with k = 0, 4, 8, 16 obstacles.
//   solve/ceres/<k>       as the planner runs (planner.solver.warm_multipliers: false): the
//                         previous cycle's (0.1 s earlier) controls shifted one step; the
//                         solver estimates the multipliers at that warm start
//   solve/ceres_warm_multipliers/<k>  also the previous cycle's multipliers (shifted) with its
//                         penalty (capped by warm_penalty_max), for the record
//   solve/ceres_cold/<k>  from zeros, for reference
//   solve/ipopt/<k>       IPOPT from zeros
// After the runs a table compares the costs (goal: Ceres within 1 % of IPOPT).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "planning/ceres_solver.h"
#include "planning/ipopt_solver.h"
#include "test_problems.h"

namespace {

using evade::planning::CeresMpcSolver;
using evade::planning::IpoptResult;
using evade::planning::Problem;
using evade::planning::SolveResult;
using evade::planning::SolverOptions;

struct Warm {
  std::vector<double> u, lambda;
  double penalty = 0;
};

// The previous cycle (0.1 s earlier) solved, its solution shifted one step.
Warm warm_start(int k, const CeresMpcSolver& solver) {
  const Problem prev = evade::planning::testing::bench_problem(k, -0.1);
  const SolveResult r = solver.solve(prev, std::vector<double>(2 * prev.N, 0.0));
  Warm w;
  const int N = prev.N, R = prev.num_rate_constraints();
  w.u.resize(r.u.size());
  for (int s = 0; s < N; ++s) {
    const int src = std::min(s + 1, N - 1);
    w.u[2 * s] = r.u[2 * src];
    w.u[2 * s + 1] = r.u[2 * src + 1];
  }
  w.penalty = r.penalty;
  w.lambda.assign(r.multipliers.size(), 0.0);
  for (int j = 4; j + 4 < R; ++j) w.lambda[j] = r.multipliers[j + 4];
  for (int i = 0; i < k; ++i)
    for (int s = 0; s + 1 < N; ++s) w.lambda[R + i * N + s] = r.multipliers[R + i * N + s + 1];
  return w;
}

std::map<int, double> g_ceres_cost, g_ceres_viol, g_ipopt_cost, g_ipopt_viol;

void BM_Ceres(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  CeresMpcSolver solver{SolverOptions{}};
  const Warm w = warm_start(k, solver);
  SolveResult r;
  for (auto _ : state) {
    r = solver.solve(pb, w.u);
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["cost"] = r.cost;
  state.counters["viol"] = r.max_violation;
  state.counters["iters"] = r.iterations;
  state.counters["outer"] = r.outer_iterations;
  state.counters["feasible"] = r.feasible;
  g_ceres_cost[k] = r.cost;
  g_ceres_viol[k] = r.max_violation;
}

// planner.solver.warm_multipliers: true. Measured no faster overall and
// less predictable (the previous cycle's multipliers may belong to another
// active set), so the planner's default is false.
void BM_CeresWarmMultipliers(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  CeresMpcSolver solver{SolverOptions{}};
  const Warm w = warm_start(k, solver);
  SolveResult r;
  for (auto _ : state) {
    r = solver.solve(pb, w.u, &w.lambda, w.penalty);
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["cost"] = r.cost;
  state.counters["viol"] = r.max_violation;
  state.counters["iters"] = r.iterations;
  state.counters["outer"] = r.outer_iterations;
  state.counters["feasible"] = r.feasible;
}

void BM_CeresCold(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  CeresMpcSolver solver{SolverOptions{}};
  SolveResult r;
  for (auto _ : state) {
    r = solver.solve(pb, std::vector<double>(2 * pb.N, 0.0));
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["cost"] = r.cost;
  state.counters["viol"] = r.max_violation;
  state.counters["iters"] = r.iterations;
  state.counters["feasible"] = r.feasible;
}

void BM_Ipopt(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  IpoptResult r;
  for (auto _ : state) {
    r = evade::planning::solve_with_ipopt(pb);
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["cost"] = r.cost;
  state.counters["viol"] = r.max_violation;
  state.counters["iters"] = r.iterations;
  state.counters["solved"] = r.solved;
  g_ipopt_cost[k] = r.cost;
  g_ipopt_viol[k] = r.max_violation;
}

BENCHMARK(BM_Ceres)->Name("solve/ceres")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CeresWarmMultipliers)->Name("solve/ceres_warm_multipliers")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CeresCold)->Name("solve/ceres_cold")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ipopt)->Name("solve/ipopt")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (!g_ceres_cost.empty() && !g_ipopt_cost.empty()) {
    std::printf("\n%-4s %14s %10s %14s %10s %10s\n", "k", "ceres_cost", "viol", "ipopt_cost", "viol", "diff_%");
    int bad = 0;
    for (const auto& [k, c] : g_ceres_cost) {
      if (!g_ipopt_cost.count(k)) continue;
      const double ip = g_ipopt_cost[k];
      const double diff = 100.0 * (c - ip) / std::max(1e-9, std::fabs(ip));
      std::printf("%-4d %14.6f %10.2e %14.6f %10.2e %10.3f%s\n", k, c, g_ceres_viol[k], ip, g_ipopt_viol[k], diff,
                  std::fabs(diff) <= 1.0 ? "" : "  (beyond 1 %)");
      if (std::fabs(diff) > 1.0) ++bad;
    }
    std::printf("cost check: %s\n", bad == 0 ? "ceres within 1 % of ipopt everywhere" : "NOT within 1 % everywhere");
  }
  return 0;
}
