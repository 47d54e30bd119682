// The metrics tool's contract (docs/SPEC.md "Metrics"): the keys of
// metrics.json, --no-reaction, and a strict configuration.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace {

const std::string kSource = EVADE_SOURCE_DIR;
const std::string kLog = kSource + "/logs/paper_sim_crossing/input.lcmlog";

struct Result {
  int status;
  std::string out;
};

// ctest runs each test as a process of its own, side by side: the output
// file is named after the test, so that two never share one.
Result run(const std::string& args) {
  const std::string path = ::testing::TempDir() + "/metrics_tool_" +
                           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".out";
  const std::string cmd = std::string(METRICS_BIN) + " " + args + " > " + path + " 2>&1";
  const int st = std::system(cmd.c_str());
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  std::remove(path.c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, ss.str()};
}

TEST(MetricsTool, WritesEveryKeyOfTheContract) {
  const auto r = run(kLog + " --config " + kSource + "/config/robot.yaml");
  ASSERT_EQ(r.status, 0) << r.out;
  for (const char* key : {"reached_goal",
                          "collided",
                          "at_fault",
                          "success",
                          "timed_out",
                          "collisions_at_fault",
                          "collisions_not_at_fault",
                          "contacts",
                          "min_dist_m",
                          "time_to_goal_s",
                          "reaction_time_s",
                          "reaction_missed",
                          "reactions",
                          "replay_plans_compared",
                          "replay_plans_differing",
                          "replay_max_plan_diff_m",
                          "speed_var",
                          "path_length_m",
                          "planner_solve_ms_p50",
                          "planner_solve_ms_p99",
                          "planner_cycle_ms_p99",
                          "solver_failures"})
    EXPECT_NE(r.out.find(std::string("\"") + key + "\": "), std::string::npos) << key << "\n" << r.out;
  // the golden window: a head-on mover is reacted to
  EXPECT_EQ(r.out.find("\"reaction_time_s\": null"), std::string::npos) << r.out;
}

TEST(MetricsTool, NoReactionSkipsTheReplay) {
  const auto r = run(kLog + " --config " + kSource + "/config/robot.yaml --no-reaction");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("\"reaction_time_s\": null"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"reaction_missed\": null"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"reactions\": null"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("replay_plans_compared"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"min_dist_m\": "), std::string::npos) << r.out;
}

TEST(MetricsTool, AMissingMetricsKeyIsAnErrorNamingIt) {
  std::ifstream f(kSource + "/config/robot.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string text = ss.str();
  const auto pos = text.find("  react_plan_diff_m:");
  ASSERT_NE(pos, std::string::npos);
  text.erase(pos, text.find('\n', pos) + 1 - pos);
  const std::string cfg = ::testing::TempDir() + "/metrics_tool_test.yaml";
  std::ofstream(cfg) << text;
  const auto r = run(kLog + " --config " + cfg);
  std::remove(cfg.c_str());
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("metrics.react_plan_diff_m"), std::string::npos) << r.out;
}

}  // namespace
