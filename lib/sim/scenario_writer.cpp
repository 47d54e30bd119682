#include "sim/scenario_writer.h"

#include <cstdio>
#include <sstream>

namespace evade::sim {
namespace {

std::string point(const Vec2& p) { return "[" + yaml_number(p.x) + ", " + yaml_number(p.y) + "]"; }

std::string points(const std::vector<Vec2>& ps) {
  std::string s = "[";
  for (size_t i = 0; i < ps.size(); ++i) s += (i ? ", " : "") + point(ps[i]);
  return s + "]";
}

const char* mode_name(WaypointMode m) {
  switch (m) {
    case WaypointMode::kPingpong:
      return "pingpong";
    case WaypointMode::kLoop:
      return "loop";
    case WaypointMode::kOnce:
      return "once";
  }
  return "once";
}

std::string obstacle(const ObstacleSpec& o) {
  std::ostringstream s;
  if (o.shape == Shape::kCylinder) {
    s << "{shape: cylinder, radius: " << yaml_number(o.radius) << ", height: " << yaml_number(o.height);
  } else {
    s << "{shape: box, size: [" << yaml_number(o.length) << ", " << yaml_number(o.width) << ", "
      << yaml_number(o.height) << "]";
  }
  s << ", x: " << yaml_number(o.x) << ", y: " << yaml_number(o.y);
  if (o.yaw != 0.0) s << ", yaw: " << yaml_number(o.yaw);
  if (o.motion == MotionKind::kConstantVelocity) {
    s << ",\n     vx: " << yaml_number(o.vx) << ", vy: " << yaml_number(o.vy);
  } else if (o.motion == MotionKind::kWaypoints) {
    s << ",\n     waypoints: " << points(o.waypoints) << ",\n     speed: " << yaml_number(o.speed)
      << ", mode: " << mode_name(o.mode);
  }
  if (o.motion != MotionKind::kStatic && o.start_delay_s != 0.0)
    s << ", start_delay_s: " << yaml_number(o.start_delay_s);
  s << "}";
  return s.str();
}

}  // namespace

std::string yaml_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.4f", v);
  std::string s = buf;
  while (s.back() == '0' && s[s.size() - 2] != '.') s.pop_back();
  if (s == "-0.0") s = "0.0";
  return s;
}

std::string scenario_yaml(const Scenario& sc, const std::vector<std::string>& header,
                          const std::vector<std::string>& notes) {
  std::ostringstream y;
  for (const std::string& h : header) y << "# " << h << "\n";
  y << "name: " << sc.name << "\n";
  y << "duration_s: " << yaml_number(sc.duration_s) << "\n";
  y << "seed: " << sc.seed << "\n";
  y << "robot:\n";
  y << "  start: {x: " << yaml_number(sc.start.x) << ", y: " << yaml_number(sc.start.y)
    << ", yaw: " << yaml_number(sc.start.yaw) << "}\n";
  y << "  goal: {x: " << yaml_number(sc.goal.x) << ", y: " << yaml_number(sc.goal.y)
    << ", tolerance: " << yaml_number(sc.goal_tolerance) << "}\n";
  if (!sc.profile.empty()) y << "  profile: " << sc.profile << "\n";
  if (sc.footprint_length > 0.0)  // else the profile's (robot_resolved)
    y << "  footprint: {length: " << yaml_number(sc.footprint_length) << ", width: " << yaml_number(sc.footprint_width)
      << "}\n";
  y << "route: " << points(sc.route) << "\n";
  y << "lidar: {";
  if (!sc.lidar.model.empty()) y << "model: " << sc.lidar.model << ", ";
  y << "rate_hz: " << yaml_number(sc.lidar.rate_hz);
  if (sc.lidar.height > 0.0) y << ", height: " << yaml_number(sc.lidar.height);
  y << ", range_noise_std: " << yaml_number(sc.lidar.range_noise_std) << "}\n";
  y << "obstacles_start: " << (sc.obstacles_start == ObstaclesStart::kAtStart ? "at_start" : "on_robot_motion") << "\n";
  y << "obstacles:" << (sc.obstacles.empty() ? " []" : "") << "\n";
  for (size_t i = 0; i < sc.obstacles.size(); ++i) {
    if (i < notes.size() && !notes[i].empty()) y << "  # " << notes[i] << "\n";
    y << "  - " << obstacle(sc.obstacles[i]) << "\n";
  }
  return y.str();
}

}  // namespace evade::sim
