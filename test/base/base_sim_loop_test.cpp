// Closed loop through the real wire format: the sim (emulating the Scout on
// a pty) and base_driver (talking to it with libserial), both as processes
// in a private network namespace. CMD_VEL from this test must move the
// simulated robot, and base_driver's ODOMETRY must follow SIM_TRUTH.
// Bounds are physical (centimetres after metres of travel), not timings.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "../bus/test_signer.h"
#include "evade/base_status_t.hpp"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "pty_peer.h"

namespace {

using Clock = std::chrono::steady_clock;

pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
  pid_t pid = ::fork();
  if (pid == 0) {
    FILE* f = std::freopen(log.c_str(), "w", stderr);
    (void)f;
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    std::_Exit(127);
  }
  return pid;
}

void stop(pid_t pid) {
  if (pid <= 0) return;
  ::kill(pid, SIGTERM);
  ::waitpid(pid, nullptr, 0);
}

struct Collector {
  void on_odometry(const lcm::ReceiveBuffer*, const std::string&, const evade::odometry_t* m) {
    odometry.push_back(*m);
  }
  void on_truth(const lcm::ReceiveBuffer*, const std::string&, const evade::sim_truth_t* m) { truth.push_back(*m); }
  void on_status(const lcm::ReceiveBuffer*, const std::string&, const evade::base_status_t* m) { status.push_back(*m); }
  std::vector<evade::odometry_t> odometry;
  std::vector<evade::sim_truth_t> truth;
  std::vector<evade::base_status_t> status;
};

TEST(BaseSimLoop, OdometryFollowsTheSimulatedRobot) {
  evade::base::testing::TempDir tmp;
  const std::string dir = tmp.path, device = dir + "/scout";
  const std::string src = EVADE_SOURCE_DIR, bin = EVADE_BIN_DIR;
  const std::string config = src + "/config/robot.yaml";

  lcm::LCM lcm;  // $LCM_DEFAULT_URL from tools/netns-run
  ASSERT_TRUE(lcm.good());
  Collector c;
  lcm.subscribe("ODOMETRY", &Collector::on_odometry, &c);
  lcm.subscribe("SIM_TRUTH", &Collector::on_truth, &c);
  lcm.subscribe("BASE_STATUS", &Collector::on_status, &c);

  // The scenario starts the robot at (-10, 0, 0); odometry starts there too.
  pid_t sim = spawn(
      {bin + "/sim", "--config", config, "--scenario", src + "/config/scenarios/paper_sim.yaml", "--device", device},
      dir + "/sim.log");
  pid_t driver = spawn({bin + "/base_driver", "--config", config, "--device", device, "--initial-pose", "-10,0,0"},
                       dir + "/base_driver.log");

  // Wait for the link, then drive a curve for 3 s at 50 Hz.
  evade::bus::HmacAuth planner = evade::bus::testing::test_signer("planner");
  auto until = [&](double seconds, const std::function<bool()>& done, bool send) {
    const auto end = Clock::now() + std::chrono::duration<double>(seconds);
    auto next = Clock::now();
    while (Clock::now() < end && !(done && done())) {
      if (send && Clock::now() >= next) {
        next += std::chrono::milliseconds(20);
        evade::cmd_vel_t cmd{};
        cmd.utime =
            std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
                .count();  // base_driver ignores late commands
        cmd.v = 0.6;
        cmd.omega = 0.3;
        const auto data = evade::bus::testing::signed_bytes(planner, "CMD_VEL", cmd, cmd.utime);  // unsigned: ignored
        lcm.publish("CMD_VEL", data.data(), static_cast<unsigned>(data.size()));
      }
      lcm.handleTimeout(5);
    }
  };
  until(
      10.0, [&] { return !c.status.empty() && c.status.back().link_ok && !c.truth.empty(); }, false);
  ASSERT_FALSE(c.status.empty()) << "no BASE_STATUS";
  ASSERT_TRUE(c.status.back().link_ok) << "base_driver never saw the sim's status frames";
  until(3.0, nullptr, true);
  until(1.0, nullptr, false);  // the watchdog stops the robot; let it settle

  stop(driver);
  stop(sim);

  ASSERT_FALSE(c.odometry.empty());
  ASSERT_FALSE(c.truth.empty());
  const auto& odo = c.odometry.back();
  // The truth sample nearest in time to the last odometry.
  const evade::sim_truth_t* best = &c.truth.front();
  for (const auto& t : c.truth)
    if (std::llabs(t.utime - odo.utime) < std::llabs(best->utime - odo.utime)) best = &t;
  const double travelled = std::hypot(best->x + 10.0, best->y);
  std::printf("truth (%.4f, %.4f, %.4f) odometry (%.4f, %.4f, %.4f), %zu odometry messages\n", best->x, best->y,
              best->yaw, odo.x, odo.y, odo.yaw, c.odometry.size());
  EXPECT_GT(travelled, 1.0) << "the robot did not move";
  // Odometry integrates the sim's reported velocities (1 mm/s, 1 mrad/s
  // steps) at receive times: a few centimetres over a couple of metres.
  EXPECT_NEAR(odo.x, best->x, 0.05);
  EXPECT_NEAR(odo.y, best->y, 0.05);
  EXPECT_NEAR(std::remainder(odo.yaw - best->yaw, 2 * M_PI), 0.0, 0.03);
  EXPECT_TRUE(c.status.back().watchdog_tripped);  // no CMD_VEL for the last second
}

}  // namespace
