// The turn out of a wall's margin (mode evade, static structure): the
// manoeuvre PlannerCore::escape_from_structure sends when the robot stands
// BLOCKED beside structure whose field holds every plan the solver finds.
//
// A robot that cannot reverse, standing with its nose at a wall's end or in
// a corner, has no plan better than standing: driving on lowers the
// field's h at once. It turns on the spot towards a heading that leads out
// of the structure. Where that turn would swing the footprint's corners
// into the margin, it turns as far as it can still stop short of it
// (the turn's own momentum included) and no further; from the heading
// gained the solver may find its way, or the next cycle's turn goes on.
#pragma once

#include <vector>

#include "planning/problem.h"

namespace evade::planning {

// Controls (2 N, v and omega per step) from pb's start, the robot going
// (v0, omega0) now: v braked at the limit (decel) to a stop; omega turning
// by yaw_by (rad, signed: + counter-clockwise; the way round is its sign)
// at the limits (omega_max, alpha), but each step's turn only while braking
// it at alpha would still stop it with the footprint no deeper into
// `field`'s margin than into_margin_m below min(0, h at the start); else
// the turn is braked.
std::vector<double> turn_out_controls(const Problem& pb, const ObstacleTrack& field, double yaw_by, double v0,
                                      double omega0, double into_margin_m);

}  // namespace evade::planning
