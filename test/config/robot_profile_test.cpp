// The merge rule robot.yaml <- profile <- scenario (config/robot_profile.h):
// each level overrides the one below, errors name the file and line a value
// came from, an unknown profile or a clash with the scenario's is a clear
// error; and the repository's profiles merge onto its robot.yaml.
#include "config/robot_profile.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>

namespace evade::config {
namespace {
namespace fs = std::filesystem;

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

// A folder with robot.yaml, robots/small.yaml and a scenario.
class RobotProfile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("robot_profile_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "robots");
    write("robot.yaml",
          "robot:\n"                      // 1
          "  footprint_length_m: 0.42\n"  // 2
          "  footprint_width_m: 0.31\n"   // 3
          "  max_v_mps: 1.0\n"            // 4
          "lidar:\n"                      // 5
          "  model: vlp16\n"              // 6
          "  mount: {x_m: 0.0, z_m: 0.5}\n");
    write("robots/small.yaml",
          "# a test robot\n"             // 1
          "robot:\n"                     // 2
          "  footprint_length_m: 0.6\n"  // 3
          "  footprint_width_m: 0.5\n"   // 4
          "  max_v_mps: -2\n"            // 5
          "lidar:\n"                     // 6
          "  mount:\n"                   // 7
          "    z_m: 0.8\n");             // 8
    write("scenario.yaml",
          "name: s\n"                                 // 1
          "robot:\n"                                  // 2
          "  profile: small\n"                        // 3
          "  footprint: {length: 0.7, width: abc}\n"  // 4
          "lidar: {model: rs_helios, rate_hz: 10}\n");
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

TEST_F(RobotProfile, EachLevelOverridesTheOneBelow) {
  // robot.yaml alone
  Node base = load_robot_config(path("robot.yaml"), {});
  EXPECT_DOUBLE_EQ(base.section("robot").get<double>("footprint_length_m"), 0.42);
  // <- profile: its values, robot.yaml's for the rest (lidar.model, mount.x_m)
  Node prof = load_robot_config(path("robot.yaml"), {"small", ""});
  EXPECT_DOUBLE_EQ(prof.section("robot").get<double>("footprint_length_m"), 0.6);
  EXPECT_DOUBLE_EQ(prof.section("lidar").section("mount").get<double>("z_m"), 0.8);
  EXPECT_DOUBLE_EQ(prof.section("lidar").section("mount").get<double>("x_m"), 0.0);
  EXPECT_EQ(prof.section("lidar").get<std::string>("model"), "vlp16");
  // <- scenario: its footprint length and LiDAR model over the profile's;
  // the profile comes from the scenario's robot.profile
  Node run = load_robot_config(path("robot.yaml"), {"", path("scenario.yaml")});
  EXPECT_EQ(run.provenance()->profile, "small");
  EXPECT_DOUBLE_EQ(run.section("robot").get<double>("footprint_length_m"), 0.7);
  EXPECT_EQ(run.section("lidar").get<std::string>("model"), "rs_helios");
  EXPECT_DOUBLE_EQ(run.section("lidar").section("mount").get<double>("z_m"), 0.8);
}

TEST_F(RobotProfile, ErrorsNameTheFileAndLineTheValueCameFrom) {
  Node run = load_robot_config(path("robot.yaml"), {"", path("scenario.yaml")});
  EXPECT_EQ(error_of([&] { run.section("robot").get_positive("max_v_mps"); }),
            path("robots/small.yaml") + ":5: key 'robot.max_v_mps': must be greater than 0");
  EXPECT_EQ(error_of([&] { run.section("robot").get<double>("footprint_width_m"); }),
            path("scenario.yaml") + ":4: key 'robot.footprint_width_m': expected a number, found 'abc'");
  // a value no layer replaced still names robot.yaml
  Node base = load_robot_config(path("robot.yaml"), {"small", ""});
  EXPECT_EQ(error_of([&] { base.section("lidar").get_choice("model", {"x"}); }),
            path("robot.yaml") + ":6: key 'lidar.model': 'vlp16' is not one of: x");
  EXPECT_EQ(base.section("robot").source("footprint_length_m"), path("robots/small.yaml") + ":3");
}

TEST_F(RobotProfile, UnknownProfileIsAClearError) {
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"big", ""});
            }),
            "--robot big: no robot profile 'big' (" + path("robots/big.yaml") + "; profiles: small)");
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"../robot", ""});
            }).rfind("--robot ../robot: ", 0),
            0u);
  write("named.yaml", "name: n\nrobot:\n  profile: big\n");
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"", path("named.yaml")});
            }),
            path("named.yaml") + ":3: key 'robot.profile': no robot profile 'big' (" + path("robots/big.yaml") +
                "; profiles: small)");
}

TEST_F(RobotProfile, CommandLineAgainstTheScenariosRobotIsAnError) {
  write("robots/other.yaml", "robot:\n  max_v_mps: 0.5\n");
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"other", path("scenario.yaml")});
            }),
            path("scenario.yaml") +
                ":3: key 'robot.profile': the scenario's robot is 'small' but --robot names 'other' (one robot per "
                "run: drop --robot, or give the scenario's)");
  EXPECT_NO_THROW(load_robot_config(path("robot.yaml"), {"small", path("scenario.yaml")}));
}

TEST_F(RobotProfile, AProfileOnlyNamesKeysRobotYamlHas) {
  write("robots/typo.yaml", "robot:\n  max_v_mps: 0.5\n  max_vv_mps: 2\n");
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"typo", ""});
            }),
            path("robots/typo.yaml") + ":3: key 'robot.max_vv_mps': unknown key (not in robot.yaml)");
  write("robots/section.yaml", "robt:\n  max_v_mps: 0.5\n");
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"section", ""});
            }),
            path("robots/section.yaml") + ":1: key 'robt': unknown section (a profile holds robot.yaml sections)");
  write("robots/shape.yaml", "lidar:\n  mount: 0.5\n");
  EXPECT_EQ(error_of([&] {
              load_robot_config(path("robot.yaml"), {"shape", ""});
            }),
            path("robots/shape.yaml") + ":2: key 'lidar.mount': expected a map, as in robot.yaml");
}

TEST_F(RobotProfile, FootprintLineSaysSizeProfileAndSource) {
  write("robots/small.yaml", "robot:\n  footprint_length_m: 0.93\n  footprint_width_m: 0.7\n");
  EXPECT_EQ(footprint_line(load_robot_config(path("robot.yaml"), {"small", ""})),
            "footprint 0.93 x 0.7 m, profile small, source " + path("robots/small.yaml") + ":2,3");
  EXPECT_EQ(footprint_line(load_robot_config(path("robot.yaml"), {})),
            "footprint 0.42 x 0.31 m, profile none, source " + path("robot.yaml") + ":2,3");
  write("s2.yaml", "name: s\nrobot:\n  footprint: {length: 1.0, width: 0.8}\n");
  EXPECT_EQ(footprint_line(load_robot_config(path("robot.yaml"), {"small", path("s2.yaml")})),
            "footprint 1 x 0.8 m, profile small, source " + path("s2.yaml") + ":3,3");
}

// The repository's profiles: partial robot.yaml files that merge onto it
// (every key one robot.yaml has), with the makers' footprints.
TEST(RepositoryProfiles, MergeOntoRobotYaml) {
  const std::string robot_yaml = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";
  EXPECT_EQ(profile_names(robot_yaml), (std::vector<std::string>{"jackal", "scout2"}));
  const Footprint jackal = effective_footprint(load_robot_config(robot_yaml, {"jackal", ""}));
  EXPECT_DOUBLE_EQ(jackal.length_m, 0.46);
  EXPECT_DOUBLE_EQ(jackal.width_m, 0.42);
  const Node scout = load_robot_config(robot_yaml, {"scout2", ""});
  EXPECT_DOUBLE_EQ(effective_footprint(scout).length_m, 0.93);
  EXPECT_EQ(scout.section("lidar").get<std::string>("model"), "rs_helios");
  // the scenarios that name them
  const std::string scenarios = std::string(EVADE_SOURCE_DIR) + "/config/scenarios/";
  EXPECT_EQ(load_robot_config(robot_yaml, {"", scenarios + "paper_sim.yaml"}).provenance()->profile, "jackal");
  EXPECT_EQ(load_robot_config(robot_yaml, {"", scenarios + "paper_realworld.yaml"}).provenance()->profile, "scout2");
}

}  // namespace
}  // namespace evade::config
