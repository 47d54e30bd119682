// Choosing the plan of a cycle among the local solves (mode evade,
// planner.guidance): each plan is checked against every constraint of the
// problem (rate limits and every D-CBF constraint) on its own rollout; of
// the plans that meet them all the one with the least cost wins, a plan of
// a class other than that of the plan chosen last cycle (not compatible,
// guidance.h)
// counting its cost times switch_cost_factor, so that two ways of about
// the same cost do not take turns. When none meets them, the fallback is
// the least violating plan, braking at the limits among the candidates.
#pragma once

#include <optional>
#include <vector>

#include "planning/guidance.h"
#include "planning/problem.h"

namespace evade::planning {

struct Candidate {
  std::vector<double> u;  // 2N controls
  Signature signature;    // its class
  double cost = 0;        // the paper's J
  double violation = 0;   // largest violation of any constraint (max_violation)
  bool feasible = false;  // finite and violation <= the tolerance
};

// u checked against every constraint of pb (tolerance: the solver's
// constraint_tolerance); its class in frame f.
Candidate check_plan(const Problem& pb, const RouteFrame& f, const std::vector<double>& u, double tolerance);

// The feasible candidate of least cost, with the switching penalty against
// `previous` (none: no penalty); ties to the lower index; -1 when none is
// feasible.
int select_plan(const std::vector<Candidate>& c, const std::optional<Signature>& previous, double switch_cost_factor);

// The fallback: the candidate of least violation (ties to the lower
// index); -1 when there is none.
int least_violating(const std::vector<Candidate>& c);

}  // namespace evade::planning
