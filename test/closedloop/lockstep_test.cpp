// The lockstep closed loop as a whole: the stack runs a short scenario in
// simulated time, reproducibly, and charges the planner's compute time
// the way its model says.
#include <gtest/gtest.h>

#include <algorithm>
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
#include "evade/prediction_list_t.hpp"
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
  for (const char* ch : {"LIDAR_SCAN", "ELEVATION_MAP", "OCCLUSIONS", "OBSTACLES", "OBSTACLE_PREDICTIONS", "ROUTE",
                         "PLAN", "CMD_VEL", "ODOMETRY", "BASE_STATUS", "SIM_TRUTH", "HEALTH"})
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
  expect_plans_charged(r,
                       [&](const evade::plan_t& p) { return static_cast<int64_t>((base + per * p.iterations) * 1e6); });
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

namespace evade::closedloop {
namespace {

// bus time a PLAN reached the bus minus the time its cycle was triggered
// (the later of the arrivals of the ODOMETRY it starts from and of the
// prediction list it was made from), for every plan that solved; and its
// charge.
struct PlanLag {
  int64_t lag_us;
  int64_t charged_us;
};
std::vector<PlanLag> plan_lags(const LoopRun& r) {
  std::map<int64_t, int64_t> odometry_at, predictions_at;
  std::vector<PlanLag> lags;
  bus::for_each_event(r.log, [&](const bus::LogEvent& e) {
    if (e.channel == "ODOMETRY") {
      evade::odometry_t o;
      if (bus::decode(e.data.data(), e.data.size(), &o)) odometry_at[o.utime] = e.timestamp;
    } else if (e.channel == "OBSTACLE_PREDICTIONS") {
      evade::prediction_list_t m;
      if (bus::decode(e.data.data(), e.data.size(), &m)) predictions_at.emplace(m.utime, e.timestamp);
    } else if (e.channel == "PLAN") {
      evade::plan_t p;
      if (!bus::decode(e.data.data(), e.data.size(), &p) || !odometry_at.count(p.utime) || p.solve_time_us <= 0) return;
      if (p.status == evade::plan_t::STATUS_STALE_INPUT || p.status == evade::plan_t::STATUS_NO_ROUTE ||
          p.status == evade::plan_t::STATUS_GOAL)
        return;
      int64_t triggered = odometry_at[p.utime];
      auto list = predictions_at.find(p.predictions_utime);
      if (list != predictions_at.end()) triggered = std::max(triggered, list->second);
      lags.push_back({e.timestamp - triggered, p.solve_time_us});
    }
  });
  return lags;
}

// One core shared with nine always-runnable threads: every callback gets at
// most a tenth of a core, so every plan takes at least ten times its charge.
TEST(Lockstep, ALoadedComputerStretchesEveryPlan) {
  LockstepRun own;
  own.planner_compute = "fixed";
  own.cpu_cores = 0;  // a core per process
  LockstepRun loaded = own;
  loaded.cpu_cores = 1;
  loaded.background_load_cores = 9;
  const std::vector<PlanLag> free_lags = plan_lags(run_once("own_cores", own));
  const std::vector<PlanLag> loaded_lags = plan_lags(run_once("loaded", loaded));
  ASSERT_GT(free_lags.size(), 50u);
  ASSERT_GT(loaded_lags.size(), 20u);
  double free_mean = 0;
  for (const PlanLag& l : free_lags) free_mean += static_cast<double>(l.lag_us - l.charged_us);
  free_mean /= static_cast<double>(free_lags.size());
  EXPECT_LT(free_mean, 1000.0);  // on a core of its own a plan leaves about when its charge has passed
  for (const PlanLag& l : loaded_lags) EXPECT_GE(l.lag_us, 10 * l.charged_us);
}

// Profiling reads a clock around every callback but changes nothing in the
// run, and gives samples to calibrate the costs from.
TEST(Lockstep, ProfilingFillsSamplesAndLeavesTheLogAsItIs) {
  LockstepRun plain;
  plain.seed = 3;
  LockstepRun profiled = plain;
  double fake_clock = 0.0;
  profiled.cpu_clock = [&fake_clock] { return fake_clock += 1e-6; };
  const LoopRun a = run_once("unprofiled", plain);
  const LoopRun b = run_once("profiled", profiled);
  EXPECT_TRUE(bytes_of(a.log) == bytes_of(b.log));
  EXPECT_TRUE(a.result.processes.at("planner").samples.empty());
  for (const char* p : {"sim", "lidar_driver", "elevation_map", "tracker", "predictor", "planner", "base_driver"})
    EXPECT_GT(b.result.processes.at(p).samples.size(), 10u) << p;
  EXPECT_GT(b.result.processes.at("planner").plan_samples.size(), 50u);
}

}  // namespace
}  // namespace evade::closedloop

#include "closedloop/lockstep_params.h"

namespace evade::closedloop {
namespace {

// robot.yaml with one line replaced; the error LockstepParams gives (empty: none).
std::string lockstep_error(const std::string& from, const std::string& to) {
  std::string text = bytes_of(kSource + "/config/robot.yaml");
  const size_t at = text.find(from);
  if (at == std::string::npos) return "premise: '" + from + "' not in robot.yaml";
  text.replace(at, from.size(), to);
  try {
    LockstepParams::from_config(config::load_string(text, "robot.yaml"));
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Lockstep, TheSharedCoresAndTheSimulatorsCostsAreReadStrictly) {
  EXPECT_EQ(lockstep_error("  cpu_cores: 2 ", "  cpu_cores: 2 "), "");
  EXPECT_NE(lockstep_error("  cpu_cores: 2 ", "  cpu_cores: -1 ").find("key 'lockstep.cpu_cores'"), std::string::npos);
  EXPECT_NE(lockstep_error("  background_load_cores: 0.0 ", "  background_load_cores: -0.5 ")
                .find("key 'lockstep.background_load_cores'"),
            std::string::npos);
  EXPECT_NE(lockstep_error("packet_s: 0.0000473}", "packet_s: 0.0000473, publish_s: 0.001}").find("publish_s"),
            std::string::npos);
}

}  // namespace
}  // namespace evade::closedloop
