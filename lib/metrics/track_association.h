// Which true obstacle each perception track is: the link between the
// planner's inputs (track ids) and SIM_TRUTH (obstacle ids) that the
// reaction time needs (metrics_rules()).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "bus/log.h"
#include "evade/sim_truth_t.hpp"

namespace evade::metrics {

// Every track in every obstacle_list_t and prediction_list_t message of the
// log (any channel; a prediction's centre is its step 0) votes, once per
// message, for the true obstacle whose shape is nearest its centre (the
// distance to the shape's surface, 0 inside; SIM_TRUTH sample at or after
// the message's utime), if that is within radius_m. A track belongs to the
// obstacle with the most votes over its life (ties: the lower obstacle id);
// a track that never came within radius_m of any obstacle belongs to none.
// `truth` must be sorted by utime. Returns track id -> obstacle id.
std::map<int64_t, int> associate_tracks(const std::vector<bus::LogEvent>& log,
                                        const std::vector<evade::sim_truth_t>& truth, double radius_m);

}  // namespace evade::metrics
