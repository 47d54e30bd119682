// sim -> UDP -> lidar_driver -> LIDAR_POINTS, both real binaries, in a
// private network namespace, for each LiDAR model (VLP-16 on its data
// port; RS-Helios MSOP and DIFOP on theirs): every point of every
// revolution, put in the world with SIM_TRUTH's robot pose and the mount
// pose the message carries, lies on the true ground, cylinder or box
// surface (within the scenario's range noise).
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "evade/pointcloud_t.hpp"
#include "evade/sim_truth_t.hpp"

extern char** environ;

namespace {
using Clock = std::chrono::steady_clock;

// Robot at (2, -1) facing -45 degrees; a tall cylinder and a turned box in
// view; 5 mm range noise.
const char* kScenario = R"(name: chain_test
duration_s: 60
robot:
  start: {x: 2.0, y: -1.0, yaw: -0.7853981633974483}
  goal: {x: 10.0, y: -9.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
lidar: {model: vlp16, rate_hz: 10, height: 0.5, range_noise_std: 0.005}
obstacles:
  - {shape: cylinder, radius: 0.4, height: 1.7, x: 5.0, y: -4.0}
  - {shape: box, size: [3.0, 1.0, 1.2], x: -1.0, y: 1.5, yaw: 0.5}
)";
constexpr double kNoise = 0.005;

pid_t spawn(std::vector<std::string> args) {
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  EXPECT_EQ(::posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ), 0);
  return pid;
}

void stop(pid_t pid) {
  if (pid <= 0) return;
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
}

// Distance from the nearest true surface.
double surface_error(double x, double y, double z, int* which) {
  double best = std::abs(z);
  *which = 0;
  double radial = std::hypot(x - 5.0, y + 4.0);
  double cyl = (z <= 1.7 + 0.02) ? std::abs(radial - 0.4) : 1e9;
  if (radial <= 0.42) cyl = std::min(cyl, std::abs(z - 1.7));
  if (cyl < best) best = cyl, *which = 1;
  double c = std::cos(0.5), s = std::sin(0.5);
  double bx = c * (x + 1.0) + s * (y - 1.5), by = -s * (x + 1.0) + c * (y - 1.5);
  double ex = std::abs(bx) - 1.5, ey = std::abs(by) - 0.5, ez = std::abs(z - 0.6) - 0.6;
  double box = std::abs(std::hypot(std::hypot(std::max(ex, 0.0), std::max(ey, 0.0)), std::max(ez, 0.0)) +
                        std::min(std::max(ex, std::max(ey, ez)), 0.0));
  if (box < best) best = box, *which = 2;
  return best;
}

// robot.yaml with lidar.model set to `model`.
std::string config_for(const std::string& model) {
  std::ifstream in(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const size_t at = text.find("model: vlp16 ");
  EXPECT_NE(at, std::string::npos);
  text.replace(at, 13, "model: " + model + " ");
  std::string path = "/tmp/evade_sim_chain_" + model + "_" + std::to_string(::getpid()) + ".yaml";
  std::ofstream(path) << text;
  return path;
}

class SimLidarDriverChain : public ::testing::TestWithParam<std::string> {};

TEST_P(SimLidarDriverChain, PointsLieOnTheTrueSurfaces) {
  const std::string model = GetParam();
  std::string scenario = "/tmp/evade_sim_chain_" + std::to_string(::getpid()) + ".yaml";
  std::string text = kScenario;
  text.replace(text.find("model: vlp16"), 12, "model: " + model);
  std::ofstream(scenario) << text;
  const std::string config = config_for(model);
  std::string device = "/tmp/evade_sim_chain_" + std::to_string(::getpid()) + ".pty";

  lcm::LCM lcm;
  ASSERT_TRUE(lcm.good());
  std::vector<evade::pointcloud_t> clouds;
  std::vector<evade::sim_truth_t> truths;
  struct Handler {
    std::vector<evade::pointcloud_t>* clouds;
    std::vector<evade::sim_truth_t>* truths;
    void cloud(const lcm::ReceiveBuffer*, const std::string&, const evade::pointcloud_t* m) { clouds->push_back(*m); }
    void truth(const lcm::ReceiveBuffer*, const std::string&, const evade::sim_truth_t* m) { truths->push_back(*m); }
  } h{&clouds, &truths};
  lcm.subscribe("LIDAR_POINTS", &Handler::cloud, &h);
  lcm.subscribe("SIM_TRUTH", &Handler::truth, &h);

  pid_t driver = spawn({LIDAR_DRIVER_BINARY, "--config", config});
  pid_t sim = spawn({SIM_BINARY, "--scenario", scenario, "--device", device, "--config", config});
  auto end = Clock::now() + std::chrono::seconds(15);
  while (clouds.size() < 6 && Clock::now() < end) lcm.handleTimeout(50);
  stop(sim);
  stop(driver);
  std::remove(scenario.c_str());
  std::remove(config.c_str());
  ASSERT_GE(clouds.size(), 6u) << "lidar_driver published too few revolutions";
  ASSERT_FALSE(truths.empty());
  const evade::sim_truth_t& t = truths.back();
  ASSERT_DOUBLE_EQ(t.x, 2.0);  // standing: the obstacles are static and the robot never moved

  // Skip the first cloud (a partial revolution), check the rest.
  int counts[3] = {0, 0, 0};
  double worst = 0.0;
  size_t points = 0;
  for (size_t k = 1; k < clouds.size(); ++k) {
    const evade::pointcloud_t& c = clouds[k];
    EXPECT_EQ(c.sensor_model, model);
    // Ground-facing lasers x ~1800 firings, less what the solids hide: VLP-16 8, RS-Helios 22.
    EXPECT_GT(c.n, model == "vlp16" ? 12000 : 36000);
    for (int i = 0; i < c.n; ++i) {
      // Sensor frame -> base (mount from the message; yaw-only mount here) -> world.
      double mc = std::cos(c.mount.yaw), ms = std::sin(c.mount.yaw);
      double bx = c.mount.x + mc * c.x[i] - ms * c.y[i], by = c.mount.y + ms * c.x[i] + mc * c.y[i];
      double bz = c.mount.z + c.z[i];
      double wc = std::cos(t.yaw), ws = std::sin(t.yaw);
      double wx = t.x + wc * bx - ws * by, wy = t.y + ws * bx + wc * by;
      int which;
      worst = std::max(worst, surface_error(wx, wy, bz, &which));
      counts[which]++;
      ++points;
    }
  }
  std::printf("%zu points in %zu revolutions: worst surface error %.4f m; %d ground, %d cylinder, %d box\n", points,
              clouds.size() - 1, worst, counts[0], counts[1], counts[2]);
  // 6 sigma of the range noise (80,000 to 200,000 draws), plus the 2 / 2.5 mm range unit and float rounding.
  EXPECT_LT(worst, 6 * kNoise + 0.003) << "over " << points << " points";
  EXPECT_GT(counts[1], 100 * static_cast<int>(clouds.size() - 1) / 2);
  EXPECT_GT(counts[2], 100 * static_cast<int>(clouds.size() - 1) / 2);
}

INSTANTIATE_TEST_SUITE_P(Models, SimLidarDriverChain, ::testing::Values("vlp16", "rs_helios"));

}  // namespace
