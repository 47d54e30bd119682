// The base_driver binary end to end, inside a private network namespace
// (NETNS), against a pseudo-terminal that plays the Scout: device missing
// at start, commands on the wire, ODOMETRY and BASE_STATUS on LCM, a
// hang-up (the process must survive libserial's hang-up abort), and a
// reconnect at the same path. Waits are generous bounds, never assertions
// on timing.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <sstream>
#include <thread>
#include <tuple>

#include "../bus/test_signer.h"
#include "base/scout_protocol.h"
#include "bus/core.h"
#include "bus/log.h"
#include "evade/base_status_t.hpp"
#include "evade/cmd_vel_t.hpp"
#include "evade/health_t.hpp"
#include "evade/odometry_t.hpp"
#include "pty_peer.h"

namespace evade::base {
namespace {

using testing::PtyPeer;
using Clock = std::chrono::steady_clock;

class Listener {
 public:
  void on_odometry(const lcm::ReceiveBuffer*, const std::string&, const evade::odometry_t* m) {
    odometry.push_back(*m);
  }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const evade::base_status_t* m) { status.push_back(*m); }
  void on_health(const lcm::ReceiveBuffer*, const std::string&, const evade::health_t* m) {
    if (m->name != "base_driver") return;
    for (const auto& c : m->counters) counters[c.name] = c.value;
  }
  std::map<std::string, int64_t> counters;  // latest base_driver HEALTH counters
  std::vector<evade::odometry_t> odometry;
  std::vector<evade::base_status_t> status;
};

class BaseDriverProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = tmp_.path;
    path_ = dir_ + "/scout";
    ASSERT_TRUE(lcm_.good());
    lcm_.subscribe("ODOMETRY", &Listener::on_odometry, &listener_);
    lcm_.subscribe("BASE_STATUS", &Listener::on_status, &listener_);
    lcm_.subscribe("HEALTH", &Listener::on_health, &listener_);
  }
  void TearDown() override {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  testing::TempDir tmp_;
  void start() {
    pid_ = ::fork();
    ASSERT_GE(pid_, 0);
    if (pid_ == 0) {
      std::string err = dir_ + "/stderr.log";
      FILE* f = std::freopen(err.c_str(), "w", stderr);
      (void)f;
      std::string bin = std::string(EVADE_BIN_DIR) + "/base_driver";
      std::string config = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";
      ::execl(bin.c_str(), bin.c_str(), "--config", config.c_str(), "--device", path_.c_str(), "--initial-pose",
              "1,2,0", static_cast<char*>(nullptr));
      std::_Exit(127);
    }
  }
  bool alive() { return ::waitpid(pid_, nullptr, WNOHANG) == 0; }
  std::string log() {
    std::ifstream in(dir_ + "/stderr.log");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  // Runs LCM and the pty for `ms`: collects command frames, optionally
  // sends CMD_VEL and motion-status frames every 20 ms.
  void pump(PtyPeer* base, int ms, double cmd_v = NAN, int16_t status_mm_s = INT16_MIN) {
    const auto end = Clock::now() + std::chrono::milliseconds(ms);
    auto next_send = Clock::now();
    while (Clock::now() < end) {
      if (Clock::now() >= next_send) {
        next_send += std::chrono::milliseconds(20);
        if (!std::isnan(cmd_v)) {
          evade::cmd_vel_t c{};
          c.utime =
              std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
                  .count();  // base_driver ignores late commands
          c.v = cmd_v;
          const auto data = bus::testing::signed_bytes(planner_, "CMD_VEL", c, c.utime);  // unsigned: ignored
          lcm_.publish("CMD_VEL", data.data(), static_cast<unsigned>(data.size()));
        }
        if (base && status_mm_s != INT16_MIN) base->write(encode(MotionStatus{status_mm_s, 0}, 0));
      }
      lcm_.handleTimeout(5);
      if (base) {
        auto bytes = base->drain(0);
        parser_.feed(bytes.data(), bytes.size(), [&](const Frame& f) {
          MotionCommand mc;
          if (from_frame(f, &mc)) commands_.push_back(mc);
        });
      }
    }
  }

  std::string dir_, path_;
  pid_t pid_ = -1;
  lcm::LCM lcm_;  // $LCM_DEFAULT_URL, set by tools/netns-run
  Listener listener_;
  StreamParser parser_;
  std::vector<MotionCommand> commands_;
  bus::HmacAuth planner_ = bus::testing::test_signer("planner");
};

TEST_F(BaseDriverProcess, SurvivesHangUpAndReconnects) {
  start();
  pump(nullptr, 400);  // no device yet
  ASSERT_TRUE(alive());

  auto base = std::make_unique<PtyPeer>(path_);
  // Commands flow; with no CMD_VEL the watchdog holds them at zero.
  for (int i = 0; i < 100 && commands_.size() < 5; ++i) pump(base.get(), 50);
  ASSERT_GE(commands_.size(), 5u);
  for (const auto& c : commands_) EXPECT_EQ(c.linear_percent, 0);

  // A planner sends 0.3 m/s: the commands ramp up toward 20 % and never exceed it.
  commands_.clear();
  pump(base.get(), 600, 0.3, 1000);
  ASSERT_FALSE(commands_.empty());
  int8_t highest = 0;
  for (const auto& c : commands_) highest = std::max(highest, c.linear_percent);
  EXPECT_GT(highest, 0);
  EXPECT_LE(highest, linear_percent(0.3));
  // Motion-status frames became ODOMETRY from the initial pose (1, 2, 0).
  ASSERT_FALSE(listener_.odometry.empty());
  EXPECT_DOUBLE_EQ(listener_.odometry.front().x, 1.0);
  EXPECT_DOUBLE_EQ(listener_.odometry.front().y, 2.0);
  EXPECT_DOUBLE_EQ(listener_.odometry.back().v, 1.0);
  EXPECT_GT(listener_.odometry.back().x, 1.0);
  ASSERT_FALSE(listener_.status.empty());
  EXPECT_TRUE(listener_.status.back().link_ok);

  // The simulator goes away: master closed, link dangling.
  base.reset();
  pump(nullptr, 500);
  ASSERT_TRUE(alive()) << log();
  ASSERT_FALSE(listener_.status.empty());
  EXPECT_FALSE(listener_.status.back().link_ok);
  EXPECT_DOUBLE_EQ(listener_.odometry.back().v, 0.0);  // considered stopped

  // ... and comes back on a new pty at the same path.
  base = std::make_unique<PtyPeer>(path_);
  commands_.clear();
  parser_.reset();
  for (int i = 0; i < 100 && commands_.size() < 5; ++i) pump(base.get(), 50);
  EXPECT_GE(commands_.size(), 5u);
  pump(base.get(), 200, NAN, 0);
  EXPECT_TRUE(listener_.status.back().link_ok);
  // HEALTH (1 Hz) tells the story: open failures, one leaked libserial
  // port (its Close() threw after the hang-up), frames parsed.
  for (int i = 0; i < 30 && listener_.counters["serial_ports_leaked"] < 1; ++i) pump(base.get(), 100, NAN, 0);
  EXPECT_EQ(listener_.counters["serial_ports_leaked"], 1);
  EXPECT_GE(listener_.counters["serial_open_failures"], 1);
  EXPECT_GE(listener_.counters["link_lost"], 1);
  EXPECT_GT(listener_.counters["motion_status_frames"], 0);

  ASSERT_EQ(::kill(pid_, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid_, &status, 0), pid_);
  pid_ = -1;
  EXPECT_TRUE(WIFEXITED(status)) << log();
  EXPECT_EQ(WEXITSTATUS(status), 0);
  const std::string text = log();
  EXPECT_NE(text.find("cannot open " + path_ + ": No such file or directory"), std::string::npos) << text;
  EXPECT_NE(text.find("hang-up"), std::string::npos) << text;
  EXPECT_NE(text.find("opened " + path_), std::string::npos) << text;
}

// Issue 20: killed while driving, the last frame on the wire is zero speed.
TEST_F(BaseDriverProcess, SigtermWhileDrivingSendsZeroSpeedLast) {
  start();
  auto base = std::make_unique<PtyPeer>(path_);
  for (int i = 0; i < 100 && commands_.size() < 5; ++i) pump(base.get(), 50);
  pump(base.get(), 800, 0.6, 600);  // driving: commands ramped up
  ASSERT_FALSE(commands_.empty());
  ASSERT_GT(commands_.back().linear_percent, 0) << log();
  ASSERT_EQ(::kill(pid_, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid_, &status, 0), pid_);
  pid_ = -1;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log();
  pump(base.get(), 100);  // what was written before the port closed
  ASSERT_FALSE(commands_.empty());
  EXPECT_EQ(commands_.back().linear_percent, 0) << log();
  EXPECT_EQ(commands_.back().angular_percent, 0);
}

TEST_F(BaseDriverProcess, ReplayNeverOverwritesALog) {
  std::vector<bus::LogEvent> in;
  evade::cmd_vel_t c{};
  c.utime = 1'700'000'000'000'000;
  in.push_back(bus::LogEvent{c.utime, "CMD_VEL", bus::encode(c)});
  bus::write_log(dir_ + "/in.lcmlog", in);
  const std::string bin = std::string(EVADE_BIN_DIR) + "/base_driver --replay " + dir_ + "/in.lcmlog";
  // onto its own input: refused, even with --force; the input intact
  int rc = std::system((bin + " --replay-out " + dir_ + "/in.lcmlog --force 2>/dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_EQ(bus::read_log(dir_ + "/in.lcmlog").size(), 1u);
  // onto an existing file: refused without --force
  std::ofstream(dir_ + "/old.lcmlog") << "precious";
  rc = std::system((bin + " --replay-out " + dir_ + "/old.lcmlog 2>/dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  std::ifstream old(dir_ + "/old.lcmlog");
  std::string text;
  old >> text;
  EXPECT_EQ(text, "precious");
  rc = std::system((bin + " --replay-out " + dir_ + "/old.lcmlog --force 2>/dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 0);
}

TEST_F(BaseDriverProcess, BadConfigExitsWithStatus2) {
  std::ofstream(dir_ + "/bad.yaml") << "robot: {}\nbase_driver: {}\n";
  std::string cmd = std::string(EVADE_BIN_DIR) + "/base_driver --config " + dir_ + "/bad.yaml 2>/dev/null";
  int rc = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(rc));
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  cmd = std::string(EVADE_BIN_DIR) + "/base_driver --initial-pose 1,2 2>/dev/null";
  rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
}

// Issue 20: tools/estop's signed stop wins over a planner still sending
// CMD_VEL at 50 Hz, until estop --release.
TEST_F(BaseDriverProcess, EstopToolStopsTheBaseWhileCommandsKeepComing) {
  start();
  auto base = std::make_unique<PtyPeer>(path_);
  for (int i = 0; i < 100 && commands_.size() < 5; ++i) pump(base.get(), 50);
  pump(base.get(), 800, 0.6, 600);
  ASSERT_GT(commands_.back().linear_percent, 0) << log();
  auto tool = [&](const std::string& args) {
    const std::string config = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";
    return std::string(EVADE_BIN_DIR) + "/estop --config " + config + " " + args + " 2>>" + dir_ + "/estop.log";
  };
  pid_t estop = ::fork();
  ASSERT_GE(estop, 0);
  if (estop == 0) {
    ::execl("/bin/sh", "sh", "-c", tool("--reason test").c_str(), static_cast<char*>(nullptr));
    std::_Exit(127);
  }
  pump(base.get(), 1000, 0.6, 600);  // the planner goes on meanwhile
  int status = 0;
  ASSERT_EQ(::waitpid(estop, &status, 0), estop);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  commands_.clear();
  pump(base.get(), 500, 0.6, 0);
  ASSERT_GE(commands_.size(), 10u);
  for (const auto& c : commands_) EXPECT_EQ(c.linear_percent, 0);
  ASSERT_FALSE(listener_.status.empty());
  EXPECT_TRUE(listener_.status.back().estop_engaged);
  // Released: the planner's commands drive again.
  ASSERT_EQ(std::system(tool("--release").c_str()), 0);
  commands_.clear();
  pump(base.get(), 800, 0.6, 600);
  ASSERT_FALSE(commands_.empty());
  EXPECT_GT(commands_.back().linear_percent, 0) << log();
  EXPECT_FALSE(listener_.status.back().estop_engaged);
  for (int i = 0; i < 30 && listener_.counters["cmd_vel_during_estop"] < 1; ++i) pump(base.get(), 100, 0.6, 600);
  EXPECT_GT(listener_.counters["cmd_vel_during_estop"], 10);
}

// Issue 20: the key must exist and be the owner's alone.
TEST_F(BaseDriverProcess, AMissingOrExposedKeyExitsWithStatus2AndSaysWhy) {
  auto run_with_key = [&](const std::string& key) {
    const std::string cmd = "EVADE_BUS_KEY=" + key + " " + std::string(EVADE_BIN_DIR) + "/base_driver --device " +
                            path_ + " 2>" + dir_ + "/key.err";
    const int rc = std::system(cmd.c_str());
    std::ifstream in(dir_ + "/key.err");
    std::stringstream ss;
    ss << in.rdbuf();
    return std::make_pair(WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str());
  };
  auto [rc, err] = run_with_key(dir_ + "/missing.key");
  EXPECT_EQ(rc, 2);
  EXPECT_NE(err.find("base_driver: bus key: no key file " + dir_ + "/missing.key"), std::string::npos) << err;
  std::ofstream(dir_ + "/open.key") << std::string(64, 'c') << "\n";
  ASSERT_EQ(::chmod((dir_ + "/open.key").c_str(), 0644), 0);
  std::tie(rc, err) = run_with_key(dir_ + "/open.key");
  EXPECT_EQ(rc, 2);
  EXPECT_NE(err.find("accessible to group or others (mode 644)"), std::string::npos) << err;
}

TEST_F(BaseDriverProcess, ReplayOfCmdVelIsDeterministic) {
  // A log with CMD_VEL at 50 Hz for 0.2 s, then none: the replayed
  // BASE_STATUS shows the watchdog clear, then tripped 0.25 s after the last
  // command; two replays give identical logs.
  std::vector<bus::LogEvent> in;
  const int64_t t0 = 1'700'000'000'000'000;
  for (int i = 0; i <= 10; ++i) {
    evade::cmd_vel_t c{};
    c.utime = t0 + i * 20'000;
    c.v = 0.4;
    in.push_back(bus::LogEvent{c.utime, "CMD_VEL", bus::testing::signed_bytes(planner_, "CMD_VEL", c, c.utime)});
  }
  // Other traffic keeps the log's clock going (the core does not read it).
  for (int i = 1; i <= 40; ++i) in.push_back(bus::LogEvent{t0 + 200'000 + i * 20'000, "OTHER", {1, 2, 3}});
  bus::write_log(dir_ + "/in.lcmlog", in);
  std::vector<std::vector<bus::LogEvent>> outs;
  for (int run = 0; run < 2; ++run) {
    const std::string out = dir_ + "/out" + std::to_string(run) + ".lcmlog";
    const std::string cmd = std::string(EVADE_BIN_DIR) + "/base_driver --replay " + dir_ + "/in.lcmlog --replay-out " +
                            out + " 2>/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    outs.push_back(bus::read_log(out));
  }
  ASSERT_EQ(outs[0].size(), outs[1].size());
  for (size_t i = 0; i < outs[0].size(); ++i) EXPECT_EQ(outs[0][i].data, outs[1][i].data) << i;
  bool saw_clear = false;
  int64_t tripped_at = -1;
  for (const auto& e : outs[0]) {
    if (e.channel != "BASE_STATUS") continue;
    evade::base_status_t s;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &s));
    if (!s.watchdog_tripped && s.utime <= t0 + 200'000) saw_clear = true;
    if (saw_clear && s.watchdog_tripped && tripped_at < 0) tripped_at = s.utime;
    EXPECT_FALSE(s.link_ok);  // no serial port in a replay
  }
  EXPECT_TRUE(saw_clear);
  // Last command at t0 + 0.2 s: tripped at the first 50 Hz tick more than
  // 0.25 s later.
  EXPECT_EQ(tripped_at, t0 + 460'000);
}

}  // namespace
}  // namespace evade::base
