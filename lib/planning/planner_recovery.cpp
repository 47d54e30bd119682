// PlannerCore's recovery in mode evade (README, What a cycle does, item 7):
// when the hard solve fails, the strategy of planner.solver.fallback picks
// the plan sent. `chain` (the default): swerve restarts, the relaxed
// problem of solve_elastic and its escape turn, else the candidate with the
// most clearance. `own_motion`: the one relaxed problem of fallback.h, else
// braking. Both start with the swerve restarts of the hard problem, which
// they skip when braking misses it too and a relaxed problem follows.
// Whatever either sends after the hard problem has failed goes no faster
// than planner.passive_safety's bound (passive_safety.h) when it is on.
#include <algorithm>
#include <cmath>
#include <limits>

#include "evade/plan_t.hpp"
#include "planning/escape.h"
#include "planning/fallback.h"
#include "planning/manoeuvres.h"
#include "planning/outcome.h"
#include "planning/passive_safety.h"
#include "planning/planner_core.h"
#include "planning/recovery_rank.h"
#include "planning/static_structure.h"

namespace evade::planning {
namespace {

// The largest amount by which a plan (its rollout's states) misses a
// barrier constraint h(X_k+1) >= decay h(X_k) over the horizon (0 when it
// meets all).
double barrier_shortfall(const Problem& pb, const std::vector<double>& states) {
  double worst = 0.0;
  for (const ObstacleTrack& o : pb.obstacles) worst = std::max(worst, -barrier_slack(pb, o, states));
  return std::isfinite(worst) ? worst : std::numeric_limits<double>::infinity();
}

}  // namespace

int8_t PlannerCore::recover(const Problem& pb, const std::vector<double>& warm_u, const evade::odometry_t& odom,
                            double v0, double w0, SolveResult* res, std::vector<double>* u, int* iterations) {
  if (p_.solver.fallback == Fallback::kOwnMotion) return recover_own_motion(pb, warm_u, v0, w0, res, u, iterations);
  return recover_chain(pb, warm_u, odom, v0, w0, res, u, iterations);
}

int PlannerCore::recovery_share() const {
  if (!p_.solver.split_budget) return p_.solver.max_total_iterations;
  return std::min(p_.solver.max_total_iterations, p_.solver.max_cycle_iterations / 2);
}

int PlannerCore::recovery_reserve(const Problem& pb) const {
  if (!p_.solver.split_budget) return 0;
  if (p_.solver.fallback == Fallback::kOwnMotion) return recovery_share();
  if (pb.obstacles.empty()) return 0;
  const std::vector<double> relax = barrier_relaxation(pb, p_.solver);
  return std::any_of(relax.begin(), relax.end(), [](double s) { return s > 0; }) ? recovery_share() : 0;
}

std::vector<double> PlannerCore::projected_braking(const Problem& pb, double v0, double w0) const {
  std::vector<double> brake = braking_controls(v0, w0);
  project_controls(pb, &brake);
  return brake;
}

bool PlannerCore::braking_misses(const Problem& pb, const std::vector<double>& brake) const {
  return max_violation(pb, brake.data()) > p_.solver.constraint_tolerance;
}

void PlannerCore::swerve_restarts(const Problem& pb, int reserve, SolveResult* res, int* iterations,
                                  std::vector<Attempt>* tried) {
  if (!p_.solver.swerves) return;
  for (double side : {1.0, -1.0}) {
    const std::optional<CeresMpcSolver> solver = budgeted_solver(*iterations, reserve);
    if (!solver) return;
    SolveResult alt = solver->solve(pb, swerve_controls(pb, side));
    *iterations += alt.iterations;
    count("solver_restart");
    if (alt.finite && tried) tried->push_back({alt.u, "mc_swerve_restart"});
    if (alt.finite && alt.feasible) {
      count("swerve_sent");
      *res = alt;
      return;
    }
  }
}

int8_t PlannerCore::recover_chain(const Problem& pb, const std::vector<double>& warm_u, const evade::odometry_t& odom,
                                  double v0, double w0, SolveResult* res, std::vector<double>* u, int* iterations) {
  std::vector<Attempt> candidates;  // unsolved plans, for the most clearance
  if (res->finite) candidates.push_back({res->u, "mc_hard"});
  std::vector<double> relax;  // solve_elastic's (none without obstacles: only the rate limits failed)
  bool can_relax = false;
  if (!pb.obstacles.empty()) {
    relax = barrier_relaxation(pb, p_.solver);
    can_relax = std::any_of(relax.begin(), relax.end(), [](double s) { return s > 0; });
    if (p_.solver.dashes)
      for (double side : {1.0, -1.0}) candidates.push_back({dash_controls(pb, side), "mc_dash"});
    if (p_.solver.rank_outcome)
      for (double side : {1.0, -1.0})
        for (double offset : {0.2, 0.35, 0.45, 0.55, 0.65})
          candidates.push_back({pull_over_controls(pb, side, offset, 1.0), "mc_pull_over"});
    if (can_relax && braking_misses(pb, projected_braking(pb, v0, w0))) {
      // the relaxed problem decides; the swerves stay candidates: with a
      // mover closing in, getting out of its way at speed can beat all else
      count("restart_skipped");
      if (p_.solver.swerves)
        for (double side : {1.0, -1.0}) candidates.push_back({swerve_controls(pb, side), "mc_swerve"});
    } else {
      // the relaxed solve, when it applies, comes next and keeps its budget
      swerve_restarts(pb, can_relax ? recovery_share() : 0, res, iterations, &candidates);
    }
  }
  if (res->finite && res->feasible) {
    *u = res->u;
    return evade::plan_t::STATUS_OK;
  }
  count("solver_infeasible");
  const Problem bounded = passively_bounded(pb);  // what is sent from here on is not certified
  // A start inside d_safe, or a static obstacle whose ellipse swells with
  // its uncertainty, can leave the hard problem without any solution
  // (standing misses it too); then the relaxed one (see solve_elastic),
  // when there is something to relax.
  const std::optional<CeresMpcSolver> solver = can_relax ? budgeted_solver(*iterations) : std::nullopt;
  if (solver) {
    const SolveResult rec = solver->solve_elastic(bounded, warm_u, &relax);
    *iterations += rec.iterations;
    if (rec.finite && rec.feasible && relaxed_plan_stands(bounded, rec.u)) {
      *u = rec.u;
      *res = rec;
      if (escape_turn(bounded, v0, w0, u)) count("escape_turn");
      return evade::plan_t::STATUS_RECOVERING;
    }
    if (rec.finite) candidates.push_back({rec.u, "mc_relaxed"});
  }
  return most_clearance(bounded, candidates, odom, v0, w0, u);
}

bool PlannerCore::apply_passive_bounds(Problem* pb) {
  if (!p_.passive_safety.enabled) return false;
  if (p_.passive_safety.turn_bound && bound_turn_passively(p_.passive_safety, pb)) count("passive_turn_bound");
  if (!bound_passively(p_.passive_safety, pb)) return false;
  count("passive_speed_bound");
  return true;
}

Problem PlannerCore::passively_bounded(const Problem& pb) {
  Problem bounded = pb;
  // with every_plan the cycle's problem was bound already (make_problem)
  if (!p_.passive_safety.every_plan) apply_passive_bounds(&bounded);
  return bounded;
}

OutcomeMargin PlannerCore::outcome_margin() const {
  return {p_.solver.outcome_margin_share, p_.solver.outcome_margin_max_m};
}

bool PlannerCore::relaxed_plan_stands(const Problem& pb, const std::vector<double>& u) const {
  // with the outcome rank, a relaxed plan that meets a mover's body goes
  // among the candidates, judged with them
  if (!p_.solver.rank_outcome) return true;
  std::vector<double> states(3 * (pb.N + 1));
  rollout(pb, u.data(), states.data());
  return plan_outcome(pb, states, p_.solver.constraint_tolerance, pb.N, outcome_margin()).kind == Outcome::kClear;
}

int8_t PlannerCore::recover_own_motion(const Problem& pb, const std::vector<double>& warm_u, double v0, double w0,
                                       SolveResult* res, std::vector<double>* u, int* iterations) {
  const std::vector<double> brake = projected_braking(pb, v0, w0);
  if (pb.obstacles.empty()) {
    // only the rate limits failed: nothing to restart against
  } else if (braking_misses(pb, brake)) {
    count("restart_skipped");  // the fallback decides
  } else {
    // the fallback's solve keeps its budget
    swerve_restarts(pb, recovery_share(), res, iterations, nullptr);
  }
  if (res->finite && res->feasible) {
    *u = res->u;
    return evade::plan_t::STATUS_OK;
  }
  count("solver_infeasible");
  const std::optional<CeresMpcSolver> solver = budgeted_solver(*iterations);
  if (!solver) {
    count("stopping");
    *u = brake;
    return evade::plan_t::STATUS_STOPPING;
  }
  *res = solve_fallback(*solver, passively_bounded(pb), warm_u, brake);
  *iterations += res->iterations;
  *u = res->u;
  count(res->feasible ? "fallback_relaxed" : "stopping");
  return res->feasible ? evade::plan_t::STATUS_RECOVERING : evade::plan_t::STATUS_STOPPING;
}

int8_t PlannerCore::most_clearance(const Problem& pb, const std::vector<Attempt>& attempts,
                                   const evade::odometry_t& odom, double v0, double w0, std::vector<double>* u) {
  const int N = p_.horizon_steps;
  // Nothing meets every constraint: of the plans at hand (the failed
  // solves, swerves and dashes to either side, the last feasible plan
  // shifted, braking), send the first in recovery_rank.h's order.
  // Replaying an old plan blindly can drive into an obstacle that is
  // sweeping across the path; braking can be worse than getting out of its
  // way. The shortfall alone (the worst step of the D-CBF chain) preferred
  // standing in an oncoming e-bike's way, deep inside its ellipse, to a
  // dash aside that falls further short at its first steps. With every way
  // into a wall's margin, the one farthest from a walker is often the one
  // that hits the wall; getting aside in a narrow passage beats standing in
  // the mover's lane; standing beats driving on into it. With
  // passive_safety.slow_chosen the chosen plan is then slowed onto passive
  // safety's reach bounds (slow_onto_reach): the side and the way stay the
  // ranking's, the speed becomes one from which the robot can still brake
  // out of each mover's reach.
  struct Candidate {
    std::vector<double> u;
    int8_t status;
    const char* counter;
    const char* label = nullptr;  // an attempt's kind (Attempt::label)
    RecoveryRank rank{};
  };
  std::vector<Candidate> candidates;
  std::vector<double> f;
  if (last_feasible_shifted(odom, &f)) candidates.push_back({f, evade::plan_t::STATUS_FALLBACK, "fallback"});
  for (const Attempt& a : attempts)
    candidates.push_back({a.u, evade::plan_t::STATUS_RECOVERING, "most_clearance", a.label});
  candidates.push_back({braking_controls(v0, w0), evade::plan_t::STATUS_STOPPING, "stopping"});
  std::vector<double> states(3 * (N + 1));
  for (Candidate& c : candidates) {
    project_controls(pb, &c.u);  // consistent with the measured speed and the limits
    rollout(pb, c.u.data(), states.data());
    // h from k = 1: where the robot is now is the same for every plan
    c.rank = {judge_recovery_plan(pb, states), min_barrier(pb, states, 1), barrier_shortfall(pb, states),
              p_.solver.clear_by_cost ? objective(pb, c.u.data(), states) : 0.0};
  }
  const Candidate* chosen = &candidates.front();  // ties: the first in the list
  for (const Candidate& c : candidates)
    if (ranks_before(c.rank, chosen->rank, p_.solver.constraint_tolerance, p_.solver.clear_by_cost)) chosen = &c;
  *u = chosen->u;
  if (p_.passive_safety.slow_chosen && slow_onto_reach(pb, chosen->rank.judged, u)) count("mc_slowed");
  count(chosen->counter);
  if (chosen->label) count(chosen->label);
  return chosen->status;
}

RecoveryJudgement PlannerCore::judge_recovery_plan(const Problem& pb, const std::vector<double>& states) const {
  const double tie = p_.solver.constraint_tolerance;
  RecoveryJudgement j;
  const StructureDepth depth = structure_depth(pb, states);
  j.into = depth.margin > tie;
  j.contact = j.into ? depth.body : 0.0;
  if (p_.solver.rank_outcome) j.outcome = plan_outcome(pb, states, tie, pb.N, outcome_margin());
  return j;
}

bool PlannerCore::slow_onto_reach(const Problem& pb, const RecoveryJudgement& judged, std::vector<double>* u) const {
  std::vector<double> slowed = *u;
  if (!project_onto_reach(pb, &slowed)) return false;
  std::vector<double> states(3 * static_cast<size_t>(pb.N + 1));
  rollout(pb, slowed.data(), states.data());
  const RecoveryJudgement s = judge_recovery_plan(pb, states);
  if (slowed_is_worse(s, judged, p_.solver.constraint_tolerance, p_.passive_safety.slowed_refused_if)) return false;
  *u = std::move(slowed);
  return true;
}

bool PlannerCore::escape_turn(const Problem& pb, double v0, double omega0, std::vector<double>* u) const {
  if (!p_.escape.enabled || pb.obstacles.empty()) return false;
  const int N = p_.horizon_steps;
  std::vector<double> states(3 * (N + 1));
  rollout(pb, u->data(), states.data());
  if (std::hypot(states[3 * N] - pb.x0, states[3 * N + 1] - pb.y0) >= p_.escape.min_progress_m) return false;
  // the obstacle nearest (in h) of those holding the robot: inside d_safe,
  // or at its edge, where the D-CBF lets h fall by only gamma h per step
  const BarrierValue* deepest = nullptr;
  std::vector<BarrierValue> h0(pb.obstacles.size());
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    h0[i] = barrier_at(pb, pb.obstacles[i], 0, start);
    if (h0[i].h < p_.escape.near_m && (!deepest || h0[i].h < deepest->h)) deepest = &h0[i];
  }
  if (!deepest) return false;
  // The heading that raises h fastest is along grad h; any within 90 deg of
  // it raises h. Of those within the cone, the one nearest the route's.
  const double out = std::atan2(deepest->gy, deepest->gx);
  const double off = wrap_angle(pb.ref_yaw[1] - out);
  const double target = out + std::clamp(off, -p_.escape.cone_half_angle_rad, p_.escape.cone_half_angle_rad);
  const double err = wrap_angle(target - pb.yaw0);
  // facing the way out (within half a step's turn): the solver's plan stands
  if (std::fabs(err) < 0.5 * p_.limits.omega_max * p_.dt_s) return false;
  // turn at the limits (yaw acceleration too), no further than the target;
  // the speed, already near zero (no headway), brakes to zero
  *u = turn_on_the_spot(pb, err, braking_controls(v0, omega0), omega0);
  return true;
}

}  // namespace evade::planning
