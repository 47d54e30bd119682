// A person steps out from behind a parked vehicle just before the robot
// passes (issue 23 item 4): the robot must be slow enough near the
// vehicle's front corner to stop before they reach it. Two scenes of the
// occlusion family (tools/scenario-gen --family occlusion --seed 204 and
// 218): a jogger at 3.0 m/s reaching the route 0.38 s before the robot's
// nominal arrival, a walker at 1.4 m/s 0.17 s before. With
// planner.occlusion.enabled false both were collisions at fault (the
// robot at 0.56 and 0.45 m/s into the person's side).
#include <gtest/gtest.h>

#include "scene_run.h"

namespace evade::closedloop {
namespace {

TEST(StepOut, AJoggerFromBehindAParkedVehicleFindsTheRobotAbleToStop) {
  testing::expect_clear_arrival("stepout_", "stepout_jogger.yaml");
}

TEST(StepOut, AWalkerFromBehindAParkedVehicleFindsTheRobotAbleToStop) {
  testing::expect_clear_arrival("stepout_", "stepout_walker.yaml");
}

}  // namespace
}  // namespace evade::closedloop
