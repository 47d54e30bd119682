// Solves planning::Problem with Ceres: single shooting (the controls are the
// only unknowns, states come from the rollout), control bounds as parameter
// bounds, and an augmented-Lagrangian outer loop for the inequality
// constraints (rate limits and barriers), since Ceres has none.
//
// For g_j(u) >= 0 the inner problem is (Powell-Hestenes-Rockafellar)
//   min_u  J(u)/2 + sum_j rho/2 max(0, lambda_j/rho - g_j(u))^2
// i.e. one extra least-squares residual sqrt(rho) max(0, lambda_j/rho - g_j)
// per constraint; after each inner solve lambda_j <- max(0, lambda_j - rho g_j)
// and rho grows while the violation does not shrink fast enough. The loop
// stops once no constraint is violated by more than target_violation and
// none with a multiplier has more slack than complementarity_tolerance_m
// (first-order optimality of the AL: lambda_j > 0 only on active ones).
//
// Constraints far from active (g_j > active margin and lambda_j = 0) are left
// out of the inner problem (their residual would be zero anyway); every outer
// iteration re-checks all of them, so the final answer is checked against the
// full set.
//
// Speed: the inner cost is one CostFunction over the 2N controls with
// analytic Jacobians (the unicycle's forward sensitivities chained with the
// barrier gradient, O(N^2) per evaluation). Ceres sees it compressed to
// 2N + 1 rows with the same J^T J, J^T r and |r|^2 (see InnerCost), so its
// dense normal-equation work does not grow with the number of obstacles.
// Warm multipliers (the planner shifts the previous cycle's by one step)
// start the loop near the answer; their penalty is capped (warm_penalty_max).
#pragma once

#include <vector>

#include "config/fields.h"
#include "planning/problem.h"

namespace evade::planning {

// How Ceres' line search along a projected trust-region step (bounded
// problems only) picks its trial steps. Cubic and quadratic interpolation
// evaluate the gradient, i.e. a whole Jacobian, at every trial, even when
// the full step is accepted at once; bisection needs only cost values.
enum class LineSearchInterpolation { kBisection, kQuadratic, kCubic };

// Mode evade when no plan meets the cycle's constraints: the recovery chain
// (relaxed problem, most clearance, escape turn) or the one fallback
// (fallback.h).
enum class Fallback { kChain, kOwnMotion };

// Ceres' linear solver for the inner problem's normal equations.
enum class LinearSolver { kDenseNormalCholesky, kDenseQr };

// `planner.solver` (but the planner's own keys: PlannerSolverParams,
// params.h); the defaults are config/robot.yaml's.
struct SolverOptions {
  int max_outer_iterations = 20;
  int max_inner_iterations = 50;              // an inner solve runs to convergence: multiplier updates
                                              // from half-solved inner problems measured slower overall
  int max_total_iterations = 300;             // Ceres iterations of one solve, all outer iterations together
  double constraint_tolerance = 1e-3;         // m (barriers), m/s and rad/s (rate limits)
  double target_violation = 1e-4;             // the outer loop stops below this (<= constraint_tolerance)
  double complementarity_tolerance_m = 1e-3;  // ... and when no constraint with a multiplier has more
                                              // slack than this (min(g_j, lambda_j / rho))
  double penalty_initial = 3e4;               // rho at the first outer iteration
  double warm_penalty_max = 3e4;              // cap on the penalty that comes with warm multipliers
  double penalty_growth = 3.0;                // rho factor when the violation stalls
  double penalty_max = 1e6;
  double violation_shrink = 0.25;           // violation must shrink by this factor or rho grows
  double active_margin_m = 0.3;             // constraints with g above this and lambda = 0 are left out
  double inner_function_tolerance = 1e-5;   // relative cost change that ends an inner solve
  double inner_parameter_tolerance = 1e-8;  // relative step that ends an inner solve
  double min_trust_radius = 1e-2;           // floor of the trust region carried between outer iterations
  LinearSolver linear_solver = LinearSolver::kDenseNormalCholesky;
  LineSearchInterpolation line_search_interpolation = LineSearchInterpolation::kBisection;
  int projection_iterations = 10;                  // Newton steps onto the constraints when the AL loop ends outside
  double projection_target_m = 2e-5;               // a projection step aims the constraints below this at this
  double projection_damping = 1e-5;                // relative ridge of a projection step's normal equations
  int projection_candidates = 5;                   // earlier iterates projected too (the cheapest within ...)
  double projection_candidate_violation_m = 0.01;  // ... this violation), besides the last
  bool estimate_multipliers = true;                // without warm multipliers: estimate them at the warm start
  double estimate_margin_m = 1e-3;                 // constraints with g below this enter the estimate
  double relax_max_obstacle_speed_mps = 0.2;       // solve_elastic excuses the swelling of obstacles predicted
                                                   // slower than this (mean over the horizon) ...
  double relax_min_track_age_s = 1.0;              // ... and tracked for this long (a new track reads as
                                                   // static while its velocity is unknown); others only a start
                                                   // inside d_safe
  bool hold_settled = false;                       // mode evade: an obstacle still for hold_still_s keeps its
                                                   // ellipse of step 0 at every step, not swelling
  double hold_still_s = 3.0;                       // ... its centre within still_radius_m for this long ...
  double still_radius_m = 0.25;                    // ... of where it was (the MBE centre drifts with the view)
  Fallback fallback = Fallback::kChain;            // mode evade, nothing meets the constraints (fallback.h)
  double fallback_gamma = 1.0;                     // own_motion links: the robot may close by this times h a step
  double fallback_penetration_weight = 1e4;        // 1/m^2: own_motion's cost of depth within d_safe (per step)
  bool fallback_true_extent = true;                // own_motion: settled obstacles without their inflation (sigma)
  bool fallback_brake_while_closing = true;        // own_motion: no faster than braking while braking closes in
  double recovery_switch_ratio = 0.8;              // solve_elastic keeps the plan grown from the previous one unless
                                                   // another start's costs less than this fraction of it
  bool rank_outcome = true;           // most_clearance: clear of movers' bodies, then contacts theirs, then ours
  double outcome_margin_share = 0.0;  // rank_outcome: m of margin per m a mover is predicted to go (0: off) ...
  double outcome_margin_max_m = 0.3;  // ... up to this (outcome.h, OutcomeMargin)
  bool clear_by_cost = false;         // rank_outcome: of two plans clear of the movers' bodies and of every inflated
                                      // ellipse (h >= 0 over the horizon), the one of lower J, not of larger h
  bool split_budget = false;          // a failed hard solve's recovery solve keeps its share of the cycle; starts pass
                                      // unused iterations on (off: the restarts' reserve only, equal shares)

  template <class V>
  void fields(V& v);
};

struct SolveResult {
  std::vector<double> u;       // 2N controls
  std::vector<double> states;  // 3(N+1)
  std::vector<double> multipliers;
  double penalty = 0;     // rho at the end (goes with the multipliers)
  bool finite = false;    // no NaN / inf anywhere
  bool feasible = false;  // max_violation <= constraint_tolerance
  double cost = 0;        // paper's J
  double max_violation = 0;
  double min_barrier = kNoObstacleBarrier;
  int iterations = 0;  // inner (Ceres) iterations summed
  int outer_iterations = 0;
};

class CeresMpcSolver {
 public:
  explicit CeresMpcSolver(SolverOptions opts) : opts_(opts) {}
  const SolverOptions& options() const { return opts_; }

  // Hard constraints; `warm_u` (2N, clamped into the bounds) starts the
  // solve, `warm_multipliers` (optional, num_constraints) too.
  // `warm_penalty` (> 0) is the penalty the warm multipliers were found
  // with: lambda / rho shifts each constraint, so the two go together.
  SolveResult solve(const Problem& pb, const std::vector<double>& warm_u,
                    const std::vector<double>* warm_multipliers = nullptr, double warm_penalty = 0.0) const;

  // When the hard problem has no solution because some constraint cannot
  // be met even by standing still (a start inside d_safe, a static
  // obstacle whose predicted ellipse swells faster than the robot can get
  // away): the D-CBF is applied to each such obstacle as it is now
  // (barrier_relaxation). `feasible` then refers to the relaxed problem;
  // max_violation and min_barrier to the original one.
  // Starts: `start_u` (the planner's previous plan shifted, so that an
  // escape under way goes on), braking at the limit, and a turn on the spot
  // to either side followed by driving off.
  // `relax`: barrier_relaxation(pb, options()) when the caller has it already.
  SolveResult solve_elastic(const Problem& pb, const std::vector<double>& start_u,
                            const std::vector<double>* relax = nullptr) const;

 private:
  SolverOptions opts_;
};

// The inner least-squares problem with every constraint in it (AL terms
// for multipliers lambda and penalty rho), residuals and row-major Jacobian
// (analytic); exposed for tests against finite differences.
bool evaluate_inner_residuals(const Problem& pb, const double* u, const std::vector<double>& lambda, double rho,
                              std::vector<double>* residuals, std::vector<double>* jacobian);

// The relaxation of solve_elastic, per constraint (num_constraints; rate
// limits 0), for obstacle i at step k:
//   - a start inside d_safe: -(1 - decay) h(X_0, O_0) when that is
//     negative, i.e. the D-CBF on h - h(X_0): h may not fall below its start;
//   - an obstacle predicted slower than relax_max_obstacle_speed_mps (mean
//     over the horizon) and tracked for relax_min_track_age_s: its swelling
//     excused, the D-CBF on h + w_k, where
//     w_k = h(X_0, O_0) - h(X_0, O'_k) is how far the ellipse of step k
//     around the current centre (O'_k) has lowered h at the start:
//     max(0, w_(k+1) - decay w_k). A mover's motion and swelling must still
//     be got out of the way of.
// All zero when neither applies; standing still meets the relaxed problem.
std::vector<double> barrier_relaxation(const Problem& pb, const SolverOptions& opts);

// Whether o is settled: predicted slower than relax_max_obstacle_speed_mps
// (mean over the horizon) and tracked for relax_min_track_age_s.
bool settled_obstacle(const Problem& pb, const ObstacleTrack& o, const SolverOptions& opts);

// hold_settled: each obstacle of pb that has been still for hold_still_s
// (ObstacleTrack::still_s: its centre within still_radius_m of where it
// was; a walker who stops for a moment, or turns round, is not) and is
// predicted slower than relax_max_obstacle_speed_mps at every step keeps its
// centre, shape and inflation of step 0 at every step. Its predicted
// ellipse otherwise swells with the velocity's uncertainty (times t, up to
// the predictor's max_inflation_m), so that a robot standing beside a bin
// misses the hard constraints of the horizon's end at once, and a gap
// between two such obstacles closes over the horizon wherever the robot
// stands. A held obstacle that starts to move is a new prediction next
// cycle. Returns how many were held.
int hold_settled_obstacles(Problem* pb, const SolverOptions& opts);

// Fills r's cost, max_violation, min_barrier, finite and feasible from
// r->u against pb (states rolled out again).
void evaluate_result(const Problem& pb, const SolverOptions& opts, SolveResult* r);

// Clamps controls into the bounds (v_cap, omega_lo/hi included) and rate
// limits (from the measured controls forward), in place.
void project_controls(const Problem& pb, std::vector<double>* u);

// Solves `pb` from each start in turn on one solve's iteration budget:
// opts.max_total_iterations split among the starts in equal shares (with
// opts.split_budget each an equal share of what the starts before it
// left; a budget smaller than their number keeps the first starts only,
// one iteration each); this
// runs after the cycle's hard solve has failed, and a cycle that overruns
// its period reacts late to everything else. The cheapest feasible result
// wins, but the first start's (the plan grown from the previous one) is
// kept unless another costs less than opts.recovery_switch_ratio of it:
// two sides of a mover often cost about the same, and a robot that takes
// the other one every cycle turns back and forth in the mover's way
// instead of getting out of it. With least_violating, when no result is
// feasible the least violating finite one wins. `found` is false when no
// result qualified (then `best` is empty); best.iterations is the sum
// over every start solved.
struct MultiStartResult {
  SolveResult best;
  bool found = false;
};
MultiStartResult solve_from_starts(const SolverOptions& opts, const Problem& pb,
                                   std::vector<std::vector<double>> starts, bool least_violating);

template <class V>
void SolverOptions::fields(V& v) {
  v.field("max_outer_iterations", max_outer_iterations, config::between(1, 1000));
  v.field("max_inner_iterations", max_inner_iterations, config::between(1, 1000));
  v.field("max_total_iterations", max_total_iterations, config::between(1, 100000));
  v.field("constraint_tolerance", constraint_tolerance, config::positive());
  v.field("target_violation", target_violation, config::between(0.0, constraint_tolerance));
  v.field("complementarity_tolerance_m", complementarity_tolerance_m, config::between(0.0, 10.0));
  v.field("min_trust_radius", min_trust_radius, config::positive());
  v.field("penalty_initial", penalty_initial, config::positive());
  v.field("warm_penalty_max", warm_penalty_max, config::between(penalty_initial, 1e12));
  v.field("penalty_growth", penalty_growth, config::between(1.0, 1e3));
  v.field("penalty_max", penalty_max, config::positive());
  v.field("violation_shrink", violation_shrink, config::between(0.0, 1.0));
  v.field("active_margin_m", active_margin_m, config::between(0.0, 100.0));
  v.field("inner_function_tolerance", inner_function_tolerance, config::positive());
  v.field("inner_parameter_tolerance", inner_parameter_tolerance, config::positive());
  v.choice("linear_solver", linear_solver,
           config::Choices<LinearSolver>{{"dense_normal_cholesky", LinearSolver::kDenseNormalCholesky},
                                         {"dense_qr", LinearSolver::kDenseQr}});
  v.choice("line_search_interpolation", line_search_interpolation,
           config::Choices<LineSearchInterpolation>{{"bisection", LineSearchInterpolation::kBisection},
                                                    {"quadratic", LineSearchInterpolation::kQuadratic},
                                                    {"cubic", LineSearchInterpolation::kCubic}});
  v.field("projection_iterations", projection_iterations, config::between(0, 1000));
  v.field("projection_target_m", projection_target_m, config::between(0.0, target_violation));
  v.field("projection_damping", projection_damping, config::between(0.0, 1.0));
  v.field("projection_candidates", projection_candidates, config::between(0, 1000));
  v.field("projection_candidate_violation_m", projection_candidate_violation_m, config::between(0.0, 10.0));
  v.field("estimate_multipliers", estimate_multipliers);
  v.field("relax_max_obstacle_speed_mps", relax_max_obstacle_speed_mps, config::between(0.0, 100.0));
  v.field("relax_min_track_age_s", relax_min_track_age_s, config::between(0.0, 3600.0));
  v.field("hold_settled", hold_settled);
  v.field("hold_still_s", hold_still_s, config::between(0.0, 3600.0));
  v.field("still_radius_m", still_radius_m, config::between(0.0, 10.0));
  v.choice("fallback", fallback,
           config::Choices<Fallback>{{"chain", Fallback::kChain}, {"own_motion", Fallback::kOwnMotion}});
  v.field("fallback_gamma", fallback_gamma, config::between(1e-6, 1.0));
  v.field("fallback_penetration_weight", fallback_penetration_weight, config::between(0.0, 1e9));
  v.field("fallback_true_extent", fallback_true_extent);
  v.field("fallback_brake_while_closing", fallback_brake_while_closing);
  v.field("recovery_switch_ratio", recovery_switch_ratio, config::between(0.0, 1.0));
  v.field("rank_outcome", rank_outcome);
  v.field("outcome_margin_share", outcome_margin_share, config::between(0.0, 10.0));
  v.field("outcome_margin_max_m", outcome_margin_max_m, config::between(0.0, 10.0));
  v.field("clear_by_cost", clear_by_cost);
  v.field("split_budget", split_budget);
  v.field("estimate_margin_m", estimate_margin_m, config::between(0.0, 10.0));
}

}  // namespace evade::planning
