// The reaction time by counterfactual replay (metrics_rules()): when did
// the planner's plan first differ from the plan it would have made without
// the obstacle?
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <vector>

#include "evade/plan_t.hpp"
#include "metrics/plan_replay.h"
#include "metrics/track_association.h"

namespace evade::metrics {

struct ObstacleReaction {
  int obstacle_id = 0;
  int64_t t_enter_utime = 0;  // it entered the local map
  int64_t t_until_utime = 0;  // the last plan time a reaction counts (it left the local map, or gave up)
  std::set<int64_t> tracks;   // perception tracks that were it at some time (track_association.h)
  // utime of the first plan that differs without it: at all, and in
  // [t_enter, t_until] (the reaction)
  std::optional<int64_t> t_change_utime;
  std::optional<int64_t> t_react_utime;
};

// How well the replay with nothing removed reproduced the recorded plans.
struct ReplayCheck {
  int compared = 0;           // recorded plans matched to a replayed one (same utime, same occurrence)
  int differing = 0;          // ... farther apart than the threshold
  double max_distance_m = 0;  // largest plan_distance_m of those compared
};

// Replays the planner once with nothing removed (the reference, compared
// with `recorded` for the check), then once per obstacle with tracks, each
// of its tracks removed from the messages of the times it was the obstacle
// (`owners`), up to its first plan in [t_enter, t_until] whose
// plan_distance_m from the reference plan of the same cycle exceeds
// threshold_m (-> t_react_utime; the first such plan at any time ->
// t_change_utime). Plans are matched by utime and, for several plans from
// one odometry utime, their order.
ReplayCheck counterfactual_reactions(const PlanReplay& replay, const std::vector<evade::plan_t>& recorded,
                                     const TrackOwners& owners, double threshold_m,
                                     std::vector<ObstacleReaction>* obstacles);

}  // namespace evade::metrics
