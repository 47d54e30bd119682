// Closed-loop tests' shared runner: one scene in the lockstep closed loop
// with config/robot.yaml (or a copy of it with some lines replaced), scored
// by the metrics against the true footprint.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bus/log.h"
#include "closedloop/closed_loop.h"
#include "closedloop/run_monitor.h"
#include "config/config.h"
#include "metrics/run_metrics.h"
#include "sim/scenario.h"

namespace evade::closedloop::testing {

inline const std::string kSource = EVADE_SOURCE_DIR;

// config/robot.yaml with each `from` replaced by its `to` (each must occur),
// written to the test's temporary directory as NAME.yaml.
inline std::string config_with(const std::vector<std::pair<std::string, std::string>>& edits, const std::string& name) {
  std::ifstream in(kSource + "/config/robot.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  for (const auto& [from, to] : edits) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  const std::string path = ::testing::TempDir() + "/" + name + ".yaml";
  std::ofstream(path) << text;
  return path;
}

// One lockstep run of `scenario` with `root`'s configuration, logged to
// NAME.lcmlog in the test's temporary directory, scored by the metrics;
// the log is removed afterwards.
struct ScoredRun {
  LockstepResult result;
  metrics::RunMetrics metrics;
};
inline ScoredRun run_scored(const config::Node& root, const sim::Scenario& scenario, const LockstepRun& options,
                            const std::string& name) {
  const std::string log_path = ::testing::TempDir() + "/" + name + ".lcmlog";
  std::filesystem::remove(log_path);
  ClosedLoop loop(root, scenario, options);
  ScoredRun r;
  {
    bus::LogWriter log(log_path);
    r.result = loop.run(&log);
  }
  r.metrics =
      metrics::compute_metrics(bus::read_log(log_path), metrics::MetricsParams::from_config(root.section("metrics")));
  std::filesystem::remove(log_path);
  return r;
}

// The scene test/closedloop/SCENE run once (the scenario's own sensor seed)
// with the configuration at config_path; NAME names its log.
inline metrics::RunMetrics run_scene(const std::string& config_path, const std::string& name,
                                     const std::string& scene) {
  const config::Node root = config::load_robot_config(config_path);
  LockstepRun options;
  options.quiet = true;
  return run_scored(root, sim::load_scenario(kSource + "/test/closedloop/" + scene), options, name).metrics;
}

// Which contacts a scene test allows: none at all, or only those the
// metrics find the robot not at fault for (a walker scripted through the
// robot's place walks into it while it stands or gives way).
enum class Contacts { kNone, kNotAtFaultOnly };

// The scene test/closedloop/SCENE with config/robot.yaml (its log named
// PREFIX + SCENE) must reach the goal with no contact at fault and, with
// Contacts::kNone, none at all; prints its least clearance, contacts and
// time to the goal.
inline void expect_clear_arrival(const std::string& prefix, const std::string& scene,
                                 Contacts allowed = Contacts::kNone) {
  const metrics::RunMetrics m = run_scene(kSource + "/config/robot.yaml", prefix + scene, scene);
  EXPECT_TRUE(m.reached_goal) << scene;
  EXPECT_EQ(m.collisions_at_fault, 0) << scene;
  if (allowed == Contacts::kNone) {
    EXPECT_TRUE(m.contacts.empty()) << scene << ": " << m.contacts.size() << " contacts";
  }
  std::printf("[figures] %s: min clearance %.3f m, %zu contacts, time to goal %.1f s\n", scene.c_str(), m.min_dist_m,
              m.contacts.size(), m.time_to_goal_s.value_or(-1.0));
}

}  // namespace evade::closedloop::testing
