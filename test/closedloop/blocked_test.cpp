// A robot that stands BLOCKED beside structure must get out (issue 18
// item 9: doorways). Three scenes of the doorway family (tools/scenario-gen
// --family doorway --seed 383, 270 and 242) where, after giving way to the
// walker coming through, the robot stood for good on 7a037e4 (all three
// timed out; doorway_wall_face.yaml also on ecefc41):
// - doorway_wall_end.yaml: beside the upper wall's end, heading along its
//   face. Once the escape's turn on the spot had turned a little, the rest
//   of it would have swung the footprint into the wall's margin either way
//   round, so it was refused and the solver turned back; now the turn
//   (escape.h) goes as far as it can still stop short of the margin.
// - doorway_gap_flicker.yaml: in front of the 0.62 m gap. One scan had
//   marked a cell inside the gap just before the robot's blind disc
//   reached it, and the disc remembered it, closing the gap to the
//   footprint; no escape turn was sent. Now a cell enters the disc's
//   memory only after static_field.blind_memory_frames (2) scans in a row
//   (StaticStructure.ACellThatFlickersOn... shows the rule alone); with 1
//   the robot still stands there until the run ends.
// - doorway_wall_face.yaml: nose at the upper wall's face beside its end,
//   0.005 m from the margin. The solver's plan creeps (0.01 m/s) and
//   promises 0.12 m by the horizon's end, made again every cycle: taken
//   for headway, it kept the escape from turning. Now a plan still within
//   escape.min_progress_m halfway through the horizon is no headway where
//   the way straight ahead is closed (planner_static.cpp). The walker
//   walks into the standing robot at 16 s; the metrics find it not at
//   fault, so that contact is allowed.
#include <gtest/gtest.h>

#include "scene_run.h"

namespace evade::closedloop {
namespace {

// Since passive safety takes a walker at the speed it walked lately
// (2026-12-01), the robot waits slowed (0.03 m/s, backing off) while the
// walker comes through, and the walker, scripted through its place,
// brushes it: a contact not at fault.
TEST(Blocked, ANoseAtAWallsEndTurnsOutAsFarAsItMayAndGoesThrough) {
  testing::expect_clear_arrival("blocked_", "doorway_wall_end.yaml", testing::Contacts::kNotAtFaultOnly);
}

TEST(Blocked, ACellFlickeringOnInANarrowGapIsNotRememberedThere) {
  testing::expect_clear_arrival("blocked_", "doorway_gap_flicker.yaml");
}

TEST(Blocked, ACreepingPlanIntoAWallsFaceIsNoHeadway) {
  testing::expect_clear_arrival("blocked_", "doorway_wall_face.yaml", testing::Contacts::kNotAtFaultOnly);
}

}  // namespace
}  // namespace evade::closedloop
