#include "planning/topology_planner.h"

#include <algorithm>

#include "evade/plan_t.hpp"

namespace evade::planning {

int local_solves_budget(const GuidanceParams& g, int max_total, int cycle_budget) {
  const int reserve = g.fallback == GuidanceParams::Fallback::kRecovery ? max_total : 0;
  return std::max(1, cycle_budget - reserve);
}

TopologyOutcome TopologyPlanner::plan(const Problem& pb, const SolveStart& previous,
                                      const std::vector<double>& braking) {
  TopologyOutcome out;
  const std::vector<GuidancePath> ways = find_guidance(pb, g_);
  out.classes = static_cast<int>(ways.size());
  std::vector<SolveStart> starts{previous};
  std::vector<Problem> guided;  // each way's problem: its path as the reference brings the solve into its class
  guided.reserve(ways.size());
  for (const GuidancePath& w : ways) guided.push_back(along_guidance(pb, w));
  for (size_t i = 0; i < ways.size(); ++i) starts.push_back({controls_along(pb, ways[i]), nullptr, 0.0, &guided[i]});
  starts.resize(solves_within(budget_, static_cast<int>(starts.size())));  // the costliest ways go first
  out.solves = static_cast<int>(starts.size());
  const std::vector<int> budgets = local_budgets(budget_, s_.max_total_iterations, out.solves);
  const std::vector<SolveResult> results = solve_side_by_side(pb, starts, s_, budgets, g_.threads);
  for (const SolveResult& r : results) out.iterations += r.iterations;
  out.critical_iterations = critical_iterations(results, assign_threads(budgets, g_.threads));
  out.previous = results[0];

  const RouteFrame f = route_frame(pb);
  std::vector<Candidate> candidates;
  for (const SolveResult& r : results) candidates.push_back(check_plan(pb, f, r.u, s_.constraint_tolerance));
  int chosen = select_plan(candidates, previous_, g_.switch_cost_factor);
  out.status = evade::plan_t::STATUS_OK;
  out.feasible = chosen >= 0;
  if (chosen < 0) {
    // every plan misses some constraint: the least violating, braking
    // included, each first brought within the bounds and rate limits
    candidates.push_back(check_plan(pb, f, braking, s_.constraint_tolerance));
    for (Candidate& c : candidates) {
      std::vector<double> u = c.u;
      project_controls(pb, &u);
      c = check_plan(pb, f, u, s_.constraint_tolerance);
    }
    chosen = least_violating(candidates);
    out.status =
        chosen == static_cast<int>(results.size()) ? evade::plan_t::STATUS_STOPPING : evade::plan_t::STATUS_RECOVERING;
  }
  const Candidate& c = candidates[chosen];
  out.u = c.u;
  if (chosen < static_cast<int>(results.size())) {
    out.result = results[chosen];
  } else {
    const int solved = least_violating({candidates.begin(), candidates.begin() + results.size()});
    if (solved >= 0) out.result = results[solved];
  }
  out.switched = previous_ && !compatible(c.signature, *previous_);
  previous_ = c.signature;
  return out;
}

}  // namespace evade::planning
