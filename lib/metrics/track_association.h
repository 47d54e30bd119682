// Which true obstacle each perception track is, and when: the link between
// the planner's inputs (track ids) and SIM_TRUTH (obstacle ids) that the
// reaction time needs (metrics_rules()).
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "bus/log.h"
#include "evade/sim_truth_t.hpp"

namespace evade::metrics {

// Each track's owner over time. A track can change owner: a walker's track
// that stays on the bin it walked past, two walkers whose tracks swap.
class TrackOwners {
 public:
  static constexpr int kNone = -1;
  // The obstacle `track` was at `utime` (kNone: none, or an unknown track).
  int owner(int64_t track, int64_t utime) const;
  // Every track that was `obstacle` at some time.
  std::set<int64_t> tracks_of(int obstacle) const;
  // (utime from which, owner) of a track, in time order.
  using Timeline = std::vector<std::pair<int64_t, int>>;
  std::map<int64_t, Timeline> timelines;
};

// Every track in every obstacle_list_t and prediction_list_t message of the
// log (any channel; a prediction's centre is its step 0) votes, once per
// message, for the true obstacle whose shape is nearest its centre (the
// distance to the shape's surface, 0 inside; SIM_TRUTH sample at or after
// the message's utime; ties: the lower id), or for none when that is
// farther than radius_m. Its first vote makes its owner; another owner
// takes over once it has had every vote of the track for switch_s (and
// owns the track from the first of those votes). `truth` must be sorted
// by utime.
TrackOwners associate_tracks(const std::vector<bus::LogEvent>& log, const std::vector<evade::sim_truth_t>& truth,
                             double radius_m, double switch_s);

}  // namespace evade::metrics
