// tools/config-dump as a user runs it: every value of robot.yaml printed
// with the line it came from, and a wrong configuration refused with exit
// status 2 and one line naming file, line and key.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

const std::string kTool = std::string(EVADE_SOURCE_DIR) + "/tools/config-dump";
const std::string kRobotYaml = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";

// stdout and stderr of `cmd`, and its exit status.
std::pair<std::string, int> run(const std::string& cmd) {
  std::string out;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return {"", -1};
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int rc = pclose(p);
  return {out, WIFEXITED(rc) ? WEXITSTATUS(rc) : -1};
}

TEST(ConfigDumpTool, PrintsEveryValueWithItsLine) {
  const auto [out, rc] = run(kTool + " --config " + kRobotYaml);
  ASSERT_EQ(rc, 0) << out;
  std::ifstream in(kRobotYaml);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  // predictions_max_age_s: the line the dump names holds that key and value.
  const std::string key = "  predictions_max_age_s: 0.25  # " + kRobotYaml + ":";
  const size_t at = out.find(key);
  ASSERT_NE(at, std::string::npos) << out;
  const int line = std::stoi(out.substr(at + key.size()));
  ASSERT_GT(line, 0);
  EXPECT_NE(lines[size_t(line - 1)].find("predictions_max_age_s: 0.25"), std::string::npos) << lines[size_t(line - 1)];
  for (const char* section : {"robot:\n", "planner:\n", "predictor:\n", "lockstep:\n", "teleop:\n"})
    EXPECT_NE(("\n" + out).find(std::string("\n") + section), std::string::npos) << section;
}

// With a robot profile and a scenario the merged values name the file they
// came from (config/robot_profile.h): the profile's, the scenario's.
TEST(ConfigDumpTool, MergedValuesNameTheProfileOrScenario) {
  const std::string src = EVADE_SOURCE_DIR;
  const auto [out, rc] =
      run(kTool + " --config " + kRobotYaml + " --scenario " + src + "/config/scenarios/paper_sim.yaml");
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("  footprint_length_m: 0.46  # " + src + "/config/robots/jackal.yaml:"), std::string::npos) << out;
  EXPECT_NE(out.find("    z_m: 0.5  # " + src + "/config/scenarios/paper_sim.yaml:"), std::string::npos) << out;
  EXPECT_NE(out.find("  predictions_max_age_s: 0.25  # " + kRobotYaml + ":"), std::string::npos) << out;
}

TEST(ConfigDumpTool, AWrongValueExitsTwoNamingFileLineAndKey) {
  const std::string bad = ::testing::TempDir() + "/config_dump_bad_" + std::to_string(::getpid()) + ".yaml";
  {
    std::ifstream in(kRobotYaml);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const std::string from = "  gate_m: 0.8 ";
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, from.size(), "  gate_m: -1 ");
    std::ofstream(bad) << text;
  }
  const auto [out, rc] = run(kTool + " --config " + bad);
  std::filesystem::remove(bad);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(out.find(bad + ":"), std::string::npos) << out;
  EXPECT_NE(out.find(": key 'tracker.gate_m': must be greater than 0"), std::string::npos) << out;
}

}  // namespace
