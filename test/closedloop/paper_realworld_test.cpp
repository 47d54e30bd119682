// The paper's real-world test in simulation (config/scenarios/
// paper_realworld.yaml: robot profile scout2, RS-Helios, two walkers and an
// electromobile) in the lockstep closed loop, with the robot configuration
// merged as every process merges it (robot.yaml <- scout2 <- the scenario):
// for each of a few sensor-noise seeds the robot reaches the goal in time
// and never touches an obstacle (the metrics use the true footprint).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "closedloop/run_monitor.h"
#include "config/robot_profile.h"
#include "scene_run.h"

namespace evade::closedloop {
namespace {

const std::string kScenario = testing::kSource + "/config/scenarios/paper_realworld.yaml";

TEST(PaperRealworld, ReachesTheGoalWithoutContactForEverySeed) {
  const config::Node root = config::load_robot_config(testing::kSource + "/config/robot.yaml", {"", kScenario});
  ASSERT_EQ(root.provenance()->profile, "scout2");
  sim::Scenario scenario = sim::load_scenario(kScenario);
  sim::resolve_robot(&scenario, root);
  ASSERT_DOUBLE_EQ(scenario.footprint_length, 0.93);
  ASSERT_EQ(scenario.lidar.model, "rs_helios");
  for (const uint64_t seed : {1u, 2u, 3u}) {
    LockstepRun options;
    options.seed = seed;
    options.quiet = true;
    const testing::ScoredRun run = testing::run_scored(
        root, scenario, options, "paper_realworld_" + std::to_string(::getpid()) + "_" + std::to_string(seed));
    const LockstepResult& r = run.result;
    const metrics::RunMetrics& m = run.metrics;
    EXPECT_EQ(r.outcome, RunMonitor::kGoal) << "seed " << seed << ": timed out at " << r.sim_s << " s";
    EXPECT_TRUE(m.reached_goal) << "seed " << seed;
    EXPECT_TRUE(m.contacts.empty()) << "seed " << seed << ": " << m.contacts.size() << " contacts";
    std::printf("[figures] paper_realworld seed %llu: min clearance %.3f m, time to goal %.1f s\n",
                static_cast<unsigned long long>(seed), m.min_dist_m, m.time_to_goal_s.value_or(-1.0));
  }
}

}  // namespace
}  // namespace evade::closedloop
