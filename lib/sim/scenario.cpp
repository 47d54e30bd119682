#include "sim/scenario.h"

#include <cmath>
#include <set>

#include "config/robot_params.h"

namespace evade::sim {
namespace {

// Top-level keys of a scenario file (SPEC.md, "Scenario file").
const std::set<std::string> kTopLevelKeys = {"name",  "duration_s", "robot",           "route",
                                             "lidar", "obstacles",  "obstacles_start", "seed"};

// Longest start_delay_s accepted: a day; anything longer is a typo.
constexpr double kMaxStartDelayS = 86400.0;

Vec2 point(const std::vector<double>& xy) { return Vec2{xy[0], xy[1]}; }

ObstacleSpec parse_obstacle(const config::Node& o, int id) {
  ObstacleSpec s;
  s.id = id;
  std::string shape = o.get_choice("shape", {"cylinder", "box"});
  if (shape == "cylinder") {
    s.shape = Shape::kCylinder;
    s.radius = o.get_positive("radius");
    s.height = o.get_positive("height");
  } else {
    s.shape = Shape::kBox;
    std::vector<double> size = o.get_doubles("size", 3);
    for (double d : size)
      if (!(d > 0.0)) o.fail("size", "every size [length, width, height] must be greater than 0");
    s.length = size[0];
    s.width = size[1];
    s.height = size[2];
  }
  s.x = o.get<double>("x");
  s.y = o.get<double>("y");
  if (o.has("yaw")) s.yaw = o.get<double>("yaw");

  bool velocity = o.has("vx") || o.has("vy");
  bool waypoints = o.has("waypoints");
  if (velocity && waypoints) o.fail("waypoints", "give either vx/vy or waypoints, not both");
  if (!waypoints) {
    for (const char* k : {"speed", "mode"})
      if (o.has(k)) o.fail(k, "only meaningful with waypoints");
  }
  if (o.has("start_delay_s")) {
    if (!velocity && !waypoints) o.fail("start_delay_s", "only meaningful with a motion (vx/vy or waypoints)");
    s.start_delay_s = o.get_double("start_delay_s", 0.0, kMaxStartDelayS);
  }
  if (velocity) {
    s.motion = MotionKind::kConstantVelocity;
    if (o.has("vx")) s.vx = o.get<double>("vx");
    if (o.has("vy")) s.vy = o.get<double>("vy");
  } else if (waypoints) {
    s.motion = MotionKind::kWaypoints;
    for (const auto& p : o.get_points("waypoints")) s.waypoints.push_back(point(p));
    if (s.waypoints.empty()) o.fail("waypoints", "needs at least one [x, y] point");
    s.speed = o.get_positive("speed");
    std::string mode = o.get_choice("mode", {"pingpong", "loop", "once"});
    s.mode = mode == "pingpong" ? WaypointMode::kPingpong : mode == "loop" ? WaypointMode::kLoop : WaypointMode::kOnce;
  }
  o.close();
  return s;
}

Scenario read_scenario(const config::Node& root);

}  // namespace

Scenario scenario_from_node(const config::Node& root) {
  try {
    return read_scenario(root);
  } catch (const YAML::Exception& e) {
    // yaml-cpp's own conversions (e.g. a key that is a list, `? [1, 2]: 3`)
    // become the same one-line error as every other bad input.
    throw config::ConfigError(root.file() + ":" + std::to_string(e.mark.line + 1) + ": key '': " + e.msg);
  }
}

namespace {
Scenario read_scenario(const config::Node& root) {
  for (const auto& k : root.keys())
    if (!kTopLevelKeys.count(k)) root.fail(k, "unknown key");

  Scenario sc;
  sc.file = root.file();
  sc.name = root.get<std::string>("name");
  sc.duration_s = root.get_positive("duration_s");
  if (root.has("seed")) {
    int64_t seed = root.get<int64_t>("seed");
    if (seed < 0) root.fail("seed", "must be 0 or greater");
    sc.seed = static_cast<uint64_t>(seed);
  }

  config::Node robot = root.section("robot");
  config::Node start = robot.section("start");
  sc.start = Pose2{start.get<double>("x"), start.get<double>("y"), start.get<double>("yaw")};
  start.close();
  config::Node goal = robot.section("goal");
  sc.goal = Vec2{goal.get<double>("x"), goal.get<double>("y")};
  sc.goal_tolerance = goal.get_positive("tolerance");
  goal.close();
  if (robot.has("profile")) sc.profile = robot.get<std::string>("profile");
  if (robot.has("footprint")) {
    config::Node footprint = robot.section("footprint");
    sc.footprint_length = footprint.get_positive("length");
    sc.footprint_width = footprint.get_positive("width");
    footprint.close();
  } else if (sc.profile.empty()) {
    robot.fail("footprint", "missing (give the footprint, or name the robot: robot.profile)");
  }
  robot.close();

  if (root.has("route")) {
    for (const auto& p : root.get_points("route")) sc.route.push_back(point(p));
    if (sc.route.size() < 2) root.fail("route", "needs at least two [x, y] points");
  } else {
    sc.route = {Vec2{sc.start.x, sc.start.y}, sc.goal};
  }

  config::Node lidar = root.section("lidar");
  // model and height: the robot profile's when the scenario names one and
  // leaves them out (resolve_robot checks the rate against the model then).
  const bool from_profile = !sc.profile.empty();
  sc.lidar.model = from_profile && !lidar.has("model") ? "" : lidar.get_choice("model", {"vlp16", "rs_helios"});
  sc.lidar.rate_hz = lidar.get_double("rate_hz", 5.0, 20.0);  // VLP-16 motor range (300-1200 rpm)
  if (sc.lidar.model == "rs_helios" && sc.lidar.rate_hz != 10.0 && sc.lidar.rate_hz != 20.0)
    lidar.fail("rate_hz", "the RS-Helios turns at 10 or 20 Hz (600 or 1200 rpm)");
  sc.lidar.height = from_profile && !lidar.has("height") ? 0.0 : lidar.get_double("height", 0.0, 10.0);
  sc.lidar.range_noise_std = lidar.get_double("range_noise_std", 0.0, 1.0);
  lidar.close();

  if (root.has("obstacles_start")) {
    sc.obstacles_start = root.get_choice("obstacles_start", {"at_start", "on_robot_motion"}) == "at_start"
                             ? ObstaclesStart::kAtStart
                             : ObstaclesStart::kOnRobotMotion;
  }

  if (root.has("obstacles")) {
    const YAML::Node& list = root.yaml()["obstacles"];
    if (list.IsNull()) {
      // "obstacles:" with nothing after it: an empty world.
    } else if (!list.IsSequence()) {
      root.fail("obstacles", "expected a list of obstacles");
    } else {
      int id = 0;
      for (const auto& e : list) {
        config::Node o(e, root.file(), "obstacles[" + std::to_string(id) + "]");
        if (!e.IsMap()) o.fail("", "expected a map {shape: ..., ...}");
        sc.obstacles.push_back(parse_obstacle(o, id));
        ++id;
      }
    }
  }
  return sc;
}
}  // namespace

Scenario load_scenario(const std::string& path) { return scenario_from_node(config::load_file(path)); }

Scenario parse_scenario(const std::string& yaml_text, const std::string& name) {
  return scenario_from_node(config::load_string(yaml_text, name));
}

std::vector<std::vector<double>> route_waypoints(const Scenario& scenario) {
  std::vector<std::vector<double>> w;
  for (const auto& p : scenario.route) w.push_back({p.x, p.y});
  return w;
}

}  // namespace evade::sim

namespace evade::sim {

bool robot_resolved(const Scenario& sc) {
  return sc.footprint_length > 0.0 && sc.footprint_width > 0.0 && !sc.lidar.model.empty() && sc.lidar.height > 0.0;
}

void resolve_robot(Scenario* sc, const config::Node& robot_root) {
  const auto robot = config::load<config::RobotParams>(robot_root.section("robot"));
  const auto lidar = config::load<config::LidarParams>(robot_root.section("lidar"));
  if (sc->footprint_length <= 0.0) sc->footprint_length = robot.footprint_length_m;
  if (sc->footprint_width <= 0.0) sc->footprint_width = robot.footprint_width_m;
  if (sc->lidar.model.empty()) {
    sc->lidar.model = lidar.model;
    if (sc->lidar.model == "rs_helios" && sc->lidar.rate_hz != 10.0 && sc->lidar.rate_hz != 20.0)
      throw config::ConfigError(sc->file +
                                ":0: key 'lidar.rate_hz': the RS-Helios of the robot profile turns at "
                                "10 or 20 Hz (600 or 1200 rpm)");
  }
  if (sc->lidar.height <= 0.0) sc->lidar.height = lidar.mount.z_m;
}

}  // namespace evade::sim
