// tools/netem-run refuses bad arguments before it touches the network
// (the live run itself is a tool, not a CI test: docs/experiments/2026-11-25-soak.md).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

const std::string kRoot = EVADE_SOURCE_DIR;

struct Result {
  int status;
  std::string out;
};

Result netem_run(const std::string& args) {
  const fs::path log = fs::temp_directory_path() / "netem_run_test.txt";
  const int st = std::system((kRoot + "/tools/netem-run " + args + " > " + log.string() + " 2>&1").c_str());
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  fs::remove(log);
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, ss.str()};
}

TEST(NetemRun, BadArgumentsAreRefusedWithTheReason) {
  const std::string out = (fs::temp_directory_path() / "netem_run_test_out").string();
  fs::remove_all(out);
  auto r = netem_run("--duration-s 5");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("netem-run --out DIR"), std::string::npos) << r.out;
  r = netem_run("--out " + out + " --loss-pct 150");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--loss-pct is at most 100"), std::string::npos) << r.out;
  r = netem_run("--out " + out + " --duration-s -3");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--duration-s takes a positive number"), std::string::npos) << r.out;
  r = netem_run("--out " + out + " --jitter-ms x");
  EXPECT_EQ(r.status, 2);
  r = netem_run("--out " + out + " --scenario /nonexistent.yaml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("no such scenario"), std::string::npos) << r.out;
  r = netem_run("--out " + out + " --frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_FALSE(fs::exists(out));  // nothing was started
}

}  // namespace
