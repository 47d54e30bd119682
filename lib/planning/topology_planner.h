// evade's topology-aware planning cycle (mode evade, planner.guidance; in
// the manner of T-MPC++, de Groot et al., T-RO 2024): guidance finds up to
// max_classes distinct ways through the predicted obstacles (guidance.h);
// one local Ceres MPC-D-CBF solve starts from each, first with the way as
// its reference (half its budget: it brings the plan into the way's class),
// then with the route's, plus one from the previous plan shifted without
// guidance, side by side within the cycle's
// iteration budget (local_solves.h); the plan is chosen by cost with a
// switching penalty, else the least violating plan or braking
// (selection.h). Holds the class chosen last cycle.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "planning/ceres_solver.h"
#include "planning/guidance.h"
#include "planning/local_solves.h"
#include "planning/selection.h"

namespace evade::planning {

struct TopologyOutcome {
  std::vector<double> u;        // the chosen plan's controls
  bool feasible = false;        // some local solve met every constraint (the chosen one)
  int8_t status = 0;            // evade::plan_t STATUS_OK, STATUS_RECOVERING (least violating) or STATUS_STOPPING
  SolveResult result;           // the chosen solve, else the least violating one (empty if no solve was finite)
  SolveResult previous;         // the solve from the previous plan (the one solve of a cycle without guidance)
  int iterations = 0;           // Ceres iterations of every solve
  int critical_iterations = 0;  // ... on the busiest thread
  int classes = 0;              // guidance classes found
  int solves = 0;               // local solves run
  bool switched = false;        // the chosen plan's class is not compatible with last cycle's
};

// The local solves' share of a cycle's Ceres iterations (cycle_budget):
// all of them, less one solve's (max_total) when the recovery chain is
// the fallback; at least 1. The previous plan's solve takes one solve's
// budget of it, the ways share the rest (local_budgets); the recovery gets
// what the previous plan's solve left of the cycle, as without guidance.
int local_solves_budget(const GuidanceParams& g, int max_total, int cycle_budget);

class TopologyPlanner {
 public:
  // cycle_budget: Ceres iterations of the cycle's local solves together.
  TopologyPlanner(GuidanceParams g, SolverOptions s, int cycle_budget) : g_(g), s_(s), budget_(cycle_budget) {}

  // `previous`: the previous plan shifted (with its multipliers, if any);
  // `braking`: braking at the limits from the measured controls.
  TopologyOutcome plan(const Problem& pb, const SolveStart& previous, const std::vector<double>& braking);

  // Forget the class chosen last (a new odometry frame).
  void reset() { previous_.reset(); }
  const std::optional<Signature>& previous_class() const { return previous_; }

 private:
  GuidanceParams g_;
  SolverOptions s_;
  int budget_;
  std::optional<Signature> previous_;
};

}  // namespace evade::planning
