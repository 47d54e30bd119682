#include "planning/planner_core.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "evade/cmd_vel_t.hpp"
#include "evade/path_t.hpp"
#include "planning/goal_approach.h"
#include "planning/input_checks.h"

namespace evade::planning {
namespace {

bool finite_odometry(const evade::odometry_t& o) {
  return std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.yaw) && std::isfinite(o.v) &&
         std::isfinite(o.omega);
}

// Controls shifted by `steps`, the tail padded with the last control.
std::vector<double> shifted(const std::vector<double>& u, int steps) {
  const int n = static_cast<int>(u.size()) / 2;
  std::vector<double> out(u.size());
  for (int k = 0; k < n; ++k) {
    const int src = std::min(k + steps, n - 1);
    out[2 * k] = u[2 * src];
    out[2 * k + 1] = u[2 * src + 1];
  }
  return out;
}

}  // namespace

PlannerCore::PlannerCore(PlannerParams params)
    : Core("planner"),
      static_(params.static_field),
      p_(params),
      mode_(mode_spec(params.mode)),
      detour_(params.detour, params.d_safe_m + params.footprint.radius),
      settled_(params.detour.memory_s),
      history_(params.curvefit.degree, params.curvefit.window_s),
      topology_(
          params.guidance, params.solver,
          local_solves_budget(params.guidance, params.solver.max_total_iterations, params.solver.max_cycle_iterations)),
      period_us_(std::llround(1e6 / params.rate_hz)) {
  subscribe<evade::odometry_t>("ODOMETRY", [this](const evade::odometry_t& m) { on_odometry(m); });
  subscribe<evade::path_t>("ROUTE", [this](const evade::path_t& m) {
    if (m.n < 2 || !route_.set_route(m.x, m.y)) count("route_invalid");
  });
  subscribe<evade::prediction_list_t>("OBSTACLE_PREDICTIONS", [this](const evade::prediction_list_t& m) {
    if (!(m.dt > 0) || !std::isfinite(m.dt)) {
      count("predictions_invalid");
      return;
    }
    if (!accept_predictions(m)) return;
    predictions_ = m;
    predictions_rx_ = now();
    record_sightings(m);
    if (mode_.source == ObstacleSource::kPredicted) on_new_obstacle_input();
  });
  subscribe<evade::obstacle_list_t>("OBSTACLES", [this](const evade::obstacle_list_t& m) {
    if (!accept_observed(m)) return;
    observed_ = m;
    observed_rx_ = now();
    history_.add(m);  // cbf_curvefit's observed centres
    if (mode_.source == ObstacleSource::kObserved) on_new_obstacle_input();
  });
  if (mode_.evade_layers && p_.occlusion.enabled)
    subscribe<evade::hidden_region_list_t>("OCCLUSIONS",
                                           [this](const evade::hidden_region_list_t& m) { occlusions_ = m; });
  subscribe_static_map();
  every(period_us_, [this] { watchdog(); });
}

std::vector<double> PlannerCore::braking_controls(double v, double omega) const {
  const int N = p_.horizon_steps;
  std::vector<double> u(2 * N);
  v = std::clamp(std::isfinite(v) ? v : 0.0, p_.limits.v_min, p_.limits.v_max);
  omega = std::clamp(std::isfinite(omega) ? omega : 0.0, -p_.limits.omega_max, p_.limits.omega_max);
  for (int k = 0; k < N; ++k) {
    v = std::max(p_.limits.v_min, v - p_.limits.decel * p_.dt_s);
    const double dw = p_.limits.alpha * p_.dt_s;
    omega = std::fabs(omega) <= dw ? 0.0 : omega - std::copysign(dw, omega);
    u[2 * k] = v;
    u[2 * k + 1] = omega;
  }
  return u;
}

void PlannerCore::on_odometry(const evade::odometry_t& odom) {
  if (!finite_odometry(odom)) {
    count("odometry_invalid");
    return;
  }
  if (!accept_odometry(odom)) return;
  odometry_rx_ = now();
  last_odometry_ = odom;
  // Perception that has just gone stale is acted on at the odometry rate,
  // not at the next plan cycle: the stop must not wait up to one period.
  const bool just_stale = input_stale() && !(last_plan_ && last_plan_->status == evade::plan_t::STATUS_STALE_INPUT);
  // A list that came while the last cycle ran waited for this odometry.
  if (cycle_pending_) {
    count("cycle_on_obstacles");
    plan_cycle(odom);
    return;
  }
  // The obstacle input runs the cycles (on_new_obstacle_input); odometry
  // runs one only when that is late: no cycle for a period of bus time
  // (the arrival times: deterministic in replay).
  if (!just_stale && last_cycle_now_ >= 0 && now() - last_cycle_now_ < period_us_) return;
  count("cycle_on_odometry");
  plan_cycle(odom);
}

void PlannerCore::on_new_obstacle_input() {
  // No odometry yet, or none within its max age: the watchdog brakes.
  if (!last_odometry_ || now() - odometry_rx_ > std::llround(p_.odometry_max_age_s * 1e6)) return;
  // No odometry newer than the last cycle's: that cycle kept the planner
  // busy and the odometry that came meanwhile is still waiting behind this
  // list; the cycle waits for it rather than plan from where the robot was
  // a cycle ago.
  if (last_odometry_->utime == last_cycle_odometry_) {
    cycle_pending_ = true;
    return;
  }
  count("cycle_on_obstacles");
  plan_cycle(*last_odometry_);
}

bool PlannerCore::predictions_stale() const {
  return predictions_ ? now() - predictions_rx_ > std::llround(p_.predictions_max_age_s * 1e6) : p_.require_obstacles;
}

bool PlannerCore::observed_stale() const {
  return observed_ ? now() - observed_rx_ > std::llround(p_.obstacles_max_age_s * 1e6) : p_.require_obstacles;
}

bool PlannerCore::input_stale() const {
  return mode_.source == ObstacleSource::kObserved ? observed_stale() : predictions_stale();
}

void PlannerCore::watchdog() {
  // Odometry stopped: keep braking from the last command at the limit.
  if (!last_odometry_ || now() - odometry_rx_ <= std::llround(p_.odometry_max_age_s * 1e6)) return;
  count("stale_odometry");
  const double elapsed = last_cmd_now_ < 0 ? 0.0 : (now() - last_cmd_now_) * 1e-6;
  const double v = std::max(p_.limits.v_min, last_cmd_v_ - p_.limits.decel * elapsed);
  const double dw = p_.limits.alpha * elapsed;
  const double w = std::fabs(last_cmd_omega_) <= dw ? 0.0 : last_cmd_omega_ - std::copysign(dw, last_cmd_omega_);
  evade::odometry_t at = *last_odometry_;
  at.v = v;
  at.omega = w;
  publish_plan(at, evade::plan_t::STATUS_STALE_INPUT, nullptr, braking_controls(v, w), 0, 0, 0);
}

void PlannerCore::record_sightings(const evade::prediction_list_t& m) {
  // ids that are gone are forgotten: the table stays as small as the track list
  std::map<int64_t, Sighting> seen;
  for (const auto& t : m.tracks) {
    const double x = t.x.empty() ? NAN : t.x[0], y = t.y.empty() ? NAN : t.y[0];  // NaN: never still
    const auto it = seen_.find(t.id);
    Sighting s = it == seen_.end() ? Sighting{m.utime, x, y, m.utime, {}} : it->second;
    if (!(std::hypot(x - s.still_x, y - s.still_y) <= p_.solver.still_radius_m))
      s = Sighting{s.first_utime, x, y, m.utime, s.speed};
    if (p_.passive_safety.speed_memory_s > 0)  // off: no memory, the prediction's speed alone
      s.speed.add(m.utime, std::hypot(t.vx, t.vy), p_.passive_safety.speed_memory_s);
    seen[t.id] = s;
  }
  seen_.swap(seen);
}

double PlannerCore::track_age_s(int64_t id, int64_t utime) const {
  auto it = seen_.find(id);
  return it == seen_.end() ? 0.0 : 1e-6 * static_cast<double>(utime - it->second.first_utime);
}

double PlannerCore::track_recent_speed(int64_t id) const {
  auto it = seen_.find(id);
  return it == seen_.end() ? 0.0 : it->second.speed.max();
}

double PlannerCore::track_still_s(int64_t id, int64_t utime) const {
  auto it = seen_.find(id);
  return it == seen_.end() ? 0.0 : 1e-6 * static_cast<double>(utime - it->second.still_since_utime);
}

bool PlannerCore::passes_robot(const evade::track_prediction_t& t, const evade::odometry_t& odom) const {
  const double speed = std::hypot(t.vx, t.vy);
  if (!(speed > 0.0)) return false;
  const double ux = t.vx / speed, uy = t.vy / speed;
  const double rx = odom.x - t.x[0], ry = odom.y - t.y[0];  // from the track to the robot
  const double lateral = std::fabs(rx * uy - ry * ux);
  const double r = std::max(t.a[0], t.b[0]);
  return rx * ux + ry * uy > 0.0 && lateral <= r + p_.d_safe_m + p_.footprint.radius + p_.detour.comfort_m;
}

PlannerCore::Sweep PlannerCore::swept_in_grid(const evade::track_prediction_t& t, const evade::odometry_t& odom,
                                              Ellipse* swept) const {
  const DetourParams& d = p_.detour;
  const double speed = std::hypot(t.vx, t.vy);
  if (speed <= 0.0 || route_.length() <= 0.0) return Sweep::kNone;
  const double dx = t.x[0] - odom.x, dy = t.y[0] - odom.y, dist = std::hypot(dx, dy);
  // the route's heading about where the track is (its arc length ahead of
  // the robot's progress is at most its distance)
  constexpr double kHeadingBaseM = 0.5;  // chord over which the route's heading is taken
  const double s = std::clamp(route_.progress() + dist, 0.0, std::max(0.0, route_.length() - kHeadingBaseM));
  double x0, y0, x1, y1;
  route_.position_at(s, &x0, &y0);
  route_.position_at(s + kHeadingBaseM, &x1, &y1);
  const double hx = x1 - x0, hy = y1 - y0, hn = std::hypot(hx, hy);
  if (hn <= 0.0) return Sweep::kNone;
  if (dx * hx + dy * hy <= 0.0) return Sweep::kNone;            // behind the robot
  const double along = (t.vx * hx + t.vy * hy) / (speed * hn);  // cosine to the route's heading
  double sweep_m;
  Sweep kind;
  if (speed <= d.leader_max_speed_mps && along >= std::cos(d.leader_max_angle_rad)) {
    // A walker ahead in the lane, going the route's way slower than the
    // robot: straight behind it the barrier's gradient has no sideways
    // part and following is a solution, so the MPC alone follows it.
    sweep_m = speed * d.leader_sweep_s;
    kind = Sweep::kLeader;
  } else if (d.oncoming_sweep_s > 0.0 && !t.sigma.empty() && t.sigma[0] <= d.oncoming_max_sigma_m &&
             -along >= std::cos(d.oncoming_max_angle_rad) && passes_robot(t, odom)) {
    // Coming towards the robot: a group abreast is wider than any swerve
    // the 2.5 s horizon can plan once it is near, and standing in its way
    // is no escape from walkers who do not give way. Its way up to the
    // robot (at most oncoming_sweep_s of it) is kept clear of, in time.
    sweep_m = std::min(dist, speed * d.oncoming_sweep_s);
    kind = Sweep::kOncoming;
  } else {
    return Sweep::kNone;
  }
  // its ellipse (as a circle of its larger semi-axis) swept along its velocity
  const double r = std::max(t.a[0], t.b[0]), half = 0.5 * sweep_m;
  swept->x = t.x[0] + t.vx / speed * half;
  swept->y = t.y[0] + t.vy / speed * half;
  swept->a = r + half;
  swept->b = r;
  swept->theta = std::atan2(t.vy, t.vx);
  return kind;
}

void PlannerCore::make_reference(const evade::odometry_t& odom, Problem* pb) {
  if (mode_.evade_layers && detour_reference(odom, pb)) return;
  route_.reference(odom.x, odom.y, odom.yaw, pb->N, p_.dt_s, p_.reference_speed_mps, p_.route_end_decel_mps2,
                   &pb->ref_x, &pb->ref_y, &pb->ref_yaw);
}

bool PlannerCore::detour_reference(const evade::odometry_t& odom, Problem* pb) {
  std::vector<std::pair<int64_t, Ellipse>> settled;
  std::vector<int64_t> moving;
  std::vector<Ellipse> swept_movers;
  bool leader = false, oncoming = false;
  if (predictions_ && p_.detour.enabled) {
    for (const auto& t : predictions_->tracks) {
      if (!valid_track(t)) continue;
      const double age_s = track_age_s(t.id, odom.utime);
      const bool established = age_s >= p_.detour.min_track_age_s;
      if (std::hypot(t.vx, t.vy) > p_.detour.max_obstacle_speed_mps) {
        moving.push_back(t.id);
        Ellipse swept;
        const Sweep kind = age_s >= p_.detour.min_mover_age_s ? swept_in_grid(t, odom, &swept) : Sweep::kNone;
        if (kind != Sweep::kNone) swept_movers.push_back(swept);
        leader |= kind == Sweep::kLeader;
        oncoming |= kind == Sweep::kOncoming;
        continue;
      }
      if (static_.stands_for(t.id))
        moving.push_back(t.id);  // its cells are in the grid's static field: its ellipse is forgotten
      else if (established)
        settled.push_back({t.id, {t.x[0], t.y[0], t.a[0], t.b[0], t.theta[0]}});
    }
  }
  settled_.update(odom.utime, settled, moving);
  std::vector<Ellipse> in_grid = settled_.obstacles();
  in_grid.insert(in_grid.end(), swept_movers.begin(), swept_movers.end());
  if (!swept_movers.empty()) count("detour_movers", static_cast<int64_t>(swept_movers.size()));
  std::vector<double> way_x, way_y;
  const DetourPlanner::Result r = detour_.plan(route_, odom.x, odom.y, in_grid, &way_x, &way_y);
  RouteFollower way_round;
  if (r == DetourPlanner::Result::kDetour && way_round.set_route(way_x, way_y)) {
    count("detour");
    if (leader) count("detour_leader");
    if (oncoming) count("detour_oncoming");
    way_round.update_progress(odom.x, odom.y, p_.route_search_window_m);
    way_round.reference(odom.x, odom.y, odom.yaw, pb->N, p_.dt_s, p_.reference_speed_mps, p_.route_end_decel_mps2,
                        &pb->ref_x, &pb->ref_y, &pb->ref_yaw);
    return true;
  }
  if (r == DetourPlanner::Result::kNoWay) count("detour_no_way");
  return false;
}

void PlannerCore::plan_cycle(const evade::odometry_t& odom) {
  last_cycle_now_ = now();
  last_cycle_odometry_ = odom.utime;
  cycle_pending_ = false;
  const double v0 = std::clamp(odom.v, p_.limits.v_min, p_.limits.v_max);
  const double w0 = std::clamp(odom.omega, -p_.limits.omega_max, p_.limits.omega_max);
  if (published_without_solving(odom, v0, w0)) return;
  const Problem pb = make_problem(odom, v0, w0);
  std::vector<double> warm_u, warm_lambda;
  warm_start(pb, odom, v0, &warm_u, &warm_lambda);
  if (mode_.evade_layers && p_.guidance.enabled) {
    plan_with_guidance(pb, warm_u, warm_lambda, odom, v0, w0);
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  // Controls only: with the previous multipliers (and their penalty) the
  // solves measured slower and costlier in bench_planner, so they start at 0.
  const std::optional<CeresMpcSolver> solver = budgeted_solver(0, mode_.evade_layers ? recovery_reserve(pb) : 0);
  SolveResult res = solver->solve(pb, warm_u, p_.solver.warm_multipliers ? &warm_lambda : nullptr, prev_penalty_);
  int iterations = res.iterations;
  int8_t status = evade::plan_t::STATUS_OK;
  std::vector<double> u = res.u;
  if (mode_.evade_layers) {
    if (!(res.finite && res.feasible)) status = recover(pb, warm_u, odom, v0, w0, &res, &u, &iterations);
  } else if (!(res.finite && res.feasible)) {
    status = paper_fallback(pb, odom, v0, w0, &u);
  }
  const double measured_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  const double solve_us = solve_time_model_ ? solve_time_model_(iterations, measured_us) : measured_us;

  finish_cycle(odom, status, pb, u, res, solve_us, iterations);
}

bool PlannerCore::published_without_solving(const evade::odometry_t& odom, double v0, double w0) {
  if (age_us(now(), odom.utime) > std::llround(p_.odometry_max_age_s * 1e6)) {
    count("stale_odometry");
    publish_plan(odom, evade::plan_t::STATUS_STALE_INPUT, nullptr, braking_controls(v0, w0), 0, 0, 0);
    return true;
  }
  if (!route_.has_route()) {
    publish_plan(odom, evade::plan_t::STATUS_NO_ROUTE, nullptr, std::vector<double>(2 * p_.horizon_steps, 0.0), 0, 0,
                 0);
    return true;
  }
  route_.update_progress(odom.x, odom.y, p_.route_search_window_m);
  const double to_end = std::hypot(odom.x - route_.end_x(), odom.y - route_.end_y());
  if (to_end <= p_.goal_tolerance_m && route_.length() - route_.progress() <= 2 * p_.goal_tolerance_m) {
    blocked(odom, true);
    publish_plan(odom, evade::plan_t::STATUS_GOAL, nullptr, braking_controls(v0, w0), 0, 0, 0);
    return true;
  }
  if (input_stale()) {
    count(mode_.source == ObstacleSource::kObserved ? "stale_obstacles" : "stale_predictions");
    publish_plan(odom, evade::plan_t::STATUS_STALE_INPUT, nullptr, braking_controls(v0, w0), 0, 0, 0);
    return true;
  }
  return brake_for_invalid_track(odom, v0, w0);
}

Problem PlannerCore::make_problem(const evade::odometry_t& odom, double v0, double w0) {
  Problem pb;
  pb.N = p_.horizon_steps;
  pb.dt = p_.dt_s;
  pb.x0 = odom.x;
  pb.y0 = odom.y;
  pb.yaw0 = odom.yaw;
  pb.v_prev = v0;
  pb.omega_prev = w0;
  pb.w = p_.weights;
  pb.lim = p_.limits;
  pb.d_safe = p_.d_safe_m;
  pb.footprint = p_.footprint;
  update_static_field(odom);
  make_reference(odom, &pb);
  if (occlusions_ && age_us(now(), occlusions_->utime) <= std::llround(p_.occlusion.max_age_s * 1e6)) {
    pb.v_cap = occlusion_speed_caps(p_.occlusion, *occlusions_, pb);
    if (!pb.v_cap.empty()) count("occlusion_speed_bound");
  }
  if (mode_.evade_layers) {
    const std::vector<double> goal_caps =
        goal_approach_caps(p_.goal_approach, pb, route_.end_x(), route_.end_y(), route_.length() - route_.progress());
    if (!goal_caps.empty()) count("goal_approach_bound");
    tighten_caps(goal_caps, &pb.v_cap);
  }
  int invalid = 0;
  const ObstacleInputs in{predictions_ ? &*predictions_ : nullptr, observed_ ? &*observed_ : nullptr, &history_};
  pb.obstacles = constraint_obstacles(p_, in, odom.utime, odom.x, odom.y, &invalid);
  if (invalid) count("tracks_invalid", invalid);
  for (auto& o : pb.obstacles) {
    o.age_s = track_age_s(o.id, odom.utime);
    o.still_s = track_still_s(o.id, odom.utime);
    o.recent_speed_mps = track_recent_speed(o.id);
  }
  // the tracker's list of the predictions' frame or a newer one
  if (p_.passive_safety.measured_position && observed_ && predictions_ && observed_->utime >= predictions_->utime)
    attach_measurements(*observed_, &pb.obstacles);
  if (mode_.evade_layers && p_.passive_safety.every_plan) apply_passive_bounds(&pb);
  if (p_.solver.hold_settled && mode_spec(p_.mode).evade_layers) {
    if (const int held = hold_settled_obstacles(&pb, p_.solver)) count("settled_held", held);
  }
  static_.apply(odom.x, odom.y, p_.constraint_decay(), &pb);
  return pb;
}

void PlannerCore::warm_start(const Problem& pb, const evade::odometry_t& odom, double v0, std::vector<double>* warm_u,
                             std::vector<double>* warm_lambda) const {
  // the previous solution shifted by the elapsed steps, and its multipliers
  // mapped by track id
  const int N = pb.N, R = pb.num_rate_constraints();
  warm_lambda->assign(pb.num_constraints(), 0.0);
  int steps = -1;
  if (!prev_u_.empty() && static_cast<int>(prev_u_.size()) == 2 * N)
    steps = static_cast<int>(std::llround((odom.utime - prev_utime_) * 1e-6 / p_.dt_s));
  if (!(steps >= 0 && steps < N)) {
    warm_u->assign(2 * N, 0.0);
    for (int k = 0; k < N; ++k) (*warm_u)[2 * k] = v0;  // hold the current speed, go straight
    return;
  }
  *warm_u = shifted(prev_u_, steps);
  if (static_cast<int>(prev_multipliers_.size()) < R) return;
  for (int j = 4; j + 4 * steps < R; ++j) (*warm_lambda)[j] = prev_multipliers_[j + 4 * steps];
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    auto it = std::find(prev_ids_.begin(), prev_ids_.end(), pb.obstacles[i].id);
    if (it == prev_ids_.end()) continue;
    const int pi = static_cast<int>(it - prev_ids_.begin());
    for (int k = 0; k + steps < N; ++k) {
      const size_t src = static_cast<size_t>(R + pi * N + k + steps);
      if (src < prev_multipliers_.size()) (*warm_lambda)[R + i * N + k] = prev_multipliers_[src];
    }
  }
}

int8_t PlannerCore::paper_fallback(const Problem& pb, const evade::odometry_t& odom, double v0, double w0,
                                   std::vector<double>* u) {
  // The paper's planner: none of evade's recovery. Braking at the limits
  // needs no solution; the paper's released code replays its last plan.
  count("solver_infeasible");
  if (p_.paper_fallback == PaperFallback::kLastPlan && last_feasible_shifted(odom, u)) {
    count("fallback");
    project_controls(pb, u);  // consistent with the measured speed and the limits
    return evade::plan_t::STATUS_FALLBACK;
  }
  count("stopping");
  *u = braking_controls(v0, w0);
  return evade::plan_t::STATUS_STOPPING;
}

void PlannerCore::finish_cycle(const evade::odometry_t& odom, int8_t status, const Problem& pb,
                               const std::vector<double>& u_in, const SolveResult& res, double solve_us,
                               int iterations) {
  std::vector<double> u = u_in;
  const bool is_blocked = blocked(odom, false);
  if (escape_from_structure(pb, odom, is_blocked, &u)) count("escape_turn_blocked");
  if (status == evade::plan_t::STATUS_OK) {
    feasible_u_ = u;
    feasible_utime_ = odom.utime;
  }
  prev_u_ = u;
  prev_utime_ = odom.utime;
  prev_multipliers_ = status == evade::plan_t::STATUS_OK ? res.multipliers : std::vector<double>{};
  prev_penalty_ = status == evade::plan_t::STATUS_OK ? res.penalty : 0.0;
  prev_ids_.clear();
  for (const auto& o : pb.obstacles) prev_ids_.push_back(o.id);
  if (is_blocked) {
    count("blocked");
    status = evade::plan_t::STATUS_BLOCKED;
  }
  publish_plan(odom, status, &pb, u, solve_us, iterations, static_cast<int>(pb.obstacles.size()));
}

bool PlannerCore::blocked(const evade::odometry_t& odom, bool restart) {
  const double s = route_.progress();
  // a new route starts its progress again: so does the mark
  if (restart || progress_mark_utime_ < 0 || s > progress_mark_m_ + p_.blocked_progress_m || s < progress_mark_m_) {
    progress_mark_m_ = s;
    progress_mark_utime_ = odom.utime;
    return false;
  }
  return age_us(odom.utime, progress_mark_utime_) > std::llround(p_.blocked_after_s * 1e6);
}

std::optional<CeresMpcSolver> PlannerCore::budgeted_solver(int spent, int reserve) {
  // Each solve gets what is left of the cycle's iteration budget (at most
  // its own), less `reserve` kept for a later one:
  // PlannerSolverParams::max_cycle_iterations.
  const int left = p_.solver.max_cycle_iterations - spent - reserve;
  if (left <= 0) {
    count("cycle_budget_spent");
    return std::nullopt;
  }
  SolverOptions o = p_.solver;
  o.max_total_iterations = std::min(o.max_total_iterations, left);
  return CeresMpcSolver(o);
}

bool PlannerCore::last_feasible_shifted(const evade::odometry_t& odom, std::vector<double>* u) const {
  const int N = p_.horizon_steps;
  if (feasible_u_.empty()) return false;
  const int fsteps = static_cast<int>(std::llround((odom.utime - feasible_utime_) * 1e-6 / p_.dt_s));
  if (fsteps < 1 || fsteps >= N) return false;
  *u = shifted(feasible_u_, fsteps);  // its tail brakes to a stop
  const std::vector<double> tail = braking_controls(feasible_u_[2 * (N - 1)], feasible_u_[2 * (N - 1) + 1]);
  for (int k = N - fsteps; k < N; ++k) {
    (*u)[2 * k] = tail[2 * (k - (N - fsteps))];
    (*u)[2 * k + 1] = tail[2 * (k - (N - fsteps)) + 1];
  }
  return true;
}

void PlannerCore::publish_plan(const evade::odometry_t& odom, int8_t status, const Problem* pb,
                               const std::vector<double>& u_in, double solve_us, int iterations, int num_obstacles) {
  (void)num_obstacles;  // the constraint set itself is what is reported
  const int N = p_.horizon_steps;
  Problem base;
  if (pb == nullptr) {
    base.N = N;
    base.dt = p_.dt_s;
    base.x0 = odom.x;
    base.y0 = odom.y;
    base.yaw0 = odom.yaw;
    base.lim = p_.limits;
    pb = &base;
  }
  std::vector<double> u = u_in;
  std::vector<double> states(3 * (N + 1));
  rollout(*pb, u.data(), states.data());
  auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!finite(u) || !finite(states)) {  // never publish NaN
    count("non_finite_plan");
    status = evade::plan_t::STATUS_STOPPING;
    u = braking_controls(odom.v, odom.omega);
    rollout(*pb, u.data(), states.data());
  }
  const evade::plan_t plan = plan_message(odom, status, *pb, u, states, solve_us, iterations);
  publish("PLAN", plan);
  last_plan_ = plan;

  evade::cmd_vel_t cmd{};
  cmd.utime = odom.utime;
  cmd.v = commanded_speed(u);
  cmd.omega = u[1];
  if (status == evade::plan_t::STATUS_STALE_INPUT) {
    // Lost perception or odometry: ask for a stop at once. The PLAN shows
    // the braking the limits allow; the base driver's limiter (and the
    // base) bring the robot to rest at the deceleration limit.
    cmd.v = 0.0;
    cmd.omega = 0.0;
  }
  publish("CMD_VEL", cmd);
  last_cmd_v_ = cmd.v;
  last_cmd_omega_ = cmd.omega;
  last_cmd_now_ = now();
}

double PlannerCore::commanded_speed(const std::vector<double>& u) const {
  // A plan's speeds are where the robot should be at the ends of its
  // steps, from a start as old as the odometry and the solve; the base
  // ramps to a command at its limits and then holds it. A plan braking at
  // the limit, sent as its first speed, has the robot reach that speed
  // early and hold it for the rest of the cycle: in lockstep crowd 213 it
  // braked at 1.24 m/s^2, not 1.5. Where the plan's second step brakes at
  // the limit too, its speed is sent instead: the base brakes until the
  // next command comes, as the plan does. Gentler slowing (most slowing
  // plans, a few cm/s a step) and speeding up send the first, the speed
  // the plan holds over its first step (lib/planning/README.md, item 9).
  if (!mode_.evade_layers || !p_.brake_ahead || u.size() < 4) return u[0];
  const double full_step = p_.limits.decel * p_.dt_s - p_.solver.constraint_tolerance;
  const bool braking = u[2] * u[0] >= 0.0 && std::fabs(u[0]) - std::fabs(u[2]) >= full_step;
  return braking ? u[2] : u[0];
}

evade::plan_t PlannerCore::plan_message(const evade::odometry_t& odom, int8_t status, const Problem& pb,
                                        const std::vector<double>& u, const std::vector<double>& states,
                                        double solve_us, int iterations) const {
  const int N = p_.horizon_steps;
  evade::plan_t plan;
  plan.utime = odom.utime;
  plan.mode = mode_name(p_.mode);
  plan.status = status;
  plan.solve_time_us = static_cast<int64_t>(solve_us);
  plan.iterations = iterations;
  plan.cost = pb.ref_x.empty() ? 0.0 : objective(pb, u.data());
  plan.horizon = N;
  plan.num_states = N + 1;
  for (int k = 0; k <= N; ++k) {
    plan.x.push_back(states[3 * k]);
    plan.y.push_back(states[3 * k + 1]);
    plan.yaw.push_back(wrap_angle(states[3 * k + 2]));
  }
  for (int k = 0; k < N; ++k) {
    plan.v.push_back(u[2 * k]);
    plan.omega.push_back(u[2 * k + 1]);
  }
  plan.min_barrier = min_barrier(pb, states);
  plan.max_violation = pb.ref_x.empty() ? 0.0 : max_violation(pb, u.data());
  for (const ObstacleTrack& o : pb.obstacles) {
    const double slack = barrier_slack(pb, o, states);
    plan.obstacle_id.push_back(o.id);
    plan.obstacle_x.push_back(o.x.empty() ? 0.0 : o.x[0]);
    plan.obstacle_y.push_back(o.y.empty() ? 0.0 : o.y[0]);
    plan.obstacle_slack.push_back(std::isfinite(slack) ? slack : kNoObstacleBarrier);
  }
  plan.num_obstacles = static_cast<int32_t>(plan.obstacle_id.size());
  plan.predictions_utime = mode_.source == ObstacleSource::kPredicted && predictions_ ? predictions_->utime : -1;
  if (!std::isfinite(plan.cost)) plan.cost = 0;
  if (!std::isfinite(plan.min_barrier)) plan.min_barrier = kNoObstacleBarrier;
  if (!std::isfinite(plan.max_violation)) plan.max_violation = 0;
  return plan;
}

std::unique_ptr<PlannerCore> PlannerCore::from_config(const config::Node& root, const std::string& mode) {
  PlannerParams params = PlannerParams::from_config(root);
  if (!mode.empty()) params.mode = parse_mode(mode);
  return std::make_unique<PlannerCore>(params);
}

}  // namespace evade::planning
