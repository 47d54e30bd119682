// A robot that stands BLOCKED beside structure must get out (issue 18
// item 9: doorways). Two scenes of the doorway family (tools/scenario-gen
// --family doorway --seed 383 and 270) where, after giving way to the
// walker coming through, the robot stood for good on 7a037e4 (both timed
// out):
// - doorway_wall_end.yaml: beside the upper wall's end, heading along its
//   face. Every turn on the spot the escape tried swung the footprint into
//   the wall's margin, so none was sent; now the turn (escape.h) goes as
//   far as it can still stop short of the margin.
// - doorway_gap_flicker.yaml: in front of the 0.62 m gap. One scan had
//   marked a cell inside the gap just before the robot's blind disc
//   reached it, and the disc remembered it, closing the gap to the
//   footprint; no escape turn was sent. Now a cell enters the disc's
//   memory only after static_field.blind_memory_frames (2) scans in a row
//   (StaticStructure.ACellThatFlickersOn... shows the rule alone); with 1
//   the robot still stands there until the run ends.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "scene_run.h"

namespace evade::closedloop {
namespace {

void expect_through(const std::string& scene) {
  const metrics::RunMetrics m = testing::run_scene(testing::kSource + "/config/robot.yaml", "blocked_" + scene, scene);
  EXPECT_TRUE(m.reached_goal) << scene;
  EXPECT_EQ(m.collisions_at_fault, 0) << scene;
  EXPECT_TRUE(m.contacts.empty()) << scene << ": " << m.contacts.size() << " contacts";
  std::printf("[figures] %s: min clearance %.3f m, time to goal %.1f s\n", scene.c_str(), m.min_dist_m,
              m.time_to_goal_s.value_or(-1.0));
}

TEST(Blocked, ANoseAtAWallsEndTurnsOutAsFarAsItMayAndGoesThrough) { expect_through("doorway_wall_end.yaml"); }

TEST(Blocked, ACellFlickeringOnInANarrowGapIsNotRememberedThere) { expect_through("doorway_gap_flicker.yaml"); }

}  // namespace
}  // namespace evade::closedloop
