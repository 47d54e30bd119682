// The main job as a test: the paper's scenario, run by tools/run_scenario
// exactly as the README's main command does (simulator, every process,
// lcm-logger), must reach the goal without touching an obstacle, and leave
// its log, metrics and picture.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

TEST(Scenario, PaperSceneInEvadeModeReachesTheGoalWithoutCollision) {
  const std::string src = EVADE_SOURCE_DIR;
  const std::string out = ::testing::TempDir() + "/scenario_paper_sim";
  std::filesystem::remove_all(out);
  const std::string cmd = src + "/tools/run_scenario " + src + "/config/scenarios/paper_sim.yaml --out " + out +
                          " --mode evade --quiet > " + out + ".log 2>&1";
  std::filesystem::create_directories(out);
  const int status = std::system(cmd.c_str());
  const std::string metrics = slurp(out + "/metrics.json");
  std::printf("%s", metrics.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(out + ".log") << metrics;
  EXPECT_NE(metrics.find("\"reached_goal\": true"), std::string::npos);
  EXPECT_NE(metrics.find("\"collided\": false"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(out + "/run.lcmlog"));
  EXPECT_GT(std::filesystem::file_size(out + "/trajectory.png"), 10'000u);
}

}  // namespace
