// The lidar_driver binary end to end, inside a private network namespace
// (NETNS): UDP packets on 127.0.0.1 -> LIDAR_POINTS on LCM; --pcap mode
// flushes and exits; --replay of the recorded LIDAR_SCAN reproduces the
// LIDAR_POINTS byte for byte.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "evade/health_t.hpp"
#include "evade/lidar_scan_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "sensing/rs_helios.h"
#include "synthetic.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kTestPort = 23680;

std::string source(const std::string& rel) { return std::string(EVADE_SOURCE_DIR) + "/" + rel; }
std::string sample_path() { return source("test/data/vlp16_sample.pcap"); }
// A temp file of this process: ctest runs this binary's tests side by side,
// and one reading a shared file while another rewrote it saw half a file.
std::string temp_path(const std::string& stem, const std::string& ext) {
  return ::testing::TempDir() + stem + "_" + std::to_string(::getpid()) + ext;
}
bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

constexpr int kTestMsopPort = 26699;
constexpr int kTestDifopPort = 27788;

// robot.yaml with the driver bound to 127.0.0.1:kTestPort (RS-Helios:
// kTestMsopPort, kTestDifopPort).
std::string test_config(const std::string& model = "vlp16") {
  std::ifstream in(source("config/robot.yaml"));
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  auto replace = [&](const std::string& from, const std::string& to) {
    size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  replace("bind_address: 0.0.0.0", "bind_address: 127.0.0.1");
  replace("vlp16_data_port: 2368", "vlp16_data_port: " + std::to_string(kTestPort));
  replace("rs_helios_msop_port: 6699", "rs_helios_msop_port: " + std::to_string(kTestMsopPort));
  replace("rs_helios_difop_port: 7788", "rs_helios_difop_port: " + std::to_string(kTestDifopPort));
  replace("model: vlp16 ", "model: " + model + " ");
  std::string path = temp_path("lidar_driver_test_" + model, ".yaml");
  std::ofstream(path) << text;
  return path;
}

pid_t spawn(const std::vector<std::string>& args) {
  pid_t pid = ::fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// Waits for the child; -1 if it did not exit within timeout. `meanwhile`
// (about 10 ms each) replaces the sleep between checks, e.g. reading the bus
// while the child publishes.
int wait_exit(pid_t pid, double timeout_s, const std::function<void()>& meanwhile = {}) {
  auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < end) {
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid)
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (meanwhile)
      meanwhile();
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  return -1;
}

struct Listener {
  lcm::LCM lcm;
  struct Event {
    std::string channel;
    int64_t recv_utime;
    std::vector<uint8_t> data;
  };
  std::vector<Event> events;
  Listener() {
    EXPECT_TRUE(lcm.good());
    lcm.subscribeFunction(".*", &Listener::on, this);
  }
  static void on(const lcm::ReceiveBuffer* rbuf, const std::string& channel, Listener* self) {
    const auto* p = static_cast<const uint8_t*>(rbuf->data);
    self->events.push_back({channel, rbuf->recv_utime, std::vector<uint8_t>(p, p + rbuf->data_size)});
  }
  // Handles messages until pred() holds or timeout; returns pred().
  bool spin_until(const std::function<bool()>& pred, double timeout_s) {
    auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (!pred() && Clock::now() < end) lcm.handleTimeout(20);
    return pred();
  }
  template <class Msg>
  std::vector<Msg> decoded(const std::string& channel) const {
    std::vector<Msg> out;
    for (const auto& e : events)
      if (e.channel == channel) {
        Msg m;
        if (m.decode(e.data.data(), 0, static_cast<int>(e.data.size())) == static_cast<int>(e.data.size()))
          out.push_back(m);
      }
    return out;
  }
  size_t count(const std::string& channel) const {
    size_t n = 0;
    for (const auto& e : events) n += e.channel == channel;
    return n;
  }
};

// Paces the sender (8 packets per 2 ms, about real time) so that a loaded
// machine never overflows the driver's socket buffer, and hears LCM meanwhile.
void pause_sending(Listener& l) {
  auto until = Clock::now() + std::chrono::milliseconds(2);
  while (Clock::now() < until) l.lcm.handleTimeout(1);
}

int64_t health_counter(const Listener& l, const std::string& name) {
  int64_t v = -1;
  for (const auto& h : l.decoded<evade::health_t>("HEALTH"))
    if (h.name == "lidar_driver")
      for (const auto& c : h.counters)
        if (c.name == name) v = c.value;
  return v;
}

TEST(LidarDriverProcess, UdpPacketsOnLoopbackBecomeLidarPoints) {
  Listener l;
  pid_t pid = spawn({LIDAR_DRIVER_BIN, "--config", test_config()});
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(l.spin_until([&] { return l.count("HEALTH") > 0; }, 10.0)) << "no HEALTH from lidar_driver";
  // A second driver on the same port cannot bind: it says so and exits 1.
  EXPECT_EQ(wait_exit(spawn({LIDAR_DRIVER_BIN, "--config", test_config()}), 10.0), 1);

  int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(kTestPort);
  ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  evade::sensing::testing::SyntheticVlp16 s;  // 10 Hz from 300 deg, a 10 m cylinder
  const int n = 200;                          // cuts near packets 16, 91, 166
  for (int k = 0; k < n; ++k) {
    auto p = s.packet(k);
    ASSERT_EQ(::sendto(fd, p.bytes.data(), p.bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to)),
              static_cast<ssize_t>(p.bytes.size()));
    if (k % 8 == 7) pause_sending(l);
  }
  const uint8_t junk[100] = {0xFF, 0xEE};
  ::sendto(fd, junk, sizeof(junk), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
  ::close(fd);

  EXPECT_TRUE(l.spin_until([&] { return l.count("LIDAR_POINTS") >= 3; }, 10.0));
  EXPECT_TRUE(l.spin_until([&] { return health_counter(l, "malformed_wrong_size") >= 1; }, 5.0));
  auto clouds = l.decoded<evade::pointcloud_t>("LIDAR_POINTS");
  ASSERT_GE(clouds.size(), 3u);
  EXPECT_EQ(l.count("LIDAR_SCAN"), l.count("LIDAR_POINTS"));
  // The two full revolutions: every firing of 360 deg, all on the 10 m cylinder.
  const double firings = 2.0 * 360.0 / s.degrees_per_block();
  for (int i : {1, 2}) {
    const auto& c = clouds[static_cast<size_t>(i)];
    EXPECT_NEAR(c.n, 16.0 * firings, 32.0);
    EXPECT_EQ(c.sensor_model, "vlp16");
    EXPECT_DOUBLE_EQ(c.mount.z, 0.5);  // robot.yaml lidar.mount.z_m
    for (int j = 0; j < c.n; j += 97) ASSERT_NEAR(std::hypot(c.x[j], c.y[j]), 10.0, 0.01);
  }
  EXPECT_EQ(health_counter(l, "data_packets"), n);

  ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid, 5.0), 0);
}

void send_to(int fd, int port, const uint8_t* data, size_t size) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  ASSERT_EQ(::sendto(fd, data, size, 0, reinterpret_cast<sockaddr*>(&to), sizeof(to)), static_cast<ssize_t>(size));
}

TEST(LidarDriverProcess, RsHeliosMsopAndDifopOnTheirOwnPorts) {
  namespace h = evade::sensing::rs_helios;
  Listener l;
  pid_t pid = spawn({LIDAR_DRIVER_BIN, "--config", test_config("rs_helios")});
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(l.spin_until([&] { return l.count("HEALTH") > 0; }, 10.0)) << "no HEALTH from lidar_driver";
  int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  const double deg_per_block = 360.0 * 10.0 * h::kBlockPeriodUs * 1e-6;  // 10 Hz
  auto msop = [&](int k) {
    h::MsopEncoder m;
    for (int b = 0; b < 12; ++b) {
      m.blocks[b].azimuth_deg = std::fmod(200.0 + (k * 12 + b) * deg_per_block, 360.0);
      for (int c = 0; c < 32; ++c) m.blocks[b].distance_m[c] = 6.0;
    }
    m.utc_us = 1'700'000'000'000'000LL + std::llround(k * 12 * h::kBlockPeriodUs);
    return m.encode();
  };
  for (int k = 0; k < 5; ++k) send_to(fd, kTestMsopPort, msop(k).data(), h::kPacketSize);  // before any DIFOP
  l.lcm.handleTimeout(50);
  h::DifopEncoder d;
  for (int c = 0; c < 32; ++c) d.vertical_deg[c] = -16.0 + c;
  send_to(fd, kTestDifopPort, d.encode().data(), h::kPacketSize);
  l.lcm.handleTimeout(50);
  for (int k = 5; k < 400; ++k) {  // 2.4 deg per packet: cuts near packets 68 and 218, 368
    send_to(fd, kTestMsopPort, msop(k).data(), h::kPacketSize);
    if (k % 8 == 7) pause_sending(l);
  }
  ::close(fd);
  EXPECT_TRUE(l.spin_until([&] { return l.count("LIDAR_POINTS") >= 3; }, 10.0));
  EXPECT_TRUE(l.spin_until([&] { return health_counter(l, "data_packets") == 395; }, 5.0));
  EXPECT_EQ(health_counter(l, "msop_before_difop"), 5);
  EXPECT_EQ(health_counter(l, "difop_packets"), 1);
  auto clouds = l.decoded<evade::pointcloud_t>("LIDAR_POINTS");
  ASSERT_GE(clouds.size(), 3u);
  for (const auto& c : clouds) EXPECT_EQ(c.sensor_model, "rs_helios");
  const auto& full = clouds[1];
  EXPECT_NEAR(full.n, 1800 * 32, 64);  // 0.2 deg firings, 32 channels
  std::vector<int> per_ring(32, 0);
  for (int j = 0; j < full.n; ++j) ++per_ring[static_cast<size_t>(full.ring[j])];
  for (int r = 0; r < 32; ++r) EXPECT_NEAR(per_ring[r], 1800, 2) << r;
  ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid, 5.0), 0);
}

TEST(LidarDriverProcess, PcapModeFlushesExitsAndReplaysIdentically) {
  ASSERT_TRUE(exists(sample_path())) << "missing " << sample_path();
  Listener l;
  const auto t0 = Clock::now();
  pid_t pid = spawn({LIDAR_DRIVER_BIN, "--config", test_config(), "--pcap", sample_path(), "--rate", "1"});
  int rc = -2;
  l.spin_until(
      [&] {
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) rc = WIFEXITED(status) ? WEXITSTATUS(status) : -3;
        return rc != -2;
      },
      20.0);
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  ASSERT_EQ(rc, 0);
  l.spin_until([&] { return l.count("LIDAR_POINTS") >= 2 && l.count("LIDAR_SCAN") >= 2; }, 2.0);
  // At the recorded pace the 100 datagrams span 0.11 s; it cannot be faster.
  EXPECT_GE(elapsed, 0.10);
  ASSERT_EQ(l.count("LIDAR_POINTS"), 2u);
  ASSERT_EQ(l.count("LIDAR_SCAN"), 2u);
  // (HEALTH is 1 Hz: a 0.11 s capture ends before its counters are reported;
  // sample_pcap_test checks them on the core.)

  // Log the scans, replay them through the binary, compare the clouds.
  const std::string in_log = temp_path("lidar_scan", ".lcmlog");
  const std::string out_log = temp_path("lidar_points_replayed", ".lcmlog");
  {
    lcm::LogFile log(in_log, "w");
    ASSERT_TRUE(log.good());
    int64_t n = 0;
    for (const auto& e : l.events) {
      if (e.channel != "LIDAR_SCAN") continue;
      lcm::LogEvent ev;
      ev.eventnum = n++;
      ev.timestamp = e.recv_utime;
      ev.channel = e.channel;
      ev.datalen = static_cast<int32_t>(e.data.size());
      ev.data = const_cast<uint8_t*>(e.data.data());
      ASSERT_EQ(log.writeEvent(&ev), 0);
    }
  }
  pid = spawn({LIDAR_DRIVER_BIN, "--config", test_config(), "--replay", in_log, "--replay-out", out_log});
  ASSERT_EQ(wait_exit(pid, 20.0), 0);
  std::vector<std::vector<uint8_t>> replayed, live;
  {
    lcm::LogFile log(out_log, "r");
    ASSERT_TRUE(log.good());
    while (const lcm::LogEvent* ev = log.readNextEvent())
      if (ev->channel == "LIDAR_POINTS")
        replayed.emplace_back(static_cast<const uint8_t*>(ev->data),
                              static_cast<const uint8_t*>(ev->data) + ev->datalen);
  }
  for (const auto& e : l.events)
    if (e.channel == "LIDAR_POINTS") live.push_back(e.data);
  ASSERT_EQ(replayed.size(), live.size());
  for (size_t i = 0; i < live.size(); ++i) EXPECT_EQ(replayed[i], live[i]) << "revolution " << i;
}

// As fast as possible, the clouds keep the capture's own time spacing: a
// cloud is stamped with its revolution's first packet, and the sample's
// second revolution starts 23 packets (1.327 ms apart) after the first,
// whatever the replay speed; two runs give the same spacing.
TEST(LidarDriverProcess, PcapAtFullSpeedKeepsTheCaptureTimeSpacing) {
  ASSERT_TRUE(exists(sample_path())) << "missing " << sample_path();
  std::vector<int64_t> spacing;
  for (int run = 0; run < 2; ++run) {
    Listener l;
    pid_t pid = spawn({LIDAR_DRIVER_BIN, "--config", test_config(), "--pcap", sample_path(), "--rate", "0"});
    // read while the driver publishes at full speed, not only after it has
    // exited (its whole output would otherwise wait in the socket buffer)
    ASSERT_EQ(wait_exit(pid, 20.0, [&] { l.lcm.handleTimeout(10); }), 0);
    l.spin_until([&] { return l.count("LIDAR_POINTS") >= 2; }, 2.0);
    const auto clouds = l.decoded<evade::pointcloud_t>("LIDAR_POINTS");
    ASSERT_EQ(clouds.size(), 2u);
    spacing.push_back(clouds[1].utime - clouds[0].utime);
  }
  EXPECT_EQ(spacing[0], spacing[1]);
  EXPECT_NEAR(static_cast<double>(spacing[0]), 23 * 1327.0, 1327.0 / 2);  // within half a packet
}

// --from-scan: no socket; LIDAR_SCAN messages on the bus (a log played
// back) become LIDAR_POINTS, and no LIDAR_SCAN is published again.
TEST(LidarDriverProcess, FromScanDecodesLidarScanMessagesOnTheBus) {
  Listener l;
  pid_t pid = spawn({LIDAR_DRIVER_BIN, "--config", test_config(), "--from-scan"});
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(l.spin_until([&] { return l.count("HEALTH") > 0; }, 10.0)) << "no HEALTH from lidar_driver";
  evade::sensing::testing::SyntheticVlp16 s;  // cuts near packets 16, 91, 166
  for (int part = 0; part < 2; ++part) {      // packets 0-99, then 100-199
    evade::lidar_scan_t scan{};
    scan.sensor_model = "vlp16";
    for (int k = part * 100; k < part * 100 + 100; ++k) {
      auto p = s.packet(k);
      evade::lidar_packet_t pk{};
      pk.utime = p.sensor_utime + 1500;
      pk.data.assign(p.bytes.begin(), p.bytes.end());
      pk.size = static_cast<int32_t>(p.bytes.size());
      scan.packets.push_back(pk);
    }
    scan.num_packets = static_cast<int32_t>(scan.packets.size());
    scan.utime = scan.packets.front().utime;
    ASSERT_EQ(l.lcm.publish("LIDAR_SCAN", &scan), 0);
  }
  EXPECT_TRUE(l.spin_until([&] { return l.count("LIDAR_POINTS") >= 3; }, 10.0));
  const auto clouds = l.decoded<evade::pointcloud_t>("LIDAR_POINTS");
  ASSERT_EQ(clouds.size(), 3u);  // the partial first revolution and the two full ones
  const double firings = 2.0 * 360.0 / s.degrees_per_block();
  for (int i : {1, 2}) {
    const auto& c = clouds[static_cast<size_t>(i)];
    EXPECT_NEAR(c.n, 16.0 * firings, 32.0);
    for (int j = 0; j < c.n; j += 97) ASSERT_NEAR(std::hypot(c.x[j], c.y[j]), 10.0, 0.01);
  }
  EXPECT_EQ(l.count("LIDAR_SCAN"), 2u);  // the test's own two, heard back
  ::kill(pid, SIGTERM);
  EXPECT_EQ(wait_exit(pid, 5.0), 0);
}

TEST(LidarDriverProcess, BadConfigExitsWithStatusTwo) {
  std::string path = temp_path("bad_lidar", ".yaml");
  std::ifstream in(test_config());
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  text.replace(text.find("time_source: receive"), 20, "time_source: gps");
  std::ofstream(path) << text;
  pid_t pid = spawn({LIDAR_DRIVER_BIN, "--config", path});
  EXPECT_EQ(wait_exit(pid, 10.0), 2);
}

}  // namespace
