// PlannerCore's cycle in mode evade with planner.guidance.enabled: the
// solves and the choice are TopologyPlanner's (topology_planner.h); when
// none meets every constraint, guidance.fallback decides.
#include <chrono>

#include "evade/plan_t.hpp"
#include "planning/planner_core.h"

namespace evade::planning {

void PlannerCore::plan_with_guidance(const Problem& pb, const std::vector<double>& warm_u,
                                     const std::vector<double>& warm_lambda, const evade::odometry_t& odom, double v0,
                                     double w0) {
  const auto t0 = std::chrono::steady_clock::now();
  SolveStart previous{warm_u, p_.solver.warm_multipliers ? &warm_lambda : nullptr, prev_penalty_};
  const TopologyOutcome o = topology_.plan(pb, previous, braking_controls(v0, w0));
  count("guidance_classes", o.classes);
  if (o.switched) count("guidance_switch");
  SolveResult res = o.result;
  std::vector<double> u = o.u;
  int8_t status = o.status;
  int recovery_iterations = 0;
  if (!o.feasible && p_.guidance.fallback == GuidanceParams::Fallback::kRecovery) {
    // evade's recovery (solver.fallback's strategy) as without guidance:
    // from the solve of the previous plan, with what that solve left of
    // the cycle's budget (the ways ran beside it, on the other threads).
    // From the least violating solve, with what all of them left, the
    // robot wavered between sides (its class changes from cycle to cycle)
    // and lost the swerve restarts.
    res = o.previous;
    int spent = o.previous.iterations;
    status = recover(pb, warm_u, odom, v0, w0, &res, &u, &spent);
    recovery_iterations = spent - o.previous.iterations;
  } else if (!o.feasible) {
    count("solver_infeasible");
    count(status == evade::plan_t::STATUS_STOPPING ? "stopping" : "least_violating");
  }
  const double measured_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  // PLAN.iterations and the compute time follow the busiest thread's
  // iterations, then the recovery's; HEALTH counts every solve's
  const int charged = o.critical_iterations + recovery_iterations;
  count("solver_iterations", o.iterations + recovery_iterations);
  const double solve_us = solve_time_model_ ? solve_time_model_(charged, measured_us) : measured_us;
  finish_cycle(odom, status, pb, u, res, solve_us, charged);
}

}  // namespace evade::planning
