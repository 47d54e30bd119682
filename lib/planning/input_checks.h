// Checks on the planner's inputs before they touch its state (issue 20):
// timeliness on bus time with arithmetic that cannot overflow, and tracks
// that cannot be constrained against yet may be near the robot. Pure
// functions; PlannerCore applies them in planner_inputs.cpp.
#pragma once

#include <cstdint>

#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"

namespace evade::planning {

// now - utime, saturated at +-INT64_MAX instead of overflowing (a sender
// may stamp anything, INT64_MAX or INT64_MIN included).
int64_t age_us(int64_t now, int64_t utime);

enum class Arrival { kOnTime, kLate, kFuture };
// Late: stamped more than max_age_us before `now`; future: more than
// max_age_us after it (a clock that disagrees with ours; trusting it would
// keep the message fresh for as long as it claims).
Arrival arrival(int64_t now, int64_t utime, int64_t max_age_us);

// True when a track fails valid_track() (non-finite or inconsistent) and
// might be within radius_m of (x, y): its first position is within it, or
// is unknown (non-finite or missing).
bool invalid_track_near(const evade::prediction_list_t& m, double x, double y, double radius_m);
// The same for observed ellipses (valid_observed()).
bool invalid_observed_near(const evade::obstacle_list_t& m, double x, double y, double radius_m);

}  // namespace evade::planning
