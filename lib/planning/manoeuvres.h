// Open-loop manoeuvres that mode evade's recovery solves from or weighs
// when the hard problem fails: 2N controls in the Problem's layout, from
// the measured speed pb.v_prev, at pb's limits; `side` +1 turns left, -1
// right. The recovery chain tries both as candidates (planner_recovery.cpp),
// the one fallback starts its solve from the dashes (fallback.h).
#pragma once

#include <vector>

#include "planning/problem.h"

namespace evade::planning {

// The measured speed held, turning at the turn-rate limit to one side for
// the first half of the horizon, then back: a swerve round what is ahead.
std::vector<double> swerve_controls(const Problem& pb, double side);

// Accelerating at the limit (up to v_max) while turning at the limit for
// the first half of the horizon, then straight on: getting away to one
// side, where from rest a swerve at the measured speed only turns on the
// spot.
std::vector<double> dash_controls(const Problem& pb, double side);

// Pulling over: onto the lane `offset` m to one side of the reference's
// line (its first point and heading), by pure pursuit, and standing `ahead`
// m further along it, at the limits (the turn, the braking). The lane is
// the reference's, not the robot's: chosen again next cycle, it is the
// same lane. Where a mover comes down the robot's lane and no plan passes
// it, getting out of its way and standing beats standing in it.
std::vector<double> pull_over_controls(const Problem& pb, double side, double offset, double ahead);

}  // namespace evade::planning
