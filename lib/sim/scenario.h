// A simulation scenario: the robot's start and goal, the route, the LiDAR
// and the obstacles with their motions, read from the scenario YAML whose
// format is fixed by SPEC.md ("Scenario file"). Every key is checked: an
// unknown key, a wrong type or a missing field is a config::ConfigError
// naming the file, the line and the key.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/config.h"

namespace evade::sim {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

struct Pose2 {
  double x = 0.0;    // m
  double y = 0.0;    // m
  double yaw = 0.0;  // rad
};

enum class Shape { kCylinder, kBox };
enum class MotionKind { kStatic, kConstantVelocity, kWaypoints };
// pingpong: to the last waypoint and back, forever; loop: back to the first
// point after the last, forever; once: stops at the last waypoint.
enum class WaypointMode { kPingpong, kLoop, kOnce };

struct ObstacleSpec {
  int id = 0;  // index in the scenario file's obstacle list
  Shape shape = Shape::kCylinder;
  double radius = 0.0;  // m, cylinders
  double length = 0.0;  // m, boxes: size along the box's yaw
  double width = 0.0;   // m, boxes: size across the box's yaw
  double height = 0.0;  // m, both: the solid spans z in [0, height]
  double x = 0.0;       // m, initial centre
  double y = 0.0;
  double yaw = 0.0;  // rad, fixed orientation (matters for boxes)

  MotionKind motion = MotionKind::kStatic;
  double vx = 0.0;  // m/s, constant velocity
  double vy = 0.0;
  // Waypoint motion: the path starts at (x, y) and visits `waypoints` in
  // order (a first waypoint equal to (x, y) is not repeated) at `speed`.
  std::vector<Vec2> waypoints;
  double speed = 0.0;  // m/s
  WaypointMode mode = WaypointMode::kOnce;
  // s: a moving obstacle stays at (x, y), at rest, until this long after
  // the obstacles started moving, then follows its motion from there.
  double start_delay_s = 0.0;
};

struct LidarSpec {
  std::string model = "vlp16";   // "" until resolve_robot when the scenario leaves it to the robot
  double rate_hz = 10.0;         // rotation rate
  double height = 0.5;           // m, sensor origin above the ground (0 until resolve_robot, likewise)
  double range_noise_std = 0.0;  // m, Gaussian noise added to each range
};

enum class ObstaclesStart { kAtStart, kOnRobotMotion };

struct Scenario {
  std::string name;
  std::string file;  // where it was read from
  double duration_s = 0.0;
  Pose2 start;
  Vec2 goal;
  double goal_tolerance = 0.0;  // m
  // The robot: `robot.profile` names its profile (config/robots/NAME.yaml;
  // "" none). The footprint and the LiDAR's model and height are the
  // scenario's own where it gives them, else 0 / "" until resolve_robot
  // takes them from the effective robot configuration.
  std::string profile;
  double footprint_length = 0.0;  // m, rectangle centred on the base, along the heading
  double footprint_width = 0.0;   // m
  std::vector<Vec2> route;
  LidarSpec lidar;
  std::vector<ObstacleSpec> obstacles;
  ObstaclesStart obstacles_start = ObstaclesStart::kOnRobotMotion;
  // Seeds the simulator's sensor noise (the LiDAR range noise): the same
  // scenario and seed give the same noise. A runner may override it.
  uint64_t seed = 1;
};

// Throws config::ConfigError "file:line: key 'k': reason".
Scenario load_scenario(const std::string& path);
Scenario parse_scenario(const std::string& yaml_text, const std::string& name);
Scenario scenario_from_node(const config::Node& root);
// The scenario's route as the route process takes it: [[x, y], ...] (m).
std::vector<std::vector<double>> route_waypoints(const Scenario& scenario);

// The robot values the scenario leaves out (footprint, lidar.model,
// lidar.height) from the effective robot configuration (robot.yaml <-
// profile <- this scenario: config/robot_profile.h), which holds the
// scenario's own where it gives them; a runner calls it once it has both.
// Throws config::ConfigError on a bad robot or lidar section.
void resolve_robot(Scenario* sc, const config::Node& robot_root);
// Whether resolve_robot has run or was not needed.
bool robot_resolved(const Scenario& sc);

}  // namespace evade::sim
