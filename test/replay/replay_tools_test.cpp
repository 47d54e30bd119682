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
  const std::string cut = kBin + "/process-replay --logs " + logs.string() + " --cut " +
                          (dir_ / "in.lcmlog").string() + " --start-s 0 --duration-s 1 --case mine --process tracker";
  EXPECT_EQ(run(cut), 2);
  EXPECT_EQ(text_of(logs / "mine" / "input.lcmlog"), "a golden case");
  EXPECT_EQ(run(cut + " --force"), 0);
  EXPECT_FALSE(evade::bus::read_log((logs / "mine" / "input.lcmlog").string()).empty());
}

}  // namespace
