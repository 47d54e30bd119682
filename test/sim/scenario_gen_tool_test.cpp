// tools/scenario-gen end to end: stdout and --out give the library's bytes,
// a bad family or configuration exits 2 with one line naming the problem.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "sim/scenario_gen.h"

namespace evade::sim::gen {
namespace {

struct Ran {
  int status = -1;
  std::string out;
};

Ran run(const std::string& args) {
  Ran r;
  std::string cmd = std::string(SCENARIO_GEN_BINARY) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof(buf), p)) > 0;) r.out.append(buf, n);
  int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string read(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

const std::string kRobot = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";
const std::string kFamilies = std::string(EVADE_SOURCE_DIR) + "/config/scenario_families.yaml";

TEST(ScenarioGenTool, StdoutAndOutGiveTheLibrarysBytes) {
  RobotFacts robot = RobotFacts::from_config(config::load_robot_config(kRobot));
  FamilyParams params = FamilyParams::from_config(config::load_file(kFamilies), robot);
  std::string expected = generate("occlusion", 11, params, robot).yaml;
  std::string flags = " --config " + kRobot + " --families " + kFamilies;
  Ran r = run("--family occlusion --seed 11" + flags);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, expected);
  std::string file = (std::filesystem::temp_directory_path() / "scenario_gen_tool_test.yaml").string();
  std::filesystem::remove(file);
  r = run("--family occlusion --seed 11 --out " + file + flags);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(read(file), expected);
  std::filesystem::remove(file);
}

// --robot NAME: the scene is drawn for the profile's footprint and LiDAR
// and names the profile, so that its runs use the same robot.
TEST(ScenarioGenTool, RobotProfileSetsTheFootprintAndIsNamed) {
  const std::string flags = " --config " + kRobot + " --families " + kFamilies;
  for (const std::string family : {"crossing", "doorway"}) {
    Ran r = run("--family " + family + " --seed 2 --robot scout2" + flags);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("  profile: scout2\n  footprint: {length: 0.93, width: 0.7}"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("lidar: {model: rs_helios, rate_hz: 10.0, height: 0.55,"), std::string::npos) << r.out;
    const Scenario sc = parse_scenario(r.out, family + ".yaml");
    EXPECT_EQ(sc.profile, "scout2");
    EXPECT_DOUBLE_EQ(sc.footprint_width, 0.7);
  }
  Ran jackal = run("--family headon --seed 2 --robot jackal" + flags);
  EXPECT_EQ(jackal.status, 0) << jackal.out;
  EXPECT_NE(jackal.out.find("footprint: {length: 0.46, width: 0.42}"), std::string::npos) << jackal.out;
  Ran none = run("--family headon --seed 2 --robot nosuch" + flags);
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.out.find("scenario-gen: --robot nosuch: no robot profile 'nosuch'"), std::string::npos) << none.out;
}

TEST(ScenarioGenTool, CheckNamesTheRulesAFileBreaks) {
  std::string flags = " --config " + kRobot + " --families " + kFamilies;
  std::string good = std::string(EVADE_SOURCE_DIR) + "/config/scenarios/paper_sim.yaml";
  Ran r = run("--check " + good + flags);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out, "");
  std::string bad = (std::filesystem::temp_directory_path() / "scenario_gen_tool_bad.yaml").string();
  {
    std::ofstream f(bad);
    f << read(good) << "  - {shape: cylinder, radius: 0.3, height: 1.7, x: -9.3, y: 0.0}\n";
  }
  r = run("--check " + bad + flags);
  EXPECT_EQ(r.status, 1);
  // 0.17 m: paper_sim's robot is the jackal profile's, 0.46 m long (its front at x = -9.77)
  EXPECT_EQ(r.out, bad + ": obstacles[8]: comes 0.170 m from the robot's start footprint in the first 2.0 s\n");
  std::filesystem::remove(bad);
}

TEST(ScenarioGenTool, BadInputExitsTwoWithOneLine) {
  Ran r = run("--family stampede --seed 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out.rfind("scenario-gen: unknown family 'stampede'", 0), 0u) << r.out;
  r = run("--seed 1");
  EXPECT_EQ(r.status, 2);
  r = run("--family crossing --seed 1 --families /nonexistent/families.yaml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("/nonexistent/families.yaml"), std::string::npos) << r.out;
  r = run("--list");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.find("crossing\nheadon\n"), 0u) << r.out;
}

}  // namespace
}  // namespace evade::sim::gen
