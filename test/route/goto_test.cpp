// tools/goto over real LCM (inside the test's private network namespace):
// X Y sends the straight route from where ODOMETRY says the robot is, a
// route file sends its polyline, no ODOMETRY is exit 1, bad input exit 2,
// and a live `route` process adopts goto's route and repeats it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bus/core.h"
#include "bus/live_bus.h"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"

namespace {

const std::string kBin = EVADE_BIN_DIR;

pid_t spawn(const std::vector<std::string>& args) {
  pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int exit_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Listens to ROUTE and, while `odometry` is set, publishes ODOMETRY at 20 Hz.
struct Bus {
  lcm::LCM lcm{evade::bus::default_lcm_url()};
  std::vector<evade::path_t> routes;
  bool odometry = true;
  Bus() { lcm.subscribe("ROUTE", &Bus::on_route, this); }
  void on_route(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    evade::path_t p;
    if (evade::bus::decode(static_cast<const uint8_t*>(rbuf->data), rbuf->data_size, &p)) routes.push_back(p);
  }
  // Runs until `pid` exits (or `seconds` pass); returns its exit code.
  int run(pid_t pid, double seconds) {
    auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    int status = 0;
    while (std::chrono::steady_clock::now() < until) {
      if (odometry) {
        evade::odometry_t o{};
        o.utime = evade::bus::wall_utime();
        o.x = -2.5;
        o.y = 1.25;
        std::vector<uint8_t> d = evade::bus::encode(o);
        lcm.publish("ODOMETRY", d.data(), static_cast<unsigned>(d.size()));
      }
      lcm.handleTimeout(50);
      if (pid > 0 && waitpid(pid, &status, WNOHANG) == pid) {
        for (int i = 0; i < 5; ++i) lcm.handleTimeout(20);  // late deliveries
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      }
    }
    return -2;
  }
};

TEST(Goto, SendsTheStraightRouteFromTheRobotToTheGoal) {
  Bus bus;
  ASSERT_TRUE(bus.lcm.good());
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "3", "4"}), 10.0), 0);
  ASSERT_EQ(bus.routes.size(), 1u);
  EXPECT_EQ(bus.routes[0].x, (std::vector<double>{-2.5, 3.0}));
  EXPECT_EQ(bus.routes[0].y, (std::vector<double>{1.25, 4.0}));
}

TEST(Goto, SendsARouteFile) {
  const std::string path = ::testing::TempDir() + "goto_route.yaml";
  std::ofstream(path) << "route: [[0, 0], [2, 0], [2, 3]]\n";
  Bus bus;
  bus.odometry = false;
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "--route", path}), 10.0), 0);
  ASSERT_EQ(bus.routes.size(), 1u);
  EXPECT_EQ(bus.routes[0].n, 3);
  EXPECT_EQ(bus.routes[0].y, (std::vector<double>{0, 0, 3}));
  std::remove(path.c_str());
}

TEST(Goto, NoOdometryOrBadInputSendsNothing) {
  Bus bus;
  bus.odometry = false;
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "3", "4", "--odometry-wait-s", "0.3"}), 10.0), 1);
  bus.odometry = true;
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "-2.5", "1.25"}), 10.0), 2);  // the goal is where the robot is
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "3"}), 10.0), 2);
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "--route", "/nonexistent.yaml"}), 10.0), 2);
  EXPECT_TRUE(bus.routes.empty());
}

TEST(Goto, ALiveRouteProcessRepeatsGotosRoute) {
  Bus bus;
  bus.odometry = false;
  pid_t route = spawn({kBin + "/route", "--config", std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"});
  bus.run(-1, 1.5);  // its configured route, once a second
  ASSERT_FALSE(bus.routes.empty()) << "route process not heard";
  const std::vector<double> configured = bus.routes.back().x;
  bus.odometry = true;
  EXPECT_EQ(bus.run(spawn({kBin + "/goto", "3", "4"}), 10.0), 0);
  bus.odometry = false;
  bus.routes.clear();
  bus.run(-1, 2.5);  // two more periods: only goto's route
  kill(route, SIGTERM);
  EXPECT_EQ(exit_code(route), 0);
  ASSERT_GE(bus.routes.size(), 2u);
  for (const auto& r : bus.routes) EXPECT_EQ(r.x, (std::vector<double>{-2.5, 3.0}));
  EXPECT_NE(configured, (std::vector<double>{-2.5, 3.0}));
}

}  // namespace
