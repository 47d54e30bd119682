#include "planning/local_solves.h"

#include <algorithm>
#include <thread>

namespace evade::planning {

int solves_within(int cycle_budget, int wanted) { return std::max(1, std::min(wanted, cycle_budget)); }

int per_solve_budget(int cycle_budget, int max_total, int solves) {
  if (solves <= 0) return 0;
  return std::max(1, std::min(max_total, cycle_budget / solves));
}

std::vector<SolveResult> solve_side_by_side(const Problem& pb, const std::vector<SolveStart>& starts,
                                            const SolverOptions& opts, int threads) {
  const int n = static_cast<int>(starts.size());
  std::vector<SolveResult> out(n);
  const CeresMpcSolver solver(opts);
  SolverOptions half = opts;
  half.max_total_iterations = std::max(1, opts.max_total_iterations / 2);
  const CeresMpcSolver stage(half);
  auto run = [&](int t, int stride) {
    for (int i = t; i < n; i += stride) {
      const SolveStart& s = starts[i];
      if (!s.guide) {
        out[i] = solver.solve(pb, s.u, s.multipliers, s.penalty);
        continue;
      }
      const SolveResult guided = stage.solve(*s.guide, s.u, s.multipliers, s.penalty);
      SolverOptions rest = opts;
      rest.max_total_iterations = std::max(1, opts.max_total_iterations - guided.iterations);
      out[i] = CeresMpcSolver(rest).solve(pb, guided.finite ? guided.u : s.u);
      out[i].iterations += guided.iterations;
    }
  };
  const int used = std::max(1, std::min(threads, n));
  if (used == 1) {
    run(0, 1);
    return out;
  }
  std::vector<std::thread> pool;
  for (int t = 1; t < used; ++t) pool.emplace_back(run, t, used);
  run(0, used);  // this thread takes the first share
  for (std::thread& th : pool) th.join();
  return out;
}

int critical_iterations(const std::vector<SolveResult>& results, int threads) {
  const int used = std::max(1, std::min<int>(threads, static_cast<int>(results.size())));
  std::vector<int> per_thread(used, 0);
  for (size_t i = 0; i < results.size(); ++i) per_thread[i % used] += results[i].iterations;
  return *std::max_element(per_thread.begin(), per_thread.end());
}

}  // namespace evade::planning
