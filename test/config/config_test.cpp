#include "config/config.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace evade::config {
namespace {

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, TypedGetters) {
  Node root = load_string("a:\n  x_m: 1.5\n  n: 3\n  on: true\n  name: hi\n  p: [1, 2]\n", "t.yaml");
  Node a = root.section("a");
  EXPECT_DOUBLE_EQ(a.get<double>("x_m"), 1.5);
  EXPECT_EQ(a.get<int>("n"), 3);
  EXPECT_TRUE(a.get<bool>("on"));
  EXPECT_EQ(a.get<std::string>("name"), "hi");
  EXPECT_EQ(a.get_doubles("p", 2), (std::vector<double>{1, 2}));
  EXPECT_NO_THROW(a.close());
}

TEST(Config, MissingKeyNamesFileLineAndKey) {
  Node root = load_string("a:\n  x_m: 1.5\n", "robot.yaml");
  EXPECT_EQ(error_of([&] { root.section("a").get<double>("y_m"); }), "robot.yaml:2: key 'a.y_m': missing");
}

TEST(Config, WrongTypeNamesFileLineAndKey) {
  Node root = load_string("a:\n  b: 1\n  x_m: fast\n", "robot.yaml");
  EXPECT_EQ(error_of([&] { root.section("a").get<double>("x_m"); }),
            "robot.yaml:3: key 'a.x_m': expected a number, found 'fast'");
  EXPECT_EQ(error_of([&] { root.section("a").get<int>("x_m"); }),
            "robot.yaml:3: key 'a.x_m': expected an integer, found 'fast'");
}

TEST(Config, UnknownKeyIsAnError) {
  Node root = load_string("a:\n  x_m: 1.5\n  x_mm: 2\n", "robot.yaml");
  Node a = root.section("a");
  a.get<double>("x_m");
  EXPECT_EQ(error_of([&] { a.close(); }), "robot.yaml:3: key 'a.x_mm': unknown key");
}

// Every program reads only its own sections: a misspelt section is caught
// when the robot configuration is loaded, by any of them.
TEST(Config, UnknownTopLevelSectionIsAnError) {
  const std::string path = ::testing::TempDir() + "/sections.yaml";
  std::ofstream(path) << "robot:\n  v_max_mps: 1.0\nplaner:\n  mode: dcbf\n";
  EXPECT_EQ(error_of([&] { load_robot_config(path); }), path + ":3: key 'planer': unknown section");
  std::ofstream(path) << "robot:\n  v_max_mps: 1.0\nplanner:\n  mode: dcbf\n";
  EXPECT_NO_THROW(load_robot_config(path));
  std::remove(path.c_str());
}

TEST(Config, TheRepositoryConfigHasEveryRobotSectionAndNoOther) {
  Node root = load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  for (const auto& s : robot_sections()) EXPECT_TRUE(root.has(s)) << s;
  EXPECT_EQ(root.keys().size(), robot_sections().size());
}

TEST(Config, NonScalarKeyIsAConfigError) {
  Node root = load_string("a:\n  x_m: 1\n  ? [1, 2]\n  : 3\n", "k.yaml");
  Node a = root.section("a");
  a.get<double>("x_m");
  EXPECT_EQ(error_of([&] { a.close(); }), "k.yaml:3: key 'a': a key must be a plain name");
  EXPECT_THROW(a.keys(), ConfigError);
}

TEST(Config, RangeAndChoice) {
  Node root = load_string("v: -1\nmode: fast\n", "r.yaml");
  EXPECT_EQ(error_of([&] { root.get_double("v", 0, 2); }), "r.yaml:1: key 'v': value -1 outside [0, 2]");
  EXPECT_EQ(error_of([&] {
              root.get_choice("mode", {"dcbf", "mpc"});
            }),
            "r.yaml:2: key 'mode': 'fast' is not one of: dcbf, mpc");
}

TEST(Config, SyntaxErrorHasLine) {
  std::string e = error_of([] { load_string("a: 1\nb: [1, 2\n", "bad.yaml"); });
  EXPECT_EQ(e.rfind("bad.yaml:", 0), 0u) << e;
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
}

TEST(Config, MissingFile) {
  EXPECT_EQ(error_of([] { load_file("/nonexistent/robot.yaml"); }),
            "/nonexistent/robot.yaml:0: key '': cannot open file");
}

// The repository's config/robot.yaml with one line replaced, loaded as a
// robot configuration; the error text, or "" when it loads.
std::string safety_error(const std::string& from, const std::string& to, const std::string& extra = "") {
  std::ifstream in(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const size_t at = text.find(from);
  if (at == std::string::npos) return "test setup: '" + from + "' not in robot.yaml";
  text.replace(at, from.size(), to);
  const std::string path = ::testing::TempDir() + "/safety.yaml";
  std::ofstream(path) << extra << text;
  std::string err = error_of([&] { load_robot_config(path); });
  std::remove(path.c_str());
  return err;
}

TEST(Safety, TheRepositoryConfigIsSafe) {
  EXPECT_EQ(safety_error("watchdog_timeout_s: 0.25", "watchdog_timeout_s: 0.25"), "");
}

TEST(Safety, AWatchdogAboveOneSecondIsRefusedWithFileLineKey) {
  const std::string err = safety_error("watchdog_timeout_s: 0.25", "watchdog_timeout_s: 1.5");
  EXPECT_NE(err.find("safety.yaml:"), std::string::npos) << err;
  EXPECT_NE(err.find("key 'base_driver.watchdog_timeout_s': must be at most 1 s"), std::string::npos) << err;
  EXPECT_EQ(safety_error("watchdog_timeout_s: 0.25", "watchdog_timeout_s: 1.0"), "");
}

TEST(Safety, APlannerPeriodNotBelowTheWatchdogIsRefused) {
  // 4 Hz = 0.25 s, the watchdog's timeout: every gap would trip it
  const std::string err = safety_error("  rate_hz: 8.0  ", "  rate_hz: 4.0  ");
  EXPECT_NE(err.find("key 'planner.rate_hz': the planner's period"), std::string::npos) << err;
  EXPECT_EQ(safety_error("  rate_hz: 8.0  ", "  rate_hz: 5.0  "), "");
}

TEST(Safety, PlanningWithoutPredictionsOnlyInATestConfig) {
  const std::string err = safety_error("require_obstacles: true", "require_obstacles: false");
  EXPECT_NE(err.find("key 'planner.require_obstacles': false"), std::string::npos) << err;
  // the line is the key's own
  std::ifstream in(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::string line;
  int n = 0, at = 0;
  while (std::getline(in, line) && !at) {
    ++n;
    if (line.find("require_obstacles:") != std::string::npos) at = n;
  }
  EXPECT_NE(err.find("safety.yaml:" + std::to_string(at) + ":"), std::string::npos) << err;
  EXPECT_EQ(safety_error("require_obstacles: true", "require_obstacles: false", "test_config: true\n"), "");
  EXPECT_NE(safety_error("require_obstacles: true", "require_obstacles: false", "test_config: false\n"), "");
}

}  // namespace
}  // namespace evade::config
