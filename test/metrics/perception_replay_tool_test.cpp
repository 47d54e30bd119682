// tools/perception-replay on the golden log: it runs the tracker as the
// tracker process does (its OBSTACLES equal the tracker's golden
// reference), and it scores the replaced log as perception-metrics does.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bus/log.h"

namespace {

const std::string kGolden = std::string(EVADE_SOURCE_DIR) + "/logs/paper_sim_crossing/";

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<evade::bus::LogEvent> channel(const std::vector<evade::bus::LogEvent>& log, const std::string& name) {
  std::vector<evade::bus::LogEvent> out;
  for (const auto& e : log)
    if (e.channel == name) out.push_back(e);
  return out;
}

int run(const std::string& cmd) { return std::system((cmd + " > /dev/null 2>&1").c_str()); }

TEST(PerceptionReplayTool, RetracksTheGoldenLogAsTheTrackerProcessDoes) {
  const std::string dir = ::testing::TempDir();
  const std::string replaced = dir + "perception_replay.lcmlog", json = dir + "perception_replay.json";
  ASSERT_EQ(
      run(std::string(PERCEPTION_REPLAY_BIN) + " " + kGolden + "input.lcmlog --log-out " + replaced + " --out " + json),
      0);
  const auto got = channel(evade::bus::read_log(replaced), "OBSTACLES");
  const auto want = channel(evade::bus::read_log(kGolden + "refs/tracker.lcmlog"), "OBSTACLES");
  ASSERT_EQ(got.size(), want.size());
  ASSERT_FALSE(got.empty());
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].timestamp, want[i].timestamp) << i;
    EXPECT_EQ(got[i].data, want[i].data) << i;
  }
  // The input's own OBSTACLE_PREDICTIONS are gone: one list per OBSTACLES,
  // made from the replayed ones.
  EXPECT_EQ(channel(evade::bus::read_log(replaced), "OBSTACLE_PREDICTIONS").size(), got.size());

  const std::string scored = dir + "perception_replay_scored.json";
  ASSERT_EQ(run(std::string(PERCEPTION_METRICS_BIN) + " " + replaced + " --out " + scored), 0);
  EXPECT_FALSE(slurp(json).empty());
  EXPECT_EQ(slurp(json), slurp(scored));
}

TEST(PerceptionReplayTool, RefusesAMissingLogAndABadConfiguration) {
  EXPECT_NE(run(std::string(PERCEPTION_REPLAY_BIN) + " /nonexistent.lcmlog"), 0);
  const std::string bad = ::testing::TempDir() + "perception_replay_bad.yaml";
  std::ofstream(bad) << "tracker: [\n";
  const int rc = run(std::string(PERCEPTION_REPLAY_BIN) + " " + kGolden + "input.lcmlog --config " + bad);
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
}

}  // namespace
