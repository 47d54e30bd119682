#include "metrics/track_association.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bus/core.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "metrics/fingerprint.h"
#include "metrics/geometry.h"

namespace evade::metrics {
namespace {

double distance_to_shape(const evade::sim_obstacle_t& o, Vec2 p) {
  double d = o.shape == "box" ? signed_distance(OrientedRect{{o.x, o.y}, o.yaw, o.length, o.width}, p)
                              : std::hypot(p.x - o.x, p.y - o.y) - o.radius;
  return std::max(d, 0.0);
}

class Voter {
 public:
  Voter(const std::vector<evade::sim_truth_t>& truth, double radius_m, double switch_s)
      : truth_(truth), radius_m_(radius_m), switch_us_(std::llround(switch_s * 1e6)) {}

  void vote(int64_t utime, int64_t track, Vec2 centre) {
    auto it = std::lower_bound(truth_.begin(), truth_.end(), utime,
                               [](const evade::sim_truth_t& t, int64_t u) { return t.utime < u; });
    if (it == truth_.end()) return;
    int best = TrackOwners::kNone;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& o : it->obstacles) {
      const double d = distance_to_shape(o, centre);
      if (d < best_d || (d == best_d && o.id < best)) {
        best_d = d;
        best = o.id;
      }
    }
    if (best_d > radius_m_) best = TrackOwners::kNone;
    update(track, utime, best);
  }

  TrackOwners owners() {
    TrackOwners out;
    for (auto& [track, s] : state_) out.timelines[track] = std::move(s.timeline);
    return out;
  }

 private:
  struct State {
    TrackOwners::Timeline timeline;
    int candidate = TrackOwners::kNone;
    int64_t candidate_since = -1;  // -1: no candidate
  };

  void update(int64_t track, int64_t utime, int nearest) {
    State& s = state_[track];
    if (s.timeline.empty()) {
      s.timeline.push_back({utime, nearest});
      return;
    }
    if (nearest == s.timeline.back().second) {
      s.candidate_since = -1;
      return;
    }
    if (s.candidate_since < 0 || s.candidate != nearest) {
      s.candidate = nearest;
      s.candidate_since = utime;
    }
    if (utime - s.candidate_since >= switch_us_) {
      s.timeline.push_back({s.candidate_since, nearest});
      s.candidate_since = -1;
    }
  }

  const std::vector<evade::sim_truth_t>& truth_;
  double radius_m_;
  int64_t switch_us_;
  std::map<int64_t, State> state_;
};

}  // namespace

int TrackOwners::owner(int64_t track, int64_t utime) const {
  auto it = timelines.find(track);
  if (it == timelines.end()) return kNone;
  int who = kNone;
  for (const auto& [from, o] : it->second) {
    if (from > utime) break;
    who = o;
  }
  return who;
}

std::set<int64_t> TrackOwners::tracks_of(int obstacle) const {
  std::set<int64_t> out;
  for (const auto& [track, timeline] : timelines)
    for (const auto& [from, o] : timeline)
      if (o == obstacle) out.insert(track);
  return out;
}

TrackOwners associate_tracks(const std::vector<bus::LogEvent>& log, const std::vector<evade::sim_truth_t>& truth,
                             double radius_m, double switch_s) {
  Voter voter(truth, radius_m, switch_s);
  for (const auto& e : log) {
    evade::obstacle_list_t ol;
    evade::prediction_list_t pl;
    if (is_type<evade::obstacle_list_t>(e.data) && bus::decode(e.data.data(), e.data.size(), &ol)) {
      for (const auto& o : ol.obstacles) voter.vote(ol.utime, o.id, {o.x, o.y});
    } else if (is_type<evade::prediction_list_t>(e.data) && bus::decode(e.data.data(), e.data.size(), &pl)) {
      for (const auto& t : pl.tracks)
        if (t.horizon > 0) voter.vote(pl.utime, t.id, {t.x[0], t.y[0]});
    }
  }
  return voter.owners();
}

}  // namespace evade::metrics
