#include "planning/local_solves.h"

#include <algorithm>
#include <thread>

namespace evade::planning {

int solves_within(int cycle_budget, int wanted) { return std::max(1, std::min(wanted, cycle_budget)); }

std::vector<int> local_budgets(int cycle_budget, int max_total, int solves) {
  if (solves <= 0) return {};
  std::vector<int> out(solves);
  out[0] = std::max(1, std::min(max_total, cycle_budget - (solves - 1)));
  if (solves == 1) return out;
  const int share = std::max(1, std::min(max_total, (cycle_budget - out[0]) / (solves - 1)));
  std::fill(out.begin() + 1, out.end(), share);
  return out;
}

std::vector<int> assign_threads(const std::vector<int>& budgets, int threads) {
  const int used = std::max(1, std::min<int>(threads, static_cast<int>(budgets.size())));
  std::vector<int> load(used, 0), out;
  for (int b : budgets) {
    const int t = static_cast<int>(std::min_element(load.begin(), load.end()) - load.begin());
    load[t] += b;
    out.push_back(t);
  }
  return out;
}

namespace {

// One start's solve: through its guide problem (half its budget), if any,
// then the shared problem.
SolveResult solve_one(const Problem& pb, const SolveStart& s, SolverOptions opts, int budget) {
  opts.max_total_iterations = budget;
  if (!s.guide) return CeresMpcSolver(opts).solve(pb, s.u, s.multipliers, s.penalty);
  SolverOptions half = opts;
  half.max_total_iterations = std::max(1, budget / 2);
  const SolveResult guided = CeresMpcSolver(half).solve(*s.guide, s.u, s.multipliers, s.penalty);
  opts.max_total_iterations = std::max(1, budget - guided.iterations);
  SolveResult out = CeresMpcSolver(opts).solve(pb, guided.finite ? guided.u : s.u);
  out.iterations += guided.iterations;
  return out;
}

}  // namespace

std::vector<SolveResult> solve_side_by_side(const Problem& pb, const std::vector<SolveStart>& starts,
                                            const SolverOptions& opts, const std::vector<int>& budgets, int threads) {
  const int n = static_cast<int>(starts.size());
  std::vector<SolveResult> out(n);
  const std::vector<int> thread = assign_threads(budgets, threads);
  const int used = n == 0 ? 1 : *std::max_element(thread.begin(), thread.end()) + 1;
  auto run = [&](int t) {
    for (int i = 0; i < n; ++i)
      if (thread[i] == t) out[i] = solve_one(pb, starts[i], opts, budgets[i]);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < used; ++t) pool.emplace_back(run, t);
  run(0);  // this thread takes the first share
  for (std::thread& th : pool) th.join();
  return out;
}

int critical_iterations(const std::vector<SolveResult>& results, const std::vector<int>& thread) {
  std::vector<int> per_thread(1, 0);
  for (size_t i = 0; i < results.size(); ++i) {
    if (thread[i] >= static_cast<int>(per_thread.size())) per_thread.resize(thread[i] + 1, 0);
    per_thread[thread[i]] += results[i].iterations;
  }
  return *std::max_element(per_thread.begin(), per_thread.end());
}

}  // namespace evade::planning
