// The scenario generator's shared helpers (scenario_gen_families.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sim/scenario_gen_families.h"
#include "sim/scenario_geometry.h"

namespace evade::sim::gen::detail {

double q(double v, double step) {
  double r = std::round(v / step) * step;
  return r == 0.0 ? 0.0 : r;  // no -0
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f", v);
  return std::string(buf) == "-0.00" ? "0.00" : buf;
}

std::string timing(double lead_s) {
  return num(std::fabs(lead_s)) + (lead_s >= 0.0 ? " s before the robot" : " s after the robot");
}

std::string count(int n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

double path_length(const std::vector<Vec2>& path) {
  double l = 0.0;
  for (size_t i = 1; i < path.size(); ++i) l += geom::distance(path[i - 1], path[i]);
  return l;
}

double arrival_s(const Ctx& c, const Draft& d, double x) {
  // Arc length along the route (monotone in x) up to x.
  const std::vector<Vec2>& r = d.sc.route;
  double s = 0.0;
  for (size_t i = 1; i < r.size(); ++i) {
    double dx = r[i].x - r[i - 1].x, seg = geom::distance(r[i - 1], r[i]);
    if (x <= r[i].x || i + 1 == r.size()) {
      double f = dx > 0.0 ? std::clamp((x - r[i - 1].x) / dx, 0.0, 1.0) : 0.0;
      s += f * seg;
      break;
    }
    s += seg;
  }
  return s / c.robot.reference_speed_mps + c.p.common.arrival_lag_s;
}

bool is_clear(const Ctx& c, const Draft& d, const ObstacleSpec& o) {
  if (start_clearance(d.sc, o, c.check) < c.check.start_margin_m) return false;
  for (const ObstacleSpec& other : d.sc.obstacles)
    if (start_gap(o, other) < c.check.apart_m) return false;
  Vec2 rest;
  if (final_rest(o, &rest)) {
    double half_diagonal = std::hypot(d.sc.footprint_length, d.sc.footprint_width) / 2.0;
    double gap =
        geom::clearance(geom::disc(d.sc.goal.x, d.sc.goal.y, half_diagonal), geom::obstacle_outline(o, rest.x, rest.y));
    if (gap < c.check.goal_margin_m) return false;
  }
  return true;
}

bool add_all_if_clear(const Ctx& c, Draft& d, const std::vector<ObstacleSpec>& os,
                      const std::vector<std::string>& notes) {
  for (size_t i = 0; i < os.size(); ++i) {
    if (!is_clear(c, d, os[i])) return false;
    for (size_t j = 0; j < i; ++j)
      if (start_gap(os[i], os[j]) < c.check.apart_m) return false;
  }
  for (size_t i = 0; i < os.size(); ++i) {
    ObstacleSpec added = os[i];
    added.id = static_cast<int>(d.sc.obstacles.size());
    d.sc.obstacles.push_back(added);
    d.notes.push_back(i < notes.size() ? notes[i] : "");
  }
  return true;
}

bool add_if_clear(const Ctx& c, Draft& d, const ObstacleSpec& o, const std::string& note) {
  return add_all_if_clear(c, d, {o}, {note});
}

Draft straight_draft(Ctx& c) {
  const CommonParams& k = c.p.common;
  Draft d;
  double half = q(c.rng.uniform(k.route_length_m) / 2.0, 0.01);
  d.sc.start = Pose2{-half, 0.0, 0.0};
  d.sc.goal = Vec2{half, 0.0};
  d.sc.goal_tolerance = k.goal_tolerance_m;
  d.sc.footprint_length = c.robot.footprint_length_m;
  d.sc.footprint_width = c.robot.footprint_width_m;
  d.sc.route = {Vec2{-half, 0.0}, d.sc.goal};
  d.sc.profile = c.robot.profile;
  d.sc.lidar.model = c.robot.lidar_model;
  d.sc.lidar.rate_hz = k.lidar_rate_hz;
  d.sc.lidar.height = c.robot.lidar_height_m;
  d.sc.lidar.range_noise_std = k.range_noise_std_m;
  d.sc.obstacles_start = ObstaclesStart::kOnRobotMotion;
  return d;
}

double meet_x(Ctx& c, const Draft& d) {
  return q(c.rng.uniform(d.sc.start.x + c.p.common.meet_from_start_m, d.sc.goal.x - c.p.common.meet_before_goal_m));
}

Vec2 heading(double angle_rad) { return Vec2{std::cos(angle_rad), std::sin(angle_rad)}; }

Vec2 along(const Vec2& from, const Vec2& dir, double distance) {
  return Vec2{from.x + dir.x * distance, from.y + dir.y * distance};
}

ObstacleSpec cylinder_body(Ctx& c, const CylinderKind& k) {
  ObstacleSpec o;
  o.shape = Shape::kCylinder;
  o.radius = q(c.rng.uniform(k.radius_m));
  o.height = q(c.rng.uniform(k.height_m));
  return o;
}

ObstacleSpec box_body(Ctx& c, const BoxKind& k, double yaw) {
  ObstacleSpec o;
  o.shape = Shape::kBox;
  o.length = q(c.rng.uniform(k.length_m));
  o.width = q(c.rng.uniform(k.width_m));
  o.height = q(c.rng.uniform(k.height_m));
  o.yaw = q(yaw, 1e-4);
  return o;
}

namespace {
// The path from arc length `cut` on.
std::vector<Vec2> cut_path(const std::vector<Vec2>& path, double cut) {
  for (size_t i = 1; i < path.size(); ++i) {
    double seg = geom::distance(path[i - 1], path[i]);
    if (cut < seg) {
      double f = cut / seg;
      std::vector<Vec2> out{
          Vec2{path[i - 1].x + f * (path[i].x - path[i - 1].x), path[i - 1].y + f * (path[i].y - path[i - 1].y)}};
      out.insert(out.end(), path.begin() + static_cast<long>(i), path.end());
      return out;
    }
    cut -= seg;
  }
  return {path.back()};
}
}  // namespace

void follow_timed(ObstacleSpec& o, std::vector<Vec2> path, double speed, double s_meet, double t_meet) {
  o.speed = q(speed);
  double delay = std::max(0.0, t_meet) - s_meet / o.speed;
  if (delay < 0.0) {
    path = cut_path(path, -delay * o.speed);
    delay = 0.0;
  }
  for (Vec2& p : path) p = Vec2{q(p.x), q(p.y)};
  o.x = path.front().x;
  o.y = path.front().y;
  o.motion = MotionKind::kWaypoints;
  o.mode = WaypointMode::kOnce;
  o.waypoints.assign(path.begin() + 1, path.end());
  if (o.waypoints.empty()) o.waypoints.push_back(path.front());
  o.start_delay_s = q(delay, 0.01);
}

}  // namespace evade::sim::gen::detail
