// The turn on the spot of the planner's escapes (mode evade): the escape
// turn out of d_safe (PlannerCore::escape_turn) and the turn out of a
// wall's margin that PlannerCore::escape_from_structure sends when the
// robot stands BLOCKED beside structure whose field holds every plan the
// solver finds.
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

// Controls (2 N, v and omega per step) of a turn on the spot from pb's
// start: v as in `brake` (2 N braking controls; their omega is not used),
// omega from omega0 turning by yaw_by (rad, signed: + counter-clockwise;
// the way round is its sign) at the limits (omega_max, alpha). With a
// `field`, each step's turn goes on only while braking it at alpha would
// still stop it with the footprint no deeper into the field's margin than
// into_margin_m below min(0, h at the start); else the turn is braked.
// Every step's turn keeps within pb's omega_lo/omega_hi where it can (a
// step at alpha from the last).
std::vector<double> turn_on_the_spot(const Problem& pb, double yaw_by, const std::vector<double>& brake, double omega0,
                                     const ObstacleTrack* field = nullptr, double into_margin_m = 0.0);

}  // namespace evade::planning
