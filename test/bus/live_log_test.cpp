// Two processes exchange messages over real LCM udpm (inside the test's
// private network namespace), recorded by the real lcm-logger; lcmlog-export
// reproduces them exactly; the same core run by the log adapter over that
// log yields identical outputs twice, equal to what it published live.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "bus/live_bus.h"
#include "bus/log.h"
#include "bus/log_replay.h"
#include "echo_core.h"

namespace evade::bus {
namespace {

pid_t spawn(const std::vector<std::string>& args) {
  pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execvp(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int stop(pid_t pid, int sig) {
  kill(pid, sig);
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

std::string run_capture(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

// A core that records every CMD_VEL it hears.
class Listener : public Core {
 public:
  Listener() : Core("listener") {
    subscribe<evade::cmd_vel_t>("ECHO_OUT", [this](const evade::cmd_vel_t& c) { heard.push_back(c); });
  }
  std::vector<evade::cmd_vel_t> heard;
};

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

constexpr int kCount = 200;

// Until the echo process answers, it is not listening yet. Then
// lcm-logger subscribes too; meanwhile the echoes of the other probes
// (sent before the first answer came back) are taken off the socket.
void handshake(LiveBus& bus, Listener& listener) {
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  int64_t probe = -1;
  while (listener.heard.empty() && std::chrono::steady_clock::now() < deadline) {
    evade::odometry_t o{};
    o.utime = probe--;
    auto bytes = encode(o);
    bus.publish("ECHO_IN", 0, bytes);
    bus.spin_once(50);
  }
  ASSERT_FALSE(listener.heard.empty()) << "bus_echo never answered";
  const auto settle = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
  while (std::chrono::steady_clock::now() < settle) bus.spin_once(10);
  listener.heard.clear();
}

std::vector<evade::odometry_t> odometry_series() {
  std::vector<evade::odometry_t> sent;
  for (int i = 0; i < kCount; ++i) {
    evade::odometry_t o{};
    o.utime = 1'000'000 + i;
    o.x = 0.1 * i;
    o.y = -1.0 / (i + 1);
    o.yaw = 0.001 * i;
    o.v = 0.5 + 1e-7 * i;
    o.omega = -0.25;
    sent.push_back(o);
  }
  return sent;
}

// Publishes `sent` to the echo process; every reply comes back in order.
void send_and_hear_echoes(LiveBus& bus, Listener& listener, const std::vector<evade::odometry_t>& sent) {
  for (const auto& o : sent) {
    bus.publish("ECHO_IN", 0, encode(o));
    bus.spin_once(0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  // a probe's echo later still (a loaded machine) is not one of these
  auto drop_probe_echoes = [&] {
    listener.heard.erase(std::remove_if(listener.heard.begin(), listener.heard.end(),
                                        [](const evade::cmd_vel_t& c) { return c.utime < 0; }),
                         listener.heard.end());
  };
  while (listener.heard.size() < sent.size() && std::chrono::steady_clock::now() < deadline) {
    bus.spin_once(50);
    drop_probe_echoes();
  }
  ASSERT_EQ(listener.heard.size(), sent.size());
  for (size_t i = 0; i < sent.size(); ++i) {
    EXPECT_EQ(listener.heard[i].utime, sent[i].utime);
    EXPECT_EQ(listener.heard[i].v, 2.0 * sent[i].v);
  }
}

// lcmlog-export reproduces every message exactly.
void expect_exported(const std::string& json, const std::vector<evade::odometry_t>& sent) {
  for (size_t i = 0; i < sent.size(); ++i) {
    const auto& o = sent[i];
    std::string msg = "\"type\":\"odometry_t\",\"msg\":{\"utime\":" + std::to_string(o.utime) +
                      ",\"x\":" + fmt("%.17g", o.x) + ",\"y\":" + fmt("%.17g", o.y) +
                      ",\"yaw\":" + fmt("%.17g", o.yaw) + ",\"v\":" + fmt("%.17g", o.v) +
                      ",\"omega\":" + fmt("%.17g", o.omega) + ",\"epoch\":" + std::to_string(o.epoch) +
                      ",\"auth_sender\":\"\",\"auth_seq\":0,";
    EXPECT_NE(json.find("{\"channel\":\"ECHO_IN\",\"utime\":"), std::string::npos);
    EXPECT_NE(json.find(msg), std::string::npos) << "missing odometry " << i;
    std::string reply = "\"type\":\"cmd_vel_t\",\"msg\":{\"utime\":" + std::to_string(o.utime) +
                        ",\"v\":" + fmt("%.17g", 2.0 * o.v) + ",\"omega\":" + fmt("%.17g", 2.0 * o.omega) +
                        ",\"auth_sender\":\"\",\"auth_seq\":0,";
    EXPECT_NE(json.find(reply), std::string::npos) << "missing reply " << i;
  }
}

// The test's replies (not the probes') among `events`.
std::vector<LogEvent> echo_replies(const std::vector<LogEvent>& events) {
  std::vector<LogEvent> out;
  for (const auto& e : events) {
    evade::cmd_vel_t c;
    if (e.channel == "ECHO_OUT" && decode(e.data.data(), e.data.size(), &c) && c.utime >= 1'000'000) out.push_back(e);
  }
  return out;
}

// The log adapter: same core over the logged inputs, twice -> identical,
// and equal to what the live process published.
void expect_replay_matches_live(const std::string& log_path) {
  auto events = read_log(log_path);
  std::vector<LogEvent> logged_out = echo_replies(events);
  ASSERT_EQ(logged_out.size(), static_cast<size_t>(kCount));
  ReplayOptions opt;
  opt.channels = {"ECHO_IN"};
  opt.keep_health = false;
  testing::EchoCore a("ECHO_IN", "ECHO_OUT"), b("ECHO_IN", "ECHO_OUT");
  auto out_a = replay({&a}, events, opt);
  auto out_b = replay({&b}, events, opt);
  ASSERT_EQ(out_a.size(), out_b.size());
  for (size_t i = 0; i < out_a.size(); ++i) {
    EXPECT_EQ(out_a[i].data, out_b[i].data);
    EXPECT_EQ(out_a[i].timestamp, out_b[i].timestamp);
  }
  std::vector<LogEvent> replayed_out = echo_replies(out_a);
  ASSERT_EQ(replayed_out.size(), logged_out.size());
  for (size_t i = 0; i < replayed_out.size(); ++i) EXPECT_EQ(replayed_out[i].data, logged_out[i].data);
}

TEST(LiveAndLog, UdpmRoundTripLoggedExportedAndReplayed) {
  ASSERT_EQ(std::getenv("EVADE_IN_NETNS") ? std::string(std::getenv("EVADE_IN_NETNS")) : "", "1")
      << "must run inside tools/netns-run";
  const std::string url = default_lcm_url();
  const std::string dir = ::testing::TempDir();
  const std::string log_path = dir + "/live_log_test.lcmlog";
  std::remove(log_path.c_str());
  const std::string bin = std::string(EVADE_BIN_DIR);

  pid_t logger = spawn({"lcm-logger", "--lcm-url=" + url, "--quiet", "--force", log_path});
  pid_t echo = spawn({bin + "/bus_echo", "--lcm-url", url});
  LiveBus bus(url);
  Listener listener;
  bus.add(listener);
  ASSERT_NO_FATAL_FAILURE(handshake(bus, listener));
  const std::vector<evade::odometry_t> sent = odometry_series();
  ASSERT_NO_FATAL_FAILURE(send_and_hear_echoes(bus, listener, sent));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  stop(echo, SIGTERM);
  stop(logger, SIGINT);

  expect_exported(run_capture(bin + "/lcmlog-export " + log_path + " --channel ECHO_IN --channel ECHO_OUT"), sent);
  expect_replay_matches_live(log_path);
}

}  // namespace
}  // namespace evade::bus

namespace evade::bus {
namespace {

// A slow core on a conflated channel hears only the newest of what queued
// up while it was busy.
class Slow : public Core {
 public:
  Slow() : Core("slow") {
    subscribe<evade::odometry_t>("ODOMETRY", [this](const evade::odometry_t& m) {
      heard.push_back(m.utime);
      if (heard.size() == 1) usleep(300'000);  // busy while the next ones queue up
    });
  }
  std::vector<int64_t> heard;
};

TEST(LiveBus, ConflatedChannelDeliversTheNewestAfterABusyHandler) {
  const std::string url = default_lcm_url();
  LiveBus rx(url), tx(url);
  Slow slow;
  rx.add(slow);
  rx.conflate("ODOMETRY");
  evade::odometry_t o{};
  o.utime = 1;
  tx.publish("ODOMETRY", 0, encode(o));
  // The first message arrives and the handler blocks for 0.3 s ...
  auto t0 = std::chrono::steady_clock::now();
  while (slow.heard.empty() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5)) {
    std::thread sender([&] {
      usleep(50'000);
      for (int i = 2; i <= 6; ++i) {  // ... while five more queue up
        evade::odometry_t m{};
        m.utime = i;
        tx.publish("ODOMETRY", 0, encode(m));
      }
    });
    rx.spin_once(100);
    sender.join();
  }
  ASSERT_GE(slow.heard.size(), 1u);
  for (int i = 0; i < 10 && slow.heard.size() < 2; ++i) rx.spin_once(100);
  for (int i = 0; i < 3; ++i) rx.spin_once(50);  // nothing else may arrive
  ASSERT_EQ(slow.heard.size(), 2u);
  EXPECT_EQ(slow.heard[1], 6) << "the queued messages 2..5 are skipped";
}

}  // namespace
}  // namespace evade::bus
