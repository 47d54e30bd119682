// A person steps out from behind a parked vehicle just before the robot
// passes (issue 23 item 4): the robot must be slow enough near the
// vehicle's front corner to stop before they reach it. Two scenes of the
// occlusion family (tools/scenario-gen --family occlusion --seed 204 and
// 218): a jogger at 3.0 m/s reaching the route 0.38 s before the robot's
// nominal arrival, a walker at 1.4 m/s 0.17 s before. With
// planner.occlusion.enabled false both were collisions at fault (the
// robot at 0.56 and 0.45 m/s into the person's side).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "scene_run.h"

namespace evade::closedloop {
namespace {

void expect_no_fault(const std::string& scene) {
  const metrics::RunMetrics m = testing::run_scene(testing::kSource + "/config/robot.yaml", "stepout_" + scene, scene);
  EXPECT_TRUE(m.reached_goal) << scene;
  EXPECT_EQ(m.collisions_at_fault, 0) << scene;
  EXPECT_TRUE(m.contacts.empty()) << scene << ": " << m.contacts.size() << " contacts";
  std::printf("[figures] %s: min clearance %.3f m, time to goal %.1f s\n", scene.c_str(), m.min_dist_m,
              m.time_to_goal_s.value_or(-1.0));
}

TEST(StepOut, AJoggerFromBehindAParkedVehicleFindsTheRobotAbleToStop) { expect_no_fault("stepout_jogger.yaml"); }

TEST(StepOut, AWalkerFromBehindAParkedVehicleFindsTheRobotAbleToStop) { expect_no_fault("stepout_walker.yaml"); }

}  // namespace
}  // namespace evade::closedloop
