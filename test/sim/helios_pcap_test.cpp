// An RS-Helios capture made by the simulator (build/bin/sim-pcap: MSOP and
// DIFOP in Ethernet/IPv4/UDP frames) read by the real lidar_driver binary
// in --pcap mode, in a private network namespace: every revolution is
// whole, on the sensor's 32-ring table, and every point lies on the true
// ground, cylinder or box surface (within the 2.5 mm distance unit).
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "evade/pointcloud_t.hpp"

extern char** environ;

namespace {
using Clock = std::chrono::steady_clock;

// Robot standing at the origin facing +x; a cylinder ahead, a box behind-left.
const char* kScenario = R"(name: helios_pcap
duration_s: 60
robot:
  start: {x: 0.0, y: 0.0, yaw: 0.0}
  goal: {x: 10.0, y: 0.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
lidar: {model: rs_helios, rate_hz: 10, height: 0.5, range_noise_std: 0.0}
obstacles:
  - {shape: cylinder, radius: 0.4, height: 1.7, x: 4.0, y: 0.5}
  - {shape: box, size: [3.0, 1.0, 1.2], x: -3.0, y: 2.5, yaw: 0.5}
)";

std::string temp(const std::string& stem, const std::string& ext) {
  return ::testing::TempDir() + stem + "_" + std::to_string(::getpid()) + ext;
}

int run(std::vector<std::string> args, lcm::LCM* lcm) {
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (::posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  auto end = Clock::now() + std::chrono::seconds(30);
  int status = 0;
  while (Clock::now() < end) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
    if (lcm)
      lcm->handleTimeout(10);
    else
      ::usleep(10000);
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -3;
}

// robot.yaml with lidar.model rs_helios (the mount stays 0.5 m up, as the scenario's).
std::string helios_config() {
  std::ifstream in(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const size_t at = text.find("model: vlp16 ");
  EXPECT_NE(at, std::string::npos);
  text.replace(at, 13, "model: rs_helios ");
  std::string path = temp("helios_config", ".yaml");
  std::ofstream(path) << text;
  return path;
}

double surface_error(double x, double y, double z) {
  double best = std::abs(z);
  const double radial = std::hypot(x - 4.0, y - 0.5);
  if (z <= 1.7 + 0.01) best = std::min(best, std::abs(radial - 0.4));
  if (radial <= 0.41) best = std::min(best, std::abs(z - 1.7));
  const double c = std::cos(0.5), s = std::sin(0.5);
  const double bx = c * (x + 3.0) + s * (y - 2.5), by = -s * (x + 3.0) + c * (y - 2.5);
  const double ex = std::abs(bx) - 1.5, ey = std::abs(by) - 0.5, ez = std::abs(z - 0.6) - 0.6;
  const double box = std::abs(std::hypot(std::hypot(std::max(ex, 0.0), std::max(ey, 0.0)), std::max(ez, 0.0)) +
                              std::min(std::max(ex, std::max(ey, ez)), 0.0));
  return std::min(best, box);
}

TEST(HeliosPcap, SimCaptureDecodesByLidarDriverPcapMode) {
  const std::string scenario = temp("helios_pcap", ".yaml"), capture = temp("helios", ".pcap");
  std::ofstream(scenario) << kScenario;
  ASSERT_EQ(run({SIM_PCAP_BINARY, "--scenario", scenario, "--out", capture, "--seconds", "0.35", "--config",
                 std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"},
                nullptr),
            0);
  std::ifstream f(capture, std::ios::binary | std::ios::ate);
  // 0.35 s: 1 DIFOP + 524 MSOP packets of 1248 bytes, each in a 1290-byte frame + 16-byte record header.
  EXPECT_EQ(static_cast<long>(f.tellg()), 24 + 525 * (16 + 1290));

  lcm::LCM lcm;
  ASSERT_TRUE(lcm.good());
  std::vector<evade::pointcloud_t> clouds;
  struct H {
    std::vector<evade::pointcloud_t>* c;
    void on(const lcm::ReceiveBuffer*, const std::string&, const evade::pointcloud_t* m) { c->push_back(*m); }
  } h{&clouds};
  lcm.subscribe("LIDAR_POINTS", &H::on, &h);
  ASSERT_EQ(run({LIDAR_DRIVER_BINARY, "--config", helios_config(), "--pcap", capture, "--rate", "0"}, &lcm), 0);
  for (int i = 0; i < 50; ++i) lcm.handleTimeout(10);
  std::remove(scenario.c_str());
  std::remove(capture.c_str());

  // Three full revolutions and the flushed last half.
  ASSERT_EQ(clouds.size(), 4u);
  double worst = 0.0;
  int on_obstacles = 0;
  for (size_t k = 0; k < clouds.size(); ++k) {
    const evade::pointcloud_t& c = clouds[k];
    EXPECT_EQ(c.sensor_model, "rs_helios");
    EXPECT_DOUBLE_EQ(c.mount.z, 0.5);
    if (k < 3) {
      EXPECT_NEAR(c.packets, 150, 1);
      std::set<int> rings(c.ring.begin(), c.ring.end());
      EXPECT_GE(rings.size(), 22u);  // the 22 downward rings, and the upward ones that see the cylinder
    }
    for (int i = 0; i < c.n; ++i) {
      const double z = c.mount.z + c.z[i];
      const double e = surface_error(c.x[i], c.y[i], z);
      worst = std::max(worst, e);
      on_obstacles += std::abs(z) > 0.01;
    }
  }
  EXPECT_LT(worst, 0.002);
  EXPECT_GT(on_obstacles, 3 * 200);
}

}  // namespace
