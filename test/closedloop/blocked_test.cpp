// A robot that stands BLOCKED beside structure must get out (issue 18
// item 9: doorways). Two scenes of the doorway family (tools/scenario-gen
// --family doorway --seed 383 and 270) where, after giving way to the
// walker coming through, the robot stood for good on 7a037e4 (both timed
// out):
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
#include <gtest/gtest.h>

#include "scene_run.h"

namespace evade::closedloop {
namespace {

TEST(Blocked, ANoseAtAWallsEndTurnsOutAsFarAsItMayAndGoesThrough) {
  testing::expect_clear_arrival("blocked_", "doorway_wall_end.yaml");
}

TEST(Blocked, ACellFlickeringOnInANarrowGapIsNotRememberedThere) {
  testing::expect_clear_arrival("blocked_", "doorway_gap_flicker.yaml");
}

}  // namespace
}  // namespace evade::closedloop
