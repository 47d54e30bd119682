// tools/launch --dry-run: the recording folder (effective configuration,
// scenario, git describe, window commands) and the logger's channels,
// without starting anything.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "config/config.h"

namespace {

namespace fs = std::filesystem;
const std::string kSrc = EVADE_SOURCE_DIR;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs the launcher; returns the one folder it made under `logdir`.
fs::path dry_run(const std::string& logdir, const std::string& args, const std::string& env = "") {
  fs::remove_all(logdir);
  const std::string cmd = env + " " + kSrc + "/tools/launch " + args + " --dry-run > " + logdir + ".out 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << cmd << "\n" << slurp(logdir + ".out");
  std::vector<fs::path> runs;
  if (fs::exists(logdir))
    for (const auto& e : fs::directory_iterator(logdir)) runs.push_back(e.path());
  EXPECT_EQ(runs.size(), 1u);
  return runs.empty() ? fs::path() : runs[0];
}

std::string temp(const std::string& stem) { return ::testing::TempDir() + stem + "_" + std::to_string(::getpid()); }

TEST(Launch, RecordsTheEffectiveConfigurationAndSourceVersionBesideTheLog) {
  // A scenario whose LiDAR sits higher than robot.yaml's, so the effective
  // configuration differs from the file the launcher was given.
  std::string scenario = slurp(kSrc + "/config/scenarios/paper_sim.yaml");
  const std::string from = "height: 0.5, range_noise_std";
  ASSERT_NE(scenario.find(from), std::string::npos);
  scenario.replace(scenario.find(from), from.size(), "height: 0.7, range_noise_std");
  const std::string scenario_path = temp("launch_scenario") + ".yaml";
  std::ofstream(scenario_path) << scenario;

  const std::string logdir = temp("launch_logs");
  const fs::path run = dry_run(logdir, "--sim " + scenario_path + " --log " + logdir);
  ASSERT_FALSE(run.empty());
  const auto cfg = evade::config::load_robot_config((run / "robot.yaml").string());
  EXPECT_DOUBLE_EQ(cfg.section("lidar").section("mount").get<double>("z_m"), 0.7);
  EXPECT_EQ(slurp(run / "scenario.yaml"), scenario);
  const std::string describe = slurp(run / "git-describe.txt");
  EXPECT_FALSE(describe.empty());
  EXPECT_EQ(describe.find("not a git checkout"), std::string::npos) << describe;

  const std::string windows = slurp(run / "launch.txt");
  std::istringstream lines(windows);
  int processes = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("logger:", 0) == 0) {
      EXPECT_NE(line.find("--invert-channels --channel=LIDAR_POINTS"), std::string::npos) << line;
      EXPECT_NE(line.find((run / "run.lcmlog").string()), std::string::npos) << line;
    } else {
      EXPECT_NE(line.find("--config " + (run / "robot.yaml").string()), std::string::npos) << line;
      ++processes;
    }
  }
  EXPECT_EQ(processes, 9);  // sim, route, 6 processes, health
  EXPECT_NE(windows.find("health:"), std::string::npos);
}

TEST(Launch, KeepsTheCloudsOnlyWhenAskedAndHonoursEvadeLogDir) {
  const std::string logdir = temp("launch_env_logs");
  const fs::path run = dry_run(logdir, "--log-points", "EVADE_LOG_DIR=" + logdir);
  ASSERT_FALSE(run.empty());
  const std::string windows = slurp(run / "launch.txt");
  EXPECT_EQ(windows.find("--invert-channels"), std::string::npos) << windows;
  EXPECT_EQ(slurp(run / "robot.yaml"), slurp(kSrc + "/config/robot.yaml"));  // no scenario: the file as given
  EXPECT_FALSE(fs::exists(run / "scenario.yaml"));
}

}  // namespace
