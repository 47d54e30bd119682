// Tools never destroy logs (issue 20): a process's --replay-out onto its
// own input or onto an existing file, and process-replay --cut onto an
// existing case, are refused without --force (the input never).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bus/log.h"

namespace fs = std::filesystem;

namespace {

const std::string kBin = EVADE_BIN_DIR;
const std::string kCase = std::string(EVADE_SOURCE_DIR) + "/logs/paper_sim_crossing/input.lcmlog";

int run(const std::string& cmd) {
  const int rc = std::system((cmd + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class ReplayTools : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("replay_tools_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(kCase, dir_ / "in.lcmlog");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ReplayTools, ReplayOutOntoItsOwnInputIsRefusedEvenWithForce) {
  const auto before = fs::file_size(dir_ / "in.lcmlog");
  const std::string in = (dir_ / "in.lcmlog").string();
  EXPECT_EQ(run(kBin + "/tracker --replay " + in + " --replay-out " + in), 2);
  EXPECT_EQ(run(kBin + "/tracker --replay " + in + " --replay-out " + in + " --force"), 2);
  EXPECT_EQ(fs::file_size(dir_ / "in.lcmlog"), before);
  EXPECT_EQ(evade::bus::read_log(in).size(), evade::bus::read_log(kCase).size());
}

TEST_F(ReplayTools, ReplayOutOntoAnExistingFileNeedsForce) {
  const std::string in = (dir_ / "in.lcmlog").string(), out = (dir_ / "out.lcmlog").string();
  std::ofstream(out) << "an earlier run";
  EXPECT_EQ(run(kBin + "/tracker --replay " + in + " --replay-out " + out), 2);
  EXPECT_EQ(text_of(out), "an earlier run");
  EXPECT_EQ(run(kBin + "/tracker --replay " + in + " --replay-out " + out + " --force"), 0);
  EXPECT_FALSE(evade::bus::read_log(out).empty());
  // a new file needs nothing
  EXPECT_EQ(run(kBin + "/tracker --replay " + in + " --replay-out " + (dir_ / "new.lcmlog").string()), 0);
}

TEST_F(ReplayTools, CutOntoAnExistingCaseNeedsForce) {
  const fs::path logs = dir_ / "logs";
  fs::create_directories(logs / "mine" / "refs");
  std::ofstream(logs / "mine" / "input.lcmlog") << "a golden case";
  const std::string cut = kBin + "/process-replay --logs " + logs.string() + " --cut " + (dir_ / "in.lcmlog").string() +
                          " --start-s 0 --duration-s 1 --case mine --process tracker";
  EXPECT_EQ(run(cut), 2);
  EXPECT_EQ(text_of(logs / "mine" / "input.lcmlog"), "a golden case");
  EXPECT_EQ(run(cut + " --force"), 0);
  EXPECT_FALSE(evade::bus::read_log((logs / "mine" / "input.lcmlog").string()).empty());
}

}  // namespace

#include "bus/core.h"
#include "evade/sim_truth_t.hpp"

namespace {

// log-migrate sim-truth-returns: a SIM_TRUTH without lidar_returns (the
// layout before issue 23) gets the current type with -1 per obstacle; a
// current one is left alone; bytes of neither layout stop it, the log untouched.
TEST_F(ReplayTools, LogMigrateAddsUnknownLidarReturnsToOldSimTruth) {
  evade::sim_truth_t t{};
  t.utime = 42;
  t.scenario = "old";
  t.obstacles.resize(2);
  t.obstacles[0].shape = "cylinder";
  t.obstacles[1].shape = "box";
  t.obstacles[1].x = 3.5;
  t.num_obstacles = 2;
  t.lidar_returns = {7, 9};
  std::vector<uint8_t> current = evade::bus::encode(t);
  std::vector<uint8_t> old(current.begin(), current.end() - 8);  // without the two int32
  old[0] ^= 0x5a;                                                // another fingerprint
  const fs::path in = dir_ / "old.lcmlog", out = dir_ / "migrated.lcmlog";
  evade::bus::write_log(in.string(), {{1, "SIM_TRUTH", old}, {2, "SIM_TRUTH", current}});
  ASSERT_EQ(run(kBin + "/log-migrate sim-truth-returns " + in.string() + " " + out.string()), 0);
  auto events = evade::bus::read_log(out.string());
  ASSERT_EQ(events.size(), 2u);
  evade::sim_truth_t a, b;
  ASSERT_TRUE(evade::bus::decode(events[0].data.data(), events[0].data.size(), &a));
  ASSERT_TRUE(evade::bus::decode(events[1].data.data(), events[1].data.size(), &b));
  EXPECT_EQ(a.lidar_returns, std::vector<int32_t>({-1, -1}));
  EXPECT_DOUBLE_EQ(a.obstacles[1].x, 3.5);
  EXPECT_EQ(a.scenario, "old");
  EXPECT_EQ(b.lidar_returns, std::vector<int32_t>({7, 9}));
  // Garbage on the channel: exit 1, no output written.
  evade::bus::write_log(in.string(), {{1, "SIM_TRUTH", std::vector<uint8_t>(old.begin(), old.end() - 3)}});
  EXPECT_EQ(run(kBin + "/log-migrate sim-truth-returns " + in.string() + " " + (dir_ / "bad.lcmlog").string()), 1);
  EXPECT_FALSE(fs::exists(dir_ / "bad.lcmlog"));
}

}  // namespace
