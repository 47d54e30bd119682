// The metrics of one run (SPEC "Metrics"), computed from a run log:
// SIM_TRUTH gives the true geometry, PLAN the planner's side.
//
// The exact rules are in metrics_rules() (printed by `metrics --help`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bus/log.h"
#include "config/config.h"
#include "config/fields.h"
#include "metrics/contacts.h"
#include "metrics/geometry.h"
#include "metrics/reaction.h"
#include "planning/params.h"

namespace evade::metrics {

struct MetricsParams {
  double local_map_size_m = 10.0;
  double motion_threshold_mps = 0.02;
  double dynamic_speed_threshold_mps = 0.05;
  double react_match_radius_m = 1.0;
  double react_owner_switch_s = 0.5;
  double react_plan_diff_m = 0.1;
  double react_max_s = 10.0;
  double fault_approach_speed_mps = 0.1;

  template <class V>
  void fields(V& v) {
    v.field("local_map_size_m", local_map_size_m, config::positive());
    v.field("motion_threshold_mps", motion_threshold_mps, config::positive());
    v.field("dynamic_speed_threshold_mps", dynamic_speed_threshold_mps, config::positive());
    v.field("react_match_radius_m", react_match_radius_m, config::positive());
    v.field("react_owner_switch_s", react_owner_switch_s, config::positive());
    v.field("react_plan_diff_m", react_plan_diff_m, config::positive());
    v.field("react_max_s", react_max_s, config::positive());
    v.field("fault_approach_speed_mps", fault_approach_speed_mps, config::positive());
  }
  static MetricsParams from_config(const config::Node& section);
};

struct ObstacleTrack {
  int id = 0;
  std::string shape;
  double radius = 0, length = 0, width = 0;
  bool dynamic = false;
  std::vector<Vec2> path;  // centre per SIM_TRUTH sample
  std::vector<double> yaw;
  std::optional<double> t_enter_s;   // since the first SIM_TRUTH: first inside the local map, moving
  std::optional<double> t_leave_s;   // last inside the local map, moving
  std::optional<double> t_change_s;  // first plan that differs without it (reaction rule), at any time
  std::optional<double> t_react_s;   // ... in [t_enter_s, min(t_leave_s, t_enter_s + react_max_s)]
  std::vector<int64_t> tracks;       // perception tracks that were it at some time (when reactions were computed)
};

struct RunMetrics {
  std::string scenario;
  std::string mode;
  bool reached_goal = false;
  bool collided = false;
  std::vector<Contact> contacts;
  bool at_fault = false;
  int collisions_at_fault = 0;
  int collisions_not_at_fault = 0;
  bool success = false;
  bool timed_out = false;
  double min_dist_m = 0.0;
  std::optional<double> time_to_goal_s;
  std::optional<double> reaction_time_s;
  int reaction_missed = 0;
  std::optional<double> speed_var;
  double path_length_m = 0.0;
  std::optional<double> planner_solve_ms_p50;
  std::optional<double> planner_solve_ms_p99;
  std::optional<double> planner_cycle_ms_p99;
  int solver_failures = 0;
  std::optional<ReplayCheck> replay_check;  // set when the reactions were computed
  int plans = 0;
  double duration_s = 0.0;           // SIM_TRUTH span
  double scenario_duration_s = 0.0;  // the scenario's time limit
  double final_goal_distance_m = 0.0;

  // For the picture.
  std::vector<Vec2> robot_path;
  std::vector<double> robot_yaw;
  std::vector<double> robot_speed;
  std::vector<double> robot_t_s;  // since first SIM_TRUTH
  std::vector<ObstacleTrack> obstacles;
  std::vector<Vec2> route;
  Vec2 goal;
  double goal_tolerance = 0.0;
  double footprint_length = 0.0, footprint_width = 0.0;
  int closest_sample = -1;
  int closest_obstacle = -1;
  Vec2 closest_on_robot, closest_on_obstacle;
};

// Throws std::runtime_error when the log has no SIM_TRUTH. With `planner`
// (the run's planner configuration; its mode is taken from the log's PLAN)
// the reaction times are computed by counterfactual replay; without it
// there are none.
RunMetrics compute_metrics(const std::vector<bus::LogEvent>& events, const MetricsParams& params,
                           const planning::PlannerParams* planner = nullptr);
std::string metrics_json(const RunMetrics& m);
// How every metric is computed, in words.
const char* metrics_rules();

}  // namespace evade::metrics
