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
  Voter(const std::vector<evade::sim_truth_t>& truth, double radius_m) : truth_(truth), radius_m_(radius_m) {}

  void vote(int64_t utime, int64_t track, Vec2 centre) {
    auto it = std::lower_bound(truth_.begin(), truth_.end(), utime,
                               [](const evade::sim_truth_t& t, int64_t u) { return t.utime < u; });
    if (it == truth_.end()) return;
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (const auto& o : it->obstacles) {
      const double d = distance_to_shape(o, centre);
      if (d < best_d || (d == best_d && o.id < best)) {
        best_d = d;
        best = o.id;
      }
    }
    if (best >= 0 && best_d <= radius_m_) ++votes_[track][best];
  }

  std::map<int64_t, int> owners() const {
    std::map<int64_t, int> out;
    for (const auto& [track, by_obstacle] : votes_) {
      int best = -1, n = 0;
      for (const auto& [obstacle, count] : by_obstacle)  // ascending ids: ties keep the lower
        if (count > n) {
          n = count;
          best = obstacle;
        }
      out[track] = best;
    }
    return out;
  }

 private:
  const std::vector<evade::sim_truth_t>& truth_;
  double radius_m_;
  std::map<int64_t, std::map<int, int>> votes_;
};

}  // namespace

std::map<int64_t, int> associate_tracks(const std::vector<bus::LogEvent>& log,
                                        const std::vector<evade::sim_truth_t>& truth, double radius_m) {
  Voter voter(truth, radius_m);
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
