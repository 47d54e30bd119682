// `health --once` end to end, inside a private network namespace (NETNS),
// with one real process (route) publishing HEALTH.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

std::string bin(const std::string& name) { return std::string(EVADE_BIN_DIR) + "/" + name; }
std::string source(const std::string& rel) { return std::string(EVADE_SOURCE_DIR) + "/" + rel; }

pid_t spawn(const std::vector<std::string>& args, const std::string& out_path = "") {
  pid_t pid = ::fork();
  if (pid == 0) {
    if (!out_path.empty()) {
      FILE* f = std::fopen(out_path.c_str(), "w");
      if (f) ::dup2(fileno(f), STDOUT_FILENO);
    }
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

int wait_status(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// robot.yaml with a shorter stale age, so a stopped process turns stale
// inside the listening window.
std::string config_with(const std::string& stale, const std::string& listen) {
  std::string text = slurp(source("config/robot.yaml"));
  auto replace = [&](const std::string& from, const std::string& to) {
    size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("stale_after_s: 2.5", "stale_after_s: " + stale);
  replace("once_listen_s: 3.0", "once_listen_s: " + listen);
  replace("wait_timeout_s: 10.0", "wait_timeout_s: 2.5");
  const std::string path = ::testing::TempDir() + "health_once_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

struct BoardRun {
  int status;
  std::string out;
};

BoardRun health_once(const std::string& config, const std::vector<std::string>& extra) {
  const std::string out = ::testing::TempDir() + "health_once_out_" + std::to_string(::getpid()) + ".txt";
  std::vector<std::string> args = {bin("health"), "--once", "--config", config};
  args.insert(args.end(), extra.begin(), extra.end());
  const int status = wait_status(spawn(args, out));
  return {status, slurp(out)};
}

class HealthOnce : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = config_with("1.6", "3.0");
    route_ = spawn({bin("route"), "--config", config_});
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  }
  void TearDown() override {
    ::kill(route_, SIGCONT);
    ::kill(route_, SIGTERM);
    wait_status(route_);
  }
  std::string config_;
  pid_t route_ = -1;
};

TEST_F(HealthOnce, ARunningProcessIsListedAndPasses) {
  const BoardRun r = health_once(config_, {"--expect", "route"});
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("PROCESS"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("route"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("STALE"), std::string::npos) << r.out;
}

TEST_F(HealthOnce, AnExpectedProcessThatIsNotRunningFails) {
  const BoardRun r = health_once(config_, {"--expect", "route,planner"});
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("planner"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("never heard"), std::string::npos) << r.out;
}

TEST_F(HealthOnce, AProcessThatStopsBeatingIsStale) {
  // Stopped 0.8 s into a 3 s window: its last heartbeat is at least 2.2 s
  // old when the board judges, past the 1.6 s stale age.
  const std::string out = ::testing::TempDir() + "health_stale_" + std::to_string(::getpid()) + ".txt";
  const pid_t board = spawn({bin("health"), "--once", "--config", config_}, out);
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  ::kill(route_, SIGSTOP);
  EXPECT_EQ(wait_status(board), 1);
  const std::string text = slurp(out);
  EXPECT_NE(text.find("route"), std::string::npos) << text;
  EXPECT_NE(text.find("STALE"), std::string::npos) << text;
}

// `health --wait-received PROCESS:CHANNEL` (what tools/run_scenario waits
// on before it starts the simulator): route reads ROUTE, its own included.
TEST_F(HealthOnce, WaitingForAnInputThatArrivesEndsWithZero) {
  // 0, not the timeout's 1 (wait_timeout_s 2.5 here).
  EXPECT_EQ(wait_status(spawn({bin("health"), "--wait-received", "route:ROUTE", "--config", config_})), 0);
}

TEST_F(HealthOnce, WaitingForAnInputThatNeverArrivesTimesOutWithOne) {
  // route has no ODOMETRY input, and nobody runs a planner.
  EXPECT_EQ(wait_status(spawn({bin("health"), "--wait-received", "route:ODOMETRY", "--config", config_})), 1);
  EXPECT_EQ(wait_status(spawn({bin("health"), "--wait-received", "planner:ROUTE", "--config", config_})), 1);
  // Malformed: a usage error, at once.
  EXPECT_EQ(wait_status(spawn({bin("health"), "--wait-received", "route", "--config", config_})), 2);
}

}  // namespace
