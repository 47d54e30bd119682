// Mode evade's one fallback (issue 18 item 3; planner.solver.fallback:
// own_motion, off by default: docs/experiments/2026-11-28-headon-2.md): when
// no plan meets every D-CBF constraint of the cycle's problem, the plan sent
// is the solution of one relaxed problem, and braking when that solve finds
// none.
//
// The relaxed problem (Problem::own_motion, penetration_weight) charges the
// robot only for its own motion: each barrier link compares h at step k + 1
// with h of the robot's step-k pose against the obstacle where it will be at
// step k + 1, so an obstacle that comes at the robot is not the plan's doing,
// and the robot may close on it by gamma h a step outside d_safe and not at
// all within it; the collision rule of the metrics (the robot's own
// velocity towards the obstacle at contact) in the planner's terms. Braking
// at the limits is made feasible by relaxing each link by what braking
// itself misses of it (a robot already moving at the obstacle cannot stop at
// once); that allowance is braking's alone: up to the last step at which
// braking's own motion closes on an obstacle, no plan is faster than braking
// (fallback_brake_while_closing; the plan may steer), since otherwise a plan
// turning aside at speed spends it, cycle after cycle, and meets the
// obstacle still moving towards it. The cost is the MPC's plus the squared depth within d_safe summed
// over obstacles and steps, so that of the plans that do not close in, the
// one that gets out of the obstacles' way wins over standing in it, and
// reversing is one of them where the robot's limits allow it (v_min < 0).
// Links and depth are taken against a settled obstacle's own extent (its
// ellipse less the uncertainty inflation the predictor added;
// fallback_true_extent; settled_obstacle: slow and tracked a while): that
// inflation, up to 0.5 m a side by the horizon's end, would otherwise cover a
// robot between two walls wherever it stood, and only standing would meet
// the links. A mover keeps its inflated ellipse: where it goes is uncertain.
#pragma once

#include <vector>

#include "planning/ceres_solver.h"
#include "planning/problem.h"

namespace evade::planning {

// o's ellipses less their uncertainty inflation (ObstacleTrack::sigma, added
// to both axes by the predictor): the obstacle's own extent along its
// predicted centres. Unchanged without sigma.
void remove_inflation(ObstacleTrack* o);

// The fallback's problem for pb: own-motion links (decay 1 -
// opts.fallback_gamma) relaxed by braking's shortfall (`brake_u`: braking at
// the limits, as plan controls), the penetration term weighted
// opts.fallback_penetration_weight; with opts.fallback_true_extent, against
// each settled obstacle's ellipses less their inflation (remove_inflation); with
// opts.fallback_brake_while_closing, v_cap at braking's speed up to the last
// step at which braking misses a link by more than constraint_tolerance.
Problem fallback_problem(const Problem& pb, const std::vector<double>& brake_u, const SolverOptions& opts);

// Starts of the fallback's solve: `warm_u` (the previous plan shifted, so
// that a way out under way goes on), braking, and a dash to either side
// (accelerating at the limit while turning at the limit for half the
// horizon; from rest this turns first); backing straight off too when
// v_min < 0. Projected onto pb's limits (the fallback problem's v_cap
// included).
std::vector<std::vector<double>> fallback_starts(const Problem& pb, const std::vector<double>& warm_u,
                                                 const std::vector<double>& brake_u);

// Solves fallback_problem (solver.options()) from every start, sharing its iteration
// budget: of the plans that meet the relaxed problem the cheapest (the
// first start's kept unless another costs less than recovery_switch_ratio
// of it), else braking. `feasible` refers to the relaxed problem (false:
// braking was returned); cost, max_violation and min_barrier to pb.
SolveResult solve_fallback(const CeresMpcSolver& solver, const Problem& pb, const std::vector<double>& warm_u,
                           const std::vector<double>& brake_u);

}  // namespace evade::planning
