#include "metrics/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "bus/core.h"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/sim_truth_t.hpp"

namespace evade::metrics {

const char* metrics_rules() {
  return R"(Rules:
- first motion: the first SIM_TRUTH with |v| above motion_threshold_mps.
- reached_goal: the robot centre comes within the scenario's goal
  tolerance of the goal; time_to_goal_s runs from first motion to then.
- min_dist_m: the smallest 2D clearance between the footprint rectangle
  and any obstacle (cylinder = circle, box = oriented rectangle) over the
  whole run up to the goal; collided: that clearance reached 0.
- local map: the square of side local_map_size_m centred on the robot,
  aligned with the world axes (as the elevation map is).
- a dynamic obstacle is one whose true speed exceeds
  dynamic_speed_threshold_mps at some point of the run.
- speed_var: population variance of the robot's true linear speed over the
  SIM_TRUTH samples, after first motion and before the goal, at which some
  moving dynamic obstacle's centre is inside the local map.
- reaction_time_s: for each dynamic obstacle, t_enter = the first time its
  centre is inside the local map while it moves; t_react = the first PLAN
  at or after t_enter in which a constraint of a track matched to it (the
  track's current centre within react_match_radius_m of the obstacle's
  true centre) is active, i.e. within react_active_tol_m of its bound at
  some step, so the obstacle is shaping the plan. The mean over obstacles
  that got a reaction; obstacles that never shaped a plan are counted in
  reaction_missed.
- path_length_m: robot path length from first motion to the goal (or end).
- planner_solve_ms_p50/p99: over PLAN messages with a solve (iterations > 0).
- solver_failures: PLAN messages with status FALLBACK, STOPPING or RECOVERING
  (no plan met every constraint).
)";
}

MetricsParams MetricsParams::from_config(const config::Node& s) {
  MetricsParams p;
  p.local_map_size_m = s.get_positive("local_map_size_m");
  p.motion_threshold_mps = s.get_positive("motion_threshold_mps");
  p.dynamic_speed_threshold_mps = s.get_positive("dynamic_speed_threshold_mps");
  p.react_match_radius_m = s.get_positive("react_match_radius_m");
  p.react_active_tol_m = s.get_positive("react_active_tol_m");
  s.close();
  return p;
}

namespace {

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  double pos = q * (v.size() - 1);
  size_t lo = static_cast<size_t>(std::floor(pos));
  size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

double obstacle_clearance(const OrientedRect& robot, const evade::sim_obstacle_t& o) {
  if (o.shape == "box") return clearance(robot, OrientedRect{{o.x, o.y}, o.yaw, o.length, o.width});
  return clearance(robot, Vec2{o.x, o.y}, o.radius);
}

bool in_local_map(const Vec2& robot, const Vec2& p, double side) {
  return std::fabs(p.x - robot.x) <= 0.5 * side && std::fabs(p.y - robot.y) <= 0.5 * side;
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::string opt(const std::optional<double>& v) { return v ? num(*v) : "null"; }

}  // namespace

RunMetrics compute_metrics(const std::vector<bus::LogEvent>& events, const MetricsParams& params) {
  RunMetrics m;
  std::vector<evade::sim_truth_t> truth;
  std::vector<evade::plan_t> plans;
  for (const auto& e : events) {
    if (e.channel == "SIM_TRUTH") {
      evade::sim_truth_t t;
      if (bus::decode(e.data.data(), e.data.size(), &t)) truth.push_back(std::move(t));
    } else if (e.channel == "PLAN") {
      evade::plan_t p;
      if (bus::decode(e.data.data(), e.data.size(), &p)) plans.push_back(std::move(p));
    } else if (e.channel == "ROUTE" && m.route.empty()) {
      evade::path_t r;
      if (bus::decode(e.data.data(), e.data.size(), &r))
        for (int i = 0; i < r.n; ++i) m.route.push_back({r.x[i], r.y[i]});
    }
  }
  if (truth.empty()) throw std::runtime_error("no SIM_TRUTH in the log: metrics need a simulated run");
  std::sort(truth.begin(), truth.end(), [](const auto& a, const auto& b) { return a.utime < b.utime; });

  const auto& first = truth.front();
  m.scenario = first.scenario;
  m.goal = {first.goal_x, first.goal_y};
  m.goal_tolerance = first.goal_tolerance;
  m.footprint_length = first.footprint_length;
  m.footprint_width = first.footprint_width;
  const int64_t t0 = first.utime;
  m.duration_s = (truth.back().utime - t0) * 1e-6;

  // Obstacles by id, and which are dynamic.
  std::map<int, size_t> index;
  for (const auto& t : truth)
    for (const auto& o : t.obstacles) {
      if (!index.count(o.id)) {
        index[o.id] = m.obstacles.size();
        ObstacleTrack tr;
        tr.id = o.id;
        tr.shape = o.shape;
        tr.radius = o.radius;
        tr.length = o.length;
        tr.width = o.width;
        m.obstacles.push_back(tr);
      }
      if (std::hypot(o.vx, o.vy) > params.dynamic_speed_threshold_mps) m.obstacles[index[o.id]].dynamic = true;
    }

  int64_t t_motion = -1, t_goal = -1;
  m.min_dist_m = std::numeric_limits<double>::infinity();
  std::vector<double> speeds_near;
  Vec2 prev{};
  for (size_t k = 0; k < truth.size(); ++k) {
    const auto& t = truth[k];
    Vec2 p{t.x, t.y};
    m.robot_path.push_back(p);
    m.robot_yaw.push_back(t.yaw);
    m.robot_speed.push_back(t.v);
    m.robot_t_s.push_back((t.utime - t0) * 1e-6);
    for (const auto& o : t.obstacles) {
      auto& tr = m.obstacles[index[o.id]];
      tr.path.push_back({o.x, o.y});
      tr.yaw.push_back(o.yaw);
    }
    if (t_goal >= 0) continue;  // after the goal only the picture needs samples
    if (t_motion < 0 && std::fabs(t.v) > params.motion_threshold_mps) t_motion = t.utime;
    if (t_motion >= 0 && k > 0) m.path_length_m += std::hypot(p.x - prev.x, p.y - prev.y);
    prev = p;

    OrientedRect robot{p, t.yaw, t.footprint_length, t.footprint_width};
    for (const auto& o : t.obstacles) {
      double c = obstacle_clearance(robot, o);
      if (c < m.min_dist_m) {
        m.min_dist_m = c;
        m.closest_sample = static_cast<int>(k);
        m.closest_obstacle = o.id;
        if (o.shape == "box")
          closest_points(robot, OrientedRect{{o.x, o.y}, o.yaw, o.length, o.width}, &m.closest_on_robot,
                         &m.closest_on_obstacle);
        else
          closest_points(robot, Vec2{o.x, o.y}, o.radius, &m.closest_on_robot, &m.closest_on_obstacle);
      }
    }
    bool dynamic_near = false;
    for (const auto& o : t.obstacles) {
      auto& tr = m.obstacles[index[o.id]];
      bool moving = t.obstacles_moving && std::hypot(o.vx, o.vy) > params.dynamic_speed_threshold_mps;
      if (tr.dynamic && moving && in_local_map(p, {o.x, o.y}, params.local_map_size_m)) {
        dynamic_near = true;
        if (!tr.t_enter_s) tr.t_enter_s = (t.utime - t0) * 1e-6;
      }
    }
    if (t_motion >= 0 && dynamic_near) speeds_near.push_back(t.v);
    if (std::hypot(p.x - m.goal.x, p.y - m.goal.y) <= m.goal_tolerance) t_goal = t.utime;
  }
  if (m.obstacles.empty()) m.min_dist_m = std::numeric_limits<double>::infinity();
  m.collided = m.min_dist_m <= 0.0;
  m.reached_goal = t_goal >= 0;
  if (m.reached_goal && t_motion >= 0) m.time_to_goal_s = (t_goal - t_motion) * 1e-6;
  m.final_goal_distance_m = std::hypot(truth.back().x - m.goal.x, truth.back().y - m.goal.y);
  if (!speeds_near.empty()) {
    double mean = 0;
    for (double v : speeds_near) mean += v;
    mean /= speeds_near.size();
    double var = 0;
    for (double v : speeds_near) var += (v - mean) * (v - mean);
    m.speed_var = var / speeds_near.size();
  }

  // Planner side.
  std::vector<double> solve_ms;
  for (const auto& p : plans) {
    ++m.plans;
    if (m.mode.empty()) m.mode = p.mode;
    if (p.iterations > 0) solve_ms.push_back(p.solve_time_us * 1e-3);
    if (p.status == evade::plan_t::STATUS_FALLBACK || p.status == evade::plan_t::STATUS_STOPPING ||
        p.status == evade::plan_t::STATUS_RECOVERING)
      ++m.solver_failures;
  }
  // Reaction: the first plan at or after t_enter in which a track matched
  // to the obstacle has an active constraint (see metrics_rules()).
  std::vector<int64_t> truth_t;
  for (const auto& t : truth) truth_t.push_back(t.utime);
  double reaction_sum = 0;
  int reactions = 0;
  for (auto& tr : m.obstacles) {
    if (!tr.dynamic || !tr.t_enter_s) continue;
    const int64_t t_enter = t0 + static_cast<int64_t>(*tr.t_enter_s * 1e6);
    for (const auto& p : plans) {
      if (p.utime < t_enter) continue;
      size_t k = std::lower_bound(truth_t.begin(), truth_t.end(), p.utime) - truth_t.begin();
      if (k >= truth.size()) break;
      if (k >= tr.path.size()) break;
      const Vec2 truth_centre = tr.path[k];
      bool reacts = false;
      for (int i = 0; i < p.num_obstacles && !reacts; ++i)
        reacts = p.obstacle_slack[i] <= params.react_active_tol_m &&
                 std::hypot(p.obstacle_x[i] - truth_centre.x, p.obstacle_y[i] - truth_centre.y) <=
                     params.react_match_radius_m;
      if (reacts) {
        tr.t_react_s = (p.utime - t0) * 1e-6;
        break;
      }
    }
    if (tr.t_react_s) {
      reaction_sum += *tr.t_react_s - *tr.t_enter_s;
      ++reactions;
    } else {
      ++m.reaction_missed;
    }
  }
  if (reactions > 0) m.reaction_time_s = reaction_sum / reactions;

  if (!solve_ms.empty()) {
    m.planner_solve_ms_p50 = percentile(solve_ms, 0.5);
    m.planner_solve_ms_p99 = percentile(solve_ms, 0.99);
  }
  return m;
}

std::string metrics_json(const RunMetrics& m) {
  std::string s = "{\n";
  auto add = [&](const std::string& k, const std::string& v, bool last = false) {
    s += "  \"" + k + "\": " + v + (last ? "\n" : ",\n");
  };
  add("scenario", "\"" + m.scenario + "\"");
  add("mode", "\"" + m.mode + "\"");
  add("reached_goal", m.reached_goal ? "true" : "false");
  add("collided", m.collided ? "true" : "false");
  add("min_dist_m", std::isfinite(m.min_dist_m) ? num(m.min_dist_m) : "null");
  add("time_to_goal_s", opt(m.time_to_goal_s));
  add("reaction_time_s", opt(m.reaction_time_s));
  add("reaction_missed", std::to_string(m.reaction_missed));
  add("speed_var", opt(m.speed_var));
  add("path_length_m", num(m.path_length_m));
  add("planner_solve_ms_p50", opt(m.planner_solve_ms_p50));
  add("planner_solve_ms_p99", opt(m.planner_solve_ms_p99));
  add("solver_failures", std::to_string(m.solver_failures));
  add("plans", std::to_string(m.plans));
  add("final_goal_distance_m", num(m.final_goal_distance_m));
  add("duration_s", num(m.duration_s), true);
  return s + "}\n";
}

}  // namespace evade::metrics
