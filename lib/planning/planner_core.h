// The planner process core: ODOMETRY-triggered MPC at rate_hz (on message
// time), publishing PLAN and CMD_VEL; never stuck (fallback to the last
// feasible plan shifted, then braking at the deceleration limit), never NaN.
#pragma once

#include <functional>

#include <cstdint>
#include <optional>
#include <map>
#include <vector>

#include "bus/core.h"
#include "evade/odometry_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/ceres_solver.h"
#include "planning/detour.h"
#include "planning/obstacles.h"
#include "planning/params.h"
#include "planning/reference.h"

namespace evade::planning {

class PlannerCore : public bus::Core {
 public:
  explicit PlannerCore(PlannerParams params);

  // Exposed for tests: the last plan published.
  const std::optional<evade::plan_t>& last_plan() const { return last_plan_; }

  // What PLAN.solve_time_us reports for a cycle, from its Ceres iterations
  // and the steady-clock time it took. Default: the measured time. The
  // lockstep closed loop puts its compute model here, so that a log made
  // in simulated time holds the time it charged and is byte-reproducible.
  using SolveTimeModel = std::function<double(int iterations, double measured_us)>;
  void set_solve_time_model(SolveTimeModel model) { solve_time_model_ = std::move(model); }

 private:
  void on_odometry(const evade::odometry_t& odom);
  void plan_cycle(const evade::odometry_t& odom);
  // The reference of this cycle: along the route, or round the settled
  // obstacles standing on it (detour.h).
  void make_reference(const evade::odometry_t& odom, Problem* pb);
  // A mover ahead that the detour grid keeps clear of, as its ellipse swept
  // along its velocity (*swept): a slow leader (going the route's way within
  // detour.leader_max_angle_rad, slower than leader_max_speed_mps: swept
  // leader_sweep_s) or an oncoming one (within oncoming_max_angle_rad of
  // the route's reverse heading: swept up to the robot, at most
  // oncoming_sweep_s).
  bool swept_in_grid(const evade::track_prediction_t& t, const evade::odometry_t& odom, SettledObstacle* swept) const;
  void watchdog();
  // Braking at the deceleration limits from (v, omega), as plan controls.
  std::vector<double> braking_controls(double v, double omega) const;
  // PlannerParams::escape_*: when *u (a relaxed plan) makes no headway from
  // inside d_safe, replaces it with a turn on the spot towards the way out
  // and returns true.
  bool escape_turn(const Problem& pb, double v0, double omega0, std::vector<double>* u) const;
  void publish_plan(const evade::odometry_t& odom, int8_t status, const Problem* pb, const std::vector<double>& u,
                    double solve_us, int iterations, int num_obstacles);

  PlannerParams p_;
  RouteFollower route_;
  DetourPlanner detour_;
  SettledMemory settled_;
  CurveFitHistory history_;
  std::map<int64_t, int64_t> first_seen_;  // track id -> utime of its first prediction
  double track_age_s(int64_t id, int64_t utime) const;  // since first_seen_ (0 for an unknown id)
  std::optional<evade::prediction_list_t> predictions_;
  int64_t predictions_rx_ = -1;        // bus time the predictions arrived
  int64_t odometry_rx_ = -1;           // bus time of the last odometry
  std::optional<evade::odometry_t> last_odometry_;
  int64_t next_plan_utime_ = -1;
  int64_t period_us_;
  // warm start: previous solution (any status) and previous feasible plan
  std::vector<double> prev_u_;
  int64_t prev_utime_ = -1;
  std::vector<double> prev_multipliers_;
  double prev_penalty_ = 0;
  std::vector<int64_t> prev_ids_;
  std::vector<double> feasible_u_;
  int64_t feasible_utime_ = -1;
  std::optional<evade::plan_t> last_plan_;
  bool predictions_stale() const;  // no predictions (when required) or older than predictions_max_age_s
  double last_cmd_v_ = 0, last_cmd_omega_ = 0;
  int64_t last_cmd_now_ = -1;
  SolveTimeModel solve_time_model_;
};

}  // namespace evade::planning
