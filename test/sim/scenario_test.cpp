// Scenario loading: the SPEC format is read exactly, every shipped scenario
// loads, and malformed files fail with file, line and key.
#include "sim/scenario.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "config/robot_profile.h"

namespace evade::sim {
namespace {

const char* kSpecExample = R"(name: paper_sim
duration_s: 60                    # hard stop
robot:
  start: {x: -10.0, y: 0.0, yaw: 0.0}
  goal: {x: 9.0, y: 0.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
route: [[-10.0, 0.0], [9.0, 0.0]]
lidar: {model: vlp16, rate_hz: 10, height: 0.5, range_noise_std: 0.01}
obstacles:
  - {shape: cylinder, radius: 0.25, height: 0.5, x: 5.0, y: 4.0}
  - {shape: box, size: [1.0, 2.0, 1.0], x: 2.0, y: 3.0, yaw: 0.3}
  - {shape: cylinder, radius: 0.25, height: 0.5, x: -4.5, y: 0.5,
     vx: -1.0, vy: 0.5}
  - {shape: cylinder, radius: 0.3, height: 1.7, x: 0.0, y: 3.0,
     waypoints: [[0.0, 3.0], [0.0, -3.0]], speed: 1.2,
     mode: pingpong}
)";

std::string error_of(const std::string& text) {
  try {
    parse_scenario(text, "bad.yaml");
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(Scenario, ReadsTheSpecExample) {
  Scenario sc = parse_scenario(kSpecExample, "spec.yaml");
  EXPECT_EQ(sc.name, "paper_sim");
  EXPECT_DOUBLE_EQ(sc.duration_s, 60.0);
  EXPECT_DOUBLE_EQ(sc.start.x, -10.0);
  EXPECT_DOUBLE_EQ(sc.goal.x, 9.0);
  EXPECT_DOUBLE_EQ(sc.goal_tolerance, 0.3);
  EXPECT_DOUBLE_EQ(sc.footprint_length, 0.42);
  EXPECT_DOUBLE_EQ(sc.footprint_width, 0.31);
  ASSERT_EQ(sc.route.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.route[1].x, 9.0);
  EXPECT_EQ(sc.lidar.model, "vlp16");
  EXPECT_DOUBLE_EQ(sc.lidar.rate_hz, 10.0);
  EXPECT_DOUBLE_EQ(sc.lidar.height, 0.5);
  EXPECT_DOUBLE_EQ(sc.lidar.range_noise_std, 0.01);
  EXPECT_EQ(sc.obstacles_start, ObstaclesStart::kOnRobotMotion);
  ASSERT_EQ(sc.obstacles.size(), 4u);
  EXPECT_EQ(sc.obstacles[0].motion, MotionKind::kStatic);
  EXPECT_EQ(sc.obstacles[1].shape, Shape::kBox);
  EXPECT_DOUBLE_EQ(sc.obstacles[1].length, 1.0);
  EXPECT_DOUBLE_EQ(sc.obstacles[1].width, 2.0);
  EXPECT_DOUBLE_EQ(sc.obstacles[1].height, 1.0);
  EXPECT_DOUBLE_EQ(sc.obstacles[1].yaw, 0.3);
  EXPECT_EQ(sc.obstacles[2].motion, MotionKind::kConstantVelocity);
  EXPECT_DOUBLE_EQ(sc.obstacles[2].vx, -1.0);
  EXPECT_DOUBLE_EQ(sc.obstacles[2].vy, 0.5);
  EXPECT_EQ(sc.obstacles[3].motion, MotionKind::kWaypoints);
  EXPECT_EQ(sc.obstacles[3].mode, WaypointMode::kPingpong);
  EXPECT_DOUBLE_EQ(sc.obstacles[3].speed, 1.2);
  ASSERT_EQ(sc.obstacles[3].waypoints.size(), 2u);
  EXPECT_DOUBLE_EQ(sc.obstacles[3].waypoints[1].y, -3.0);
  EXPECT_EQ(sc.obstacles[3].id, 3);
}

TEST(Scenario, ObstaclesStartAtStart) {
  Scenario sc = parse_scenario(std::string(kSpecExample) + "obstacles_start: at_start\n", "s.yaml");
  EXPECT_EQ(sc.obstacles_start, ObstaclesStart::kAtStart);
}

TEST(Scenario, SeedDefaultsToOneAndIsRead) {
  EXPECT_EQ(parse_scenario(kSpecExample, "s.yaml").seed, 1u);
  EXPECT_EQ(parse_scenario(std::string(kSpecExample) + "seed: 4000000000\n", "s.yaml").seed, 4000000000u);
  EXPECT_EQ(parse_scenario(std::string(kSpecExample) + "seed: 0\n", "s.yaml").seed, 0u);
  EXPECT_EQ(error_of(std::string(kSpecExample) + "seed: -3\n"), "bad.yaml:17: key 'seed': must be 0 or greater");
  EXPECT_EQ(error_of(std::string(kSpecExample) + "seed: 1.5\n").rfind("bad.yaml:17: key 'seed':", 0), 0u);
}

TEST(Scenario, StartDelayIsReadForMoversOnly) {
  Scenario sc = parse_scenario(kSpecExample, "s.yaml");
  for (const ObstacleSpec& o : sc.obstacles) EXPECT_EQ(o.start_delay_s, 0.0);
  sc = parse_scenario(replace(kSpecExample, "mode: pingpong}", "mode: pingpong, start_delay_s: 2.5}"), "s.yaml");
  EXPECT_DOUBLE_EQ(sc.obstacles[3].start_delay_s, 2.5);
  sc = parse_scenario(replace(kSpecExample, "vx: -1.0, vy: 0.5}", "vx: -1.0, vy: 0.5, start_delay_s: 1}"), "s.yaml");
  EXPECT_DOUBLE_EQ(sc.obstacles[2].start_delay_s, 1.0);
  EXPECT_EQ(error_of(replace(kSpecExample, "x: 5.0, y: 4.0}", "x: 5.0, y: 4.0, start_delay_s: 1}")),
            "bad.yaml:10: key 'obstacles[0].start_delay_s': only meaningful with a motion (vx/vy or waypoints)");
  EXPECT_EQ(error_of(replace(kSpecExample, "mode: pingpong}", "mode: pingpong, start_delay_s: -1}")),
            "bad.yaml:16: key 'obstacles[3].start_delay_s': value -1 outside [0, 86400]");
}

TEST(Scenario, LidarModelIsVlp16OrRsHeliosAtItsRates) {
  Scenario sc = parse_scenario(replace(kSpecExample, "model: vlp16", "model: rs_helios"), "s.yaml");
  EXPECT_EQ(sc.lidar.model, "rs_helios");
  sc = parse_scenario(replace(replace(kSpecExample, "model: vlp16", "model: rs_helios"), "rate_hz: 10", "rate_hz: 20"),
                      "s.yaml");
  EXPECT_DOUBLE_EQ(sc.lidar.rate_hz, 20.0);
  EXPECT_EQ(error_of(replace(replace(kSpecExample, "model: vlp16", "model: rs_helios"), "rate_hz: 10", "rate_hz: 15")),
            "bad.yaml:8: key 'lidar.rate_hz': the RS-Helios turns at 10 or 20 Hz (600 or 1200 rpm)");
  EXPECT_EQ(error_of(replace(kSpecExample, "model: vlp16", "model: hdl32")),
            "bad.yaml:8: key 'lidar.model': 'hdl32' is not one of: vlp16, rs_helios");
  EXPECT_DOUBLE_EQ(parse_scenario(replace(kSpecExample, "rate_hz: 10", "rate_hz: 15"), "s.yaml").lidar.rate_hz, 15.0);
}

TEST(Scenario, UnknownTopLevelKeyNamesFileLineKey) {
  EXPECT_EQ(error_of(std::string(kSpecExample) + "speed_limit: 3\n"), "bad.yaml:17: key 'speed_limit': unknown key");
}

TEST(Scenario, UnknownObstacleKeyNamesFileLineKey) {
  std::string text = replace(kSpecExample, "x: 5.0, y: 4.0}", "x: 5.0, y: 4.0, colour: red}");
  EXPECT_EQ(error_of(text), "bad.yaml:10: key 'obstacles[0].colour': unknown key");
}

TEST(Scenario, CylinderWithABoxSizeIsAnError) {
  std::string text =
      replace(kSpecExample, "radius: 0.25, height: 0.5, x: 5.0", "radius: 0.25, height: 0.5, size: [1, 1, 1], x: 5.0");
  EXPECT_EQ(error_of(text), "bad.yaml:10: key 'obstacles[0].size': unknown key");
}

TEST(Scenario, WrongTypeNamesFileLineKey) {
  std::string text = replace(kSpecExample, "speed: 1.2", "speed: fast");
  EXPECT_EQ(error_of(text), "bad.yaml:15: key 'obstacles[3].speed': expected a number, found 'fast'");
  text = replace(kSpecExample, "rate_hz: 10", "rate_hz: [10]");
  EXPECT_EQ(error_of(text), "bad.yaml:8: key 'lidar.rate_hz': expected a number, found a list");
}

TEST(Scenario, MissingFieldNamesFileLineKey) {
  std::string text = replace(kSpecExample, "  goal: {x: 9.0, y: 0.0, tolerance: 0.3}", "  goal: {x: 9.0, y: 0.0}");
  EXPECT_EQ(error_of(text), "bad.yaml:5: key 'robot.goal.tolerance': missing");
  text = replace(kSpecExample, ", speed: 1.2,", ",");
  EXPECT_EQ(error_of(text), "bad.yaml:14: key 'obstacles[3].speed': missing");
}

// robot.profile names the robot: the footprint and the LiDAR's model and
// height may then be left to it (resolve_robot fills them from the merged
// configuration); without a profile the footprint is required.
TEST(Scenario, AProfileMayGiveTheFootprintAndLidar) {
  const std::string named =
      replace(replace(kSpecExample, "  footprint: {length: 0.42, width: 0.31}\n", "  profile: small\n"),
              "lidar: {model: vlp16, rate_hz: 10, height: 0.5, range_noise_std: 0.01}",
              "lidar: {rate_hz: 10, range_noise_std: 0.01}");
  Scenario sc = parse_scenario(named, "named.yaml");
  EXPECT_EQ(sc.profile, "small");
  EXPECT_FALSE(robot_resolved(sc));
  const config::Node root =
      config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml", {"scout2", ""});
  resolve_robot(&sc, root);
  EXPECT_TRUE(robot_resolved(sc));
  EXPECT_DOUBLE_EQ(sc.footprint_length, 0.93);
  EXPECT_DOUBLE_EQ(sc.footprint_width, 0.7);
  EXPECT_EQ(sc.lidar.model, "rs_helios");
  EXPECT_DOUBLE_EQ(sc.lidar.height, 0.55);
  // the scenario's own values stay its own
  Scenario own = parse_scenario(kSpecExample, "own.yaml");
  resolve_robot(&own, root);
  EXPECT_DOUBLE_EQ(own.footprint_length, 0.42);
  EXPECT_EQ(own.lidar.model, "vlp16");
  EXPECT_EQ(error_of(replace(kSpecExample, "  footprint: {length: 0.42, width: 0.31}\n", "")),
            "bad.yaml:4: key 'robot.footprint': missing (give the footprint, or name the robot: robot.profile)");
}

TEST(Scenario, BadValuesAreRejected) {
  EXPECT_EQ(error_of(replace(kSpecExample, "mode: pingpong", "mode: bounce")),
            "bad.yaml:16: key 'obstacles[3].mode': 'bounce' is not one of: pingpong, loop, once");
  EXPECT_EQ(error_of(replace(kSpecExample, "shape: box", "shape: sphere")),
            "bad.yaml:11: key 'obstacles[1].shape': 'sphere' is not one of: cylinder, box");
  EXPECT_EQ(error_of(replace(kSpecExample, "size: [1.0, 2.0, 1.0]", "size: [1.0, 2.0]")),
            "bad.yaml:11: key 'obstacles[1].size': expected 3 numbers, found 2");
  EXPECT_EQ(error_of(replace(kSpecExample, "radius: 0.3,", "radius: -0.3,")),
            "bad.yaml:14: key 'obstacles[3].radius': must be greater than 0");
  EXPECT_EQ(error_of(replace(kSpecExample, "vx: -1.0, vy: 0.5", "vx: -1.0, vy: 0.5, waypoints: [[0, 0]]")),
            "bad.yaml:13: key 'obstacles[2].waypoints': give either vx/vy or waypoints, not both");
  EXPECT_EQ(error_of(replace(kSpecExample, "x: 5.0, y: 4.0}", "x: 5.0, y: 4.0, speed: 1}")),
            "bad.yaml:10: key 'obstacles[0].speed': only meaningful with waypoints");
  EXPECT_EQ(error_of(replace(kSpecExample, "obstacles:\n", "obstacles: 3\nx:\n")).rfind("bad.yaml:", 0), 0u);
}

TEST(Scenario, NonScalarKeysAreAConfigErrorNotACrash) {
  EXPECT_EQ(error_of("? [1, 2]\n: 3\nname: x\n").rfind("bad.yaml:1: ", 0), 0u);
  std::string text = replace(kSpecExample, "x: 5.0, y: 4.0}", "x: 5.0, y: 4.0, ? [1]: 2}");
  EXPECT_EQ(error_of(text).rfind("bad.yaml:10: ", 0), 0u) << error_of(text);
}

// Random byte edits of a valid file: each either loads or fails with a
// ConfigError naming the file; nothing else escapes (no crash, no other
// exception type).
TEST(Scenario, MutatedFilesLoadOrFailCleanly) {
  std::mt19937 rng(42);
  const std::string alphabet = "{}[]:,-?&*!|>'\"#%@ \n\t0123456789.eEabxyz_";
  int errors = 0;
  for (int i = 0; i < 3000; ++i) {
    std::string text = kSpecExample;
    int edits = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < edits; ++k) {
      size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0:
          text[at] = alphabet[rng() % alphabet.size()];
          break;
        case 1:
          text.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
        default:
          text.erase(at, 1);
          break;
      }
    }
    try {
      parse_scenario(text, "m.yaml");
    } catch (const config::ConfigError& e) {
      ++errors;
      ASSERT_EQ(std::string(e.what()).rfind("m.yaml:", 0), 0u) << e.what();
    } catch (const std::exception& e) {
      FAIL() << "escaped: " << e.what() << "\n" << text;
    }
  }
  EXPECT_GT(errors, 1000);  // most edits break something
}

TEST(Scenario, EveryShippedScenarioLoads) {
  std::filesystem::path dir = std::filesystem::path(EVADE_SOURCE_DIR) / "config" / "scenarios";
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    Scenario sc = load_scenario(e.path().string());
    EXPECT_FALSE(sc.obstacles.empty());
    EXPECT_GE(sc.duration_s, 30.0);
    ++n;
  }
  EXPECT_GE(n, 5);
}

TEST(Scenario, PaperSimIsThePaperScene) {
  Scenario sc = load_scenario(std::string(EVADE_SOURCE_DIR) + "/config/scenarios/paper_sim.yaml");
  EXPECT_DOUBLE_EQ(sc.start.x, -10.0);
  EXPECT_DOUBLE_EQ(sc.start.y, 0.0);
  EXPECT_DOUBLE_EQ(sc.start.yaw, 0.0);
  EXPECT_DOUBLE_EQ(sc.goal.x, 9.0);
  EXPECT_DOUBLE_EQ(sc.goal.y, 0.0);
  EXPECT_EQ(sc.obstacles_start, ObstaclesStart::kOnRobotMotion);
  ASSERT_EQ(sc.obstacles.size(), 8u);
  struct Expect {
    double x, y, vx, vy;
  };
  const Expect expected[8] = {{5, 4, 0, 0},           {3.7, -3.7, 0, 0},   {-8, -8, 0, 0},     {-1.2, 0.8, 0, 0},
                              {-4.5, 0.5, -1.0, 0.5}, {-10, -1.9, 0, 0.5}, {7, -0.8, -0.7, 0}, {-5, -2.8, 0, 0.9}};
  for (int i = 0; i < 8; ++i) {
    const ObstacleSpec& o = sc.obstacles[static_cast<size_t>(i)];
    EXPECT_EQ(o.shape, Shape::kCylinder);
    EXPECT_DOUBLE_EQ(o.radius, 0.25);
    EXPECT_DOUBLE_EQ(o.height, 0.5);
    EXPECT_DOUBLE_EQ(o.x, expected[i].x) << i;
    EXPECT_DOUBLE_EQ(o.y, expected[i].y) << i;
    EXPECT_DOUBLE_EQ(o.vx, expected[i].vx) << i;
    EXPECT_DOUBLE_EQ(o.vy, expected[i].vy) << i;
    EXPECT_EQ(o.motion, i < 4 ? MotionKind::kStatic : MotionKind::kConstantVelocity) << i;
  }
}

}  // namespace
}  // namespace evade::sim
