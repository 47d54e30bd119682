// PlannerCore's input gate (issue 20), kept apart from the planning itself:
// what of ODOMETRY and OBSTACLE_PREDICTIONS the planner may act on.
#include <algorithm>
#include <cmath>
#include <string>

#include "evade/plan_t.hpp"
#include "planning/input_checks.h"
#include "planning/planner_core.h"

namespace evade::planning {

bool PlannerCore::accept_odometry(const evade::odometry_t& odom) {
  // Late odometry is not used: the watchdog brakes once the last usable
  // one is older than odometry_max_age_s. Odometry from the future would
  // hold the rate limiter (and its age) hostage for as long as it claims.
  if (!on_time("odometry", odom.utime, p_.odometry_max_age_s)) return false;
  if (have_epoch_ && odom.epoch != epoch_) {
    start_new_epoch(odom);
    return false;
  }
  epoch_ = odom.epoch;
  have_epoch_ = true;
  // Not newer than the last: a repeat, or base_driver's "stopped" message
  // after a lost link (stamped with the last real odometry's time).
  if (last_odometry_ && odom.utime <= last_odometry_->utime) {
    count("odometry_not_newer");
    return false;
  }
  return true;
}

void PlannerCore::start_new_epoch(const evade::odometry_t& odom) {
  // base_driver restarted: its pose starts again from its initial pose, so
  // everything held in the old frame is void. Stop, then plan from scratch
  // once predictions made after this moment arrive.
  count("odometry_epoch_changed");
  epoch_ = odom.epoch;
  epoch_start_utime_ = odom.utime;
  predictions_.reset();
  predictions_rx_ = -1;
  observed_.reset();
  observed_rx_ = -1;
  static_.clear();
  seen_.clear();
  history_ = CurveFitHistory(p_.curvefit.degree, p_.curvefit.window_s);
  settled_ = SettledMemory(p_.detour.memory_s);
  prev_u_.clear();
  prev_utime_ = -1;
  prev_multipliers_.clear();
  prev_penalty_ = 0;
  prev_ids_.clear();
  topology_.reset();
  feasible_u_.clear();
  feasible_utime_ = -1;
  last_cycle_now_ = -1;
  cycle_pending_ = false;
  last_cycle_odometry_ = -1;
  odometry_rx_ = now();
  last_odometry_ = odom;
  const double v0 = std::clamp(odom.v, p_.limits.v_min, p_.limits.v_max);
  const double w0 = std::clamp(odom.omega, -p_.limits.omega_max, p_.limits.omega_max);
  publish_plan(odom, evade::plan_t::STATUS_STALE_INPUT, nullptr, braking_controls(v0, w0), 0, 0, 0);
}

bool PlannerCore::on_time(const std::string& input, int64_t utime, double max_age_s) {
  switch (arrival(now(), utime, std::llround(max_age_s * 1e6))) {
    case Arrival::kLate:
      count(input + "_late");
      return false;
    case Arrival::kFuture:
      count(input + "_future");
      return false;
    case Arrival::kOnTime:
      break;
  }
  return true;
}

bool PlannerCore::of_this_epoch(const std::string& input, int64_t utime) {
  if (epoch_start_utime_ >= 0 && utime < epoch_start_utime_) {
    count(input + "_before_epoch");  // perceived in the old odometry frame
    return false;
  }
  return true;
}

bool PlannerCore::accept_predictions(const evade::prediction_list_t& m) {
  return on_time("predictions", m.utime, p_.predictions_max_age_s) && of_this_epoch("predictions", m.utime);
}

bool PlannerCore::accept_observed(const evade::obstacle_list_t& m) {
  return on_time("obstacles", m.utime, p_.obstacles_max_age_s) && of_this_epoch("obstacles", m.utime);
}

bool PlannerCore::brake_for_invalid_track(const evade::odometry_t& odom, double v0, double w0) {
  const double r = p_.obstacle_consider_radius_m;
  const bool observed = mode_.source == ObstacleSource::kObserved;
  if (observed ? !(observed_ && invalid_observed_near(*observed_, odom.x, odom.y, r))
               : !(predictions_ && invalid_track_near(*predictions_, odom.x, odom.y, r)))
    return false;
  // Something is there that cannot be constrained against: brake.
  count("tracks_invalid_near");
  publish_plan(odom, evade::plan_t::STATUS_STOPPING, nullptr, braking_controls(v0, w0), 0, 0, 0);
  return true;
}

}  // namespace evade::planning
