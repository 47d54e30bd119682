#include "metrics/reaction.h"

#include <map>
#include <utility>

namespace evade::metrics {
namespace {

// Plans keyed by (utime, how many plans of that utime came before it): a
// stream of plans is looked up in order with next().
class PlanIndex {
 public:
  explicit PlanIndex(const std::vector<evade::plan_t>& plans) : plans_(plans) {
    std::map<int64_t, int> seen;
    for (size_t i = 0; i < plans.size(); ++i) index_[{plans[i].utime, seen[plans[i].utime]++}] = i;
  }
  // The indexed plan of the same cycle as `p`, the next plan of a stream.
  const evade::plan_t* next(const evade::plan_t& p) {
    auto it = index_.find({p.utime, stream_[p.utime]++});
    return it == index_.end() ? nullptr : &plans_[it->second];
  }

 private:
  const std::vector<evade::plan_t>& plans_;
  std::map<std::pair<int64_t, int>, size_t> index_;
  std::map<int64_t, int> stream_;
};

}  // namespace

ReplayCheck counterfactual_reactions(const PlanReplay& replay, const std::vector<evade::plan_t>& recorded,
                                     const TrackOwners& owners, double threshold_m,
                                     std::vector<ObstacleReaction>* obstacles) {
  const std::vector<evade::plan_t> reference = replay.plans();
  ReplayCheck check;
  {
    PlanIndex index(reference);
    for (const auto& r : recorded) {
      const evade::plan_t* p = index.next(r);
      if (!p) continue;
      const double d = plan_distance_m(r, *p);
      ++check.compared;
      if (d > threshold_m) ++check.differing;
      check.max_distance_m = std::max(check.max_distance_m, d);
    }
  }
  for (auto& o : *obstacles) {
    if (o.tracks.empty()) continue;
    PlanIndex index(reference);
    const auto is_it = [&](int64_t utime, int64_t id) { return owners.owner(id, utime) == o.obstacle_id; };
    replay.run(is_it, [&](const evade::plan_t& p) {
      if (p.utime > o.t_until_utime) return false;
      const evade::plan_t* ref = index.next(p);
      if (!ref || plan_distance_m(p, *ref) <= threshold_m) return true;
      if (!o.t_change_utime) o.t_change_utime = p.utime;
      if (p.utime < o.t_enter_utime) return true;
      o.t_react_utime = p.utime;
      return false;
    });
  }
  return check;
}

}  // namespace evade::metrics
