// The local solves of one cycle side by side (mode evade, planner.guidance):
// one Ceres MPC-D-CBF solve per start, on a few threads, each Ceres solve
// single-threaded. The cycle's iteration budget is split among the starts
// before any solve begins, and solve i runs on thread i mod threads, so the
// results (and the iterations charged) never depend on thread timing: a
// replay plans as the live run did.
#pragma once

#include <vector>

#include "planning/ceres_solver.h"
#include "planning/problem.h"

namespace evade::planning {

struct SolveStart {
  std::vector<double> u;                             // 2N controls
  const std::vector<double>* multipliers = nullptr;  // optional warm multipliers (num_constraints)
  double penalty = 0.0;                              // their penalty
  // A guide problem (null: none): the start is first solved on it with
  // half the budget, then the shared problem from that plan with the rest.
  const Problem* guide = nullptr;
};

// How many of `wanted` solves a cycle budget runs: one iteration each at
// least (the first start first), at least one solve.
int solves_within(int cycle_budget, int wanted);
// Each of `solves` solves' iterations, fixed before solving. The first
// (the previous plan's, the one solve of a cycle without guidance) gets
// what a solve gets without guidance, one solve's budget (max_total),
// leaving at least 1 to each other; the others share the rest equally,
// each at most max_total, at least 1.
std::vector<int> local_budgets(int cycle_budget, int max_total, int solves);

// The thread of each solve: in order, the one with the fewest iterations
// assigned so far (ties to the lower thread), of min(threads, solves).
std::vector<int> assign_threads(const std::vector<int>& budgets, int threads);

// Solves pb from every start (through its guide problem, if any) with opts,
// start i within budgets[i] iterations on thread assign_threads(budgets,
// threads)[i]; results in start order, iterations those of both stages.
std::vector<SolveResult> solve_side_by_side(const Problem& pb, const std::vector<SolveStart>& starts,
                                            const SolverOptions& opts, const std::vector<int>& budgets, int threads);

// The Ceres iterations on the busiest thread (solve i on thread[i]): what
// the cycle's compute time follows.
int critical_iterations(const std::vector<SolveResult>& results, const std::vector<int>& thread);

}  // namespace evade::planning
