// The lockstep closed loop as a whole: the stack runs a short scenario in
// simulated time, reproducibly, and charges the planner's compute time
// the way its model says.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>

#include "bus/core.h"
#include "bus/log.h"
#include "closedloop/closed_loop.h"
#include "closedloop/run_monitor.h"
#include "config/config.h"
#include "evade/odometry_t.hpp"
#include "evade/plan_t.hpp"
#include "sim/scenario.h"

namespace evade::closedloop {
namespace {

namespace fs = std::filesystem;
const std::string kSource = EVADE_SOURCE_DIR;

struct LoopRun {
  LockstepResult result;
  std::string log;
};

LoopRun run_once(const std::string& name, const LockstepRun& options) {
  const config::Node root = config::load_robot_config(kSource + "/config/robot.yaml");
  const sim::Scenario scenario = sim::load_scenario(kSource + "/test/closedloop/crossing.yaml");
  const std::string path = ::testing::TempDir() + "/lockstep_" + name + ".lcmlog";
  fs::remove(path);
  ClosedLoop loop(root, scenario, options);
  LoopRun r;
  {
    bus::LogWriter log(path);
    r.result = loop.run(&log);
  }
  r.log = path;
  return r;
}

std::string bytes_of(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

TEST(Lockstep, TheSameScenarioSeedAndConfigGiveAByteIdenticalLog) {
  LockstepRun options;
  options.seed = 7;
  const LoopRun a = run_once("a", options);
  const LoopRun b = run_once("b", options);
  EXPECT_EQ(a.result.outcome, RunMonitor::kGoal);
  const std::string la = bytes_of(a.log), lb = bytes_of(b.log);
  EXPECT_GT(la.size(), 1'000'000u);
  EXPECT_TRUE(la == lb) << "logs differ: " << la.size() << " vs " << lb.size() << " bytes";
  // The premise: the seed reaches the simulated sensor, so that equal logs
  // are not equal for lack of any randomness.
  options.seed = 8;
  const LoopRun c = run_once("c", options);
  EXPECT_FALSE(bytes_of(c.log) == la);
}

TEST(Lockstep, EveryChannelOfALiveRunIsInTheLogInTimeOrder) {
  const LoopRun r = run_once("channels", LockstepRun{});
  std::set<std::string> seen;
  int64_t last = -1;
  bool ordered = true;
  bus::for_each_event(r.log, [&](const bus::LogEvent& e) {
    seen.insert(e.channel);
    ordered = ordered && e.timestamp >= last;
    last = e.timestamp;
  });
  EXPECT_TRUE(ordered);
  for (const char* ch : {"LIDAR_SCAN", "ELEVATION_MAP", "OBSTACLES", "OBSTACLE_PREDICTIONS", "ROUTE", "PLAN", "CMD_VEL",
                         "ODOMETRY", "BASE_STATUS", "SIM_TRUTH", "HEALTH"})
    EXPECT_TRUE(seen.count(ch)) << ch;
  EXPECT_FALSE(seen.count("LIDAR_POINTS"));  // left out, as run_scenario's lcm-logger does
  EXPECT_EQ(r.result.outcome, RunMonitor::kGoal);
  EXPECT_LT(r.result.sim_s, 30.0);
}

// Each PLAN that solved reports the compute time its model charged, and
// reaches the bus that long (plus the bus latency) after the ODOMETRY it
// was made from.
void expect_plans_charged(const LoopRun& r, const std::function<int64_t(const evade::plan_t&)>& expected_us) {
  const config::Node root = config::load_robot_config(kSource + "/config/robot.yaml");
  const int64_t latency = std::llround(root.section("lockstep").get<double>("bus_latency_s") * 1e6);
  std::map<int64_t, int64_t> odometry_at;  // utime -> bus time it reached the planner
  int plans = 0, iterated = 0;
  bus::for_each_event(r.log, [&](const bus::LogEvent& e) {
    if (e.channel == "ODOMETRY") {
      evade::odometry_t o;
      ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &o));
      odometry_at[o.utime] = e.timestamp;
    } else if (e.channel == "PLAN") {
      evade::plan_t p;
      ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &p));
      const bool solved = p.status != evade::plan_t::STATUS_STALE_INPUT && p.status != evade::plan_t::STATUS_NO_ROUTE &&
                          p.status != evade::plan_t::STATUS_GOAL;
      if (!solved || !odometry_at.count(p.utime)) return;  // no solve, no compute time
      EXPECT_EQ(p.solve_time_us, expected_us(p)) << "plan at " << p.utime;
      EXPECT_GE(e.timestamp - odometry_at[p.utime], p.solve_time_us + latency) << "plan at " << p.utime;
      ++plans;
      if (p.iterations > 0) ++iterated;
    }
  });
  EXPECT_GT(plans, 50);
  EXPECT_GT(iterated, 10);
}

TEST(Lockstep, ThePlannerIsChargedByItsIterations) {
  const config::Node root = config::load_robot_config(kSource + "/config/robot.yaml");
  const config::Node s = root.section("lockstep");
  const double base = s.get<double>("planner_base_s"), per = s.get<double>("planner_per_iteration_s");
  LockstepRun options;
  options.planner_compute = "iterations";
  const LoopRun r = run_once("iterations", options);
  expect_plans_charged(r, [&](const evade::plan_t& p) {
    return static_cast<int64_t>((base + per * p.iterations) * 1e6);
  });
}

TEST(Lockstep, AFixedPlannerComputeTimeIsChargedForEveryCycle) {
  const config::Node root = config::load_robot_config(kSource + "/config/robot.yaml");
  const double fixed = root.section("lockstep").get<double>("planner_fixed_s");
  LockstepRun options;
  options.planner_compute = "fixed";
  const LoopRun r = run_once("fixed", options);
  expect_plans_charged(r, [&](const evade::plan_t&) { return static_cast<int64_t>(fixed * 1e6); });
}

}  // namespace
}  // namespace evade::closedloop
