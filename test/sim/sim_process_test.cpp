// The sim binary end to end, in a private network namespace: its UDP
// packets decode (with the driver's decoder) into points on the true
// surfaces, its pty speaks Scout UART v1 (and survives the driver closing
// and reopening it), SIM_TRUTH arrives on LCM, bad input exits with a
// one-line reason.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>
#include <vector>

#include "base/scout_protocol.h"
#include "bus/core.h"
#include "evade/sim_truth_t.hpp"
#include "sensing/vlp16.h"

extern char** environ;

namespace {
namespace v = evade::sensing::vlp16;
namespace base = evade::base;
using Clock = std::chrono::steady_clock;

// A standing robot at (1, 2) facing 90 degrees, a cylinder 4 m in front of
// it and a box behind; nothing moves until the robot does.
const char* kScenario = R"(name: process_test
duration_s: 60
robot:
  start: {x: 1.0, y: 2.0, yaw: 1.5707963267948966}
  goal: {x: 1.0, y: 12.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
lidar: {model: vlp16, rate_hz: 10, height: 0.5, range_noise_std: 0.0}
obstacles:
  - {shape: cylinder, radius: 0.3, height: 1.7, x: 1.0, y: 6.0, vx: 1.0}
  - {shape: box, size: [2.0, 1.0, 1.0], x: 1.0, y: -2.0, yaw: 0.0}
)";

std::string temp_path(const std::string& stem) {
  return "/tmp/evade_sim_test_" + std::to_string(::getpid()) + "_" + stem;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Runs `args` to completion; returns the exit status, stderr in *err.
int run_to_end(std::vector<std::string> args, std::string* err) {
  std::string err_path = temp_path("stderr");
  std::string cmd;
  for (auto& a : args) cmd += "'" + a + "' ";
  cmd += "2>" + err_path;
  int status = std::system(cmd.c_str());
  *err = slurp(err_path);
  std::remove(err_path.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class SimProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    scenario_ = temp_path("scenario.yaml");
    std::ofstream(scenario_) << kScenario;
    device_ = temp_path("scout");
    // A UDP socket on a free port stands in for lidar_driver.
    udp_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(::bind(udp_, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
    socklen_t len = sizeof(a);
    ::getsockname(udp_, reinterpret_cast<sockaddr*>(&a), &len);
    int port = ntohs(a.sin_port);
    int buf = 8 << 20;
    ::setsockopt(udp_, SOL_SOCKET, SO_RCVBUF, &buf, sizeof(buf));
    timeval tv{0, 200'000};
    ::setsockopt(udp_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));

    std::vector<std::string> args = {
        SIM_BINARY, "--scenario", scenario_, "--device", device_, "--lidar-dest", "127.0.0.1:" + std::to_string(port)};
    std::vector<char*> argv;
    for (auto& s : args) argv.push_back(s.data());
    argv.push_back(nullptr);
    ASSERT_EQ(::posix_spawn(&pid_, SIM_BINARY, nullptr, nullptr, argv.data(), environ), 0);
    // Wait for the device link.
    auto until = Clock::now() + std::chrono::seconds(10);
    while (::access(device_.c_str(), F_OK) != 0 && Clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_EQ(::access(device_.c_str(), F_OK), 0) << "sim did not link " << device_;
  }
  void TearDown() override {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      int status = 0;
      ::waitpid(pid_, &status, 0);
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "sim did not stop cleanly";
      // It removes its own link on the way out.
      EXPECT_NE(::access(device_.c_str(), F_OK), 0);
    }
    if (udp_ >= 0) ::close(udp_);
    std::remove(scenario_.c_str());
  }

  int open_port() {
    int fd = ::open(device_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    termios t{};
    ::tcgetattr(fd, &t);
    ::cfmakeraw(&t);
    ::tcsetattr(fd, TCSANOW, &t);
    return fd;
  }
  // Reads frames for `seconds`, sending `cmd` (if any) every 20 ms.
  std::vector<base::Frame> exchange(int fd, double seconds, const base::MotionCommand* cmd) {
    std::vector<base::Frame> frames;
    base::StreamParser parser;
    auto end = Clock::now() + std::chrono::duration<double>(seconds);
    uint8_t count = 0;
    while (Clock::now() < end) {
      if (cmd) {
        base::FrameBytes f = base::encode(*cmd, count++);
        EXPECT_EQ(::write(fd, f.data(), f.size()), static_cast<ssize_t>(f.size()));
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      uint8_t buf[1024];
      ssize_t n;
      while ((n = ::read(fd, buf, sizeof(buf))) > 0)
        parser.feed(buf, static_cast<size_t>(n), [&](const base::Frame& f) { frames.push_back(f); });
    }
    EXPECT_EQ(parser.stats().bad_checksum + parser.stats().bad_length, 0u);
    return frames;
  }

  std::string scenario_, device_;
  int udp_ = -1;
  pid_t pid_ = -1;
};

TEST_F(SimProcess, PacketsDecodeOntoTheTrueSurfaces) {
  std::vector<v::Return> pts;
  int packets = 0;
  uint8_t buf[2048];
  auto end = Clock::now() + std::chrono::seconds(10);
  while (packets < 300 && Clock::now() < end) {
    ssize_t n = ::recv(udp_, buf, sizeof(buf), 0);
    if (n <= 0) continue;
    ASSERT_EQ(n, 1206);
    ASSERT_EQ(v::decode_packet(buf, static_cast<size_t>(n), {}, &pts, nullptr), v::PacketStatus::kOk);
    ++packets;
  }
  ASSERT_EQ(packets, 300);  // 0.4 s of data: four revolutions
  int cylinder = 0, box = 0;
  double worst = 0.0;
  for (const auto& p : pts) {
    // Sensor frame -> world: the robot faces +y at (1, 2), sensor 0.5 m up.
    double x = 1.0 - p.y, y = 2.0 + p.x, z = 0.5 + p.z;
    double e_ground = std::abs(z);
    double e_cyl = (z <= 1.7 + 1e-3) ? std::abs(std::hypot(x - 1.0, y - 6.0) - 0.3) : 1e9;
    double e_box = 1e9;
    if (std::abs(x - 1.0) <= 1.0 + 2e-3 && z <= 1.0 + 2e-3) e_box = std::abs(y - (-1.5));  // face towards the robot
    double e = std::min({e_ground, e_cyl, e_box});
    worst = std::max(worst, e);
    cylinder += e == e_cyl;
    box += e == e_box;
  }
  EXPECT_LT(worst, 0.002);
  EXPECT_GT(cylinder, 100);
  EXPECT_GT(box, 100);
}

TEST_F(SimProcess, ScoutFramesRoundTripAndTheLinkSurvivesAReopen) {
  int fd = open_port();
  ASSERT_GE(fd, 0);
  base::MotionCommand go;
  go.control_mode = base::kControlModeSerial;
  go.linear_percent = 40;  // 0.6 m/s
  go.angular_percent = -20;
  std::vector<base::Frame> frames = exchange(fd, 1.5, &go);
  int system = 0, motion = 0;
  int fastest = 0, turn = 0;
  for (const auto& f : frames) {
    base::MotionStatus m;
    base::SystemStatus s;
    if (base::from_frame(f, &m)) {
      ++motion;
      fastest = std::max<int>(fastest, m.linear_mm_s);
      turn = std::min<int>(turn, m.angular_mrad_s);
    }
    if (base::from_frame(f, &s)) ++system;
  }
  EXPECT_GT(system, 50);  // 50 Hz for 1.5 s, loosely
  EXPECT_GT(motion, 50);
  // The base reaches the commanded velocities (never more).
  EXPECT_EQ(fastest, 600);
  EXPECT_EQ(turn, -105);  // -20 % of 0.5235 rad/s
  base::MotionStatus last{};

  // The driver goes away (port closed, no commands): the base brakes to rest.
  ::close(fd);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  fd = open_port();
  ASSERT_GE(fd, 0) << "the port must still be there after a close";
  frames = exchange(fd, 0.5, nullptr);
  ASSERT_FALSE(frames.empty());
  ASSERT_TRUE(base::from_frame(frames.back(), &last));
  EXPECT_EQ(last.linear_mm_s, 0);
  EXPECT_EQ(last.angular_mrad_s, 0);
  ::close(fd);
}

TEST_F(SimProcess, PublishesSimTruth) {
  lcm::LCM lcm;
  ASSERT_TRUE(lcm.good());
  std::vector<evade::sim_truth_t> got;
  struct Handler {
    std::vector<evade::sim_truth_t>* out;
    void on(const lcm::ReceiveBuffer*, const std::string&, const evade::sim_truth_t* m) { out->push_back(*m); }
  } h{&got};
  lcm.subscribe("SIM_TRUTH", &Handler::on, &h);
  auto end = Clock::now() + std::chrono::seconds(1);
  while (Clock::now() < end) lcm.handleTimeout(50);
  ASSERT_GT(got.size(), 25u);
  const auto& t = got.back();
  EXPECT_DOUBLE_EQ(t.x, 1.0);
  EXPECT_DOUBLE_EQ(t.y, 2.0);
  EXPECT_EQ(t.num_obstacles, 2);
  EXPECT_FALSE(t.obstacles_moving);  // the robot has not moved
  EXPECT_DOUBLE_EQ(t.obstacles[0].x, 1.0);
  EXPECT_EQ(t.scenario, "process_test");
  // Stamped with the host clock, like every other process.
  int64_t wall =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count();
  EXPECT_LT(std::abs(wall - t.utime), 2'000'000);
}

TEST(SimProcessErrors, BadScenarioExitsWithFileLineKey) {
  std::string path = temp_path("bad.yaml");
  std::string text = kScenario;
  text.replace(text.find("vx: 1.0"), 7, "vx: fast");
  std::ofstream(path) << text;
  std::string err;
  EXPECT_EQ(run_to_end({SIM_BINARY, "--scenario", path}, &err), 2);
  EXPECT_NE(err.find(path + ":9: key 'obstacles[0].vx': expected a number, found 'fast'"), std::string::npos) << err;
  std::remove(path.c_str());
}

TEST(SimProcessRun, StopsAtTheScenarioDurationFasterWithSpeed) {
  std::string path = temp_path("short.yaml");
  std::string text = kScenario;
  text.replace(text.find("duration_s: 60"), 14, "duration_s: 2");
  std::ofstream(path) << text;
  std::string err;
  auto t0 = Clock::now();
  EXPECT_EQ(run_to_end({SIM_BINARY, "--scenario", path, "--speed", "10", "--device", temp_path("scout_fast")}, &err), 0)
      << err;
  double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  // 2 simulated seconds at 10x take 0.2 s of wall time; at 1x they would take 2 s.
  EXPECT_LT(wall_s, 1.5);
  EXPECT_NE(err.find("scenario duration 2 s reached"), std::string::npos) << err;
  std::remove(path.c_str());
}

TEST(SimProcessErrors, BadLidarDestinationIsRefused) {
  std::string err;
  EXPECT_EQ(run_to_end({SIM_BINARY, "--scenario", std::string(EVADE_SOURCE_DIR) + "/config/scenarios/paper_sim.yaml",
                        "--lidar-dest", "localhost"},
                       &err),
            2);
  EXPECT_NE(err.find("expected HOST:PORT"), std::string::npos) << err;
}

// The robot's body (sim.robot_body_height_m, 0.3 m in robot.yaml) must stay
// below the LiDAR, and the RS-Helios turns at 10 or 20 Hz only.
TEST(SimProcessErrors, ALidarTheSimCannotSimulateIsRefused) {
  std::string path = temp_path("low_lidar.yaml");
  std::string text = kScenario;
  const size_t at = text.find("height: 0.5, range_noise_std");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 11, "height: 0.2");
  std::ofstream(path) << text;
  std::string err;
  EXPECT_EQ(run_to_end({SIM_BINARY, "--scenario", path}, &err), 2);
  EXPECT_NE(err.find("robot_body_height_m must be below the LiDAR"), std::string::npos) << err;
  text = kScenario;
  text.replace(text.find("model: vlp16, rate_hz: 10"), 25, "model: rs_helios, rate_hz: 15");
  std::ofstream(path) << text;
  EXPECT_EQ(run_to_end({SIM_BINARY, "--scenario", path}, &err), 2);
  EXPECT_NE(err.find("key 'lidar.rate_hz': the RS-Helios turns at 10 or 20 Hz"), std::string::npos) << err;
  std::remove(path.c_str());
}

}  // namespace
