#include "planning/static_structure.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "planning/input_checks.h"
#include "planning/obstacles.h"

namespace evade::planning {

void StaticStructure::keep_map(const evade::grid_map_t& m) {
  maps_.push_back(m);
  while (maps_.size() > kMapsKept) maps_.pop_front();
}

void StaticStructure::clear() {
  maps_.clear();
  field_.reset();
  static_ids_.clear();
}

const evade::grid_map_t* StaticStructure::nearest_map(int64_t utime) const {
  const evade::grid_map_t* map = nullptr;
  for (const auto& m : maps_)
    if (!map || std::llabs(m.utime - utime) < std::llabs(map->utime - utime)) map = &m;
  return map;
}

bool StaticStructure::static_now(const evade::track_prediction_t& t, const Inputs& in) const {
  if (!is_static_track(t, in.track_age_s ? in.track_age_s(t.id) : 0.0, p_)) return false;
  if (!in.observed) return false;
  return std::any_of(in.observed->obstacles.begin(), in.observed->obstacles.end(),
                     [&](const evade::obstacle_t& o) { return o.id == t.id; });
}

StaticStructure::Update StaticStructure::update(const Inputs& in) {
  field_.reset();
  static_ids_.clear();
  // the map of the scan the predictions come from (else the nearest in time)
  const evade::grid_map_t* map = nearest_map(in.predictions ? in.predictions->utime : in.odometry_utime);
  if (!map || age_us(in.odometry_utime, map->utime) > std::llround(p_.map_max_age_s * 1e6)) return Update::kStale;
  std::vector<Ellipse> movers, keep;
  std::vector<int64_t> ids;
  if (in.predictions) {
    const double shift_s = (map->utime - in.predictions->utime) * 1e-6;
    for (const auto& t : in.predictions->tracks) {
      if (!valid_track(t)) continue;
      const bool still = static_now(t, in);
      const Ellipse e{t.x[0] + (still ? 0.0 : t.vx * shift_s), t.y[0] + (still ? 0.0 : t.vy * shift_s), t.a[0], t.b[0],
                      t.theta[0]};
      (still ? keep : movers).push_back(e);
      if (still) ids.push_back(t.id);
    }
  }
  field_ = StaticField::build(*map, movers, keep, p_);
  if (!field_) return Update::kInvalid;
  // a static track stands for its cells only where this map holds some of
  // a structure patch in its ellipse (else, hidden, missing from this scan
  // or standing alone, its ellipse stays)
  for (size_t i = 0; i < ids.size(); ++i)
    if (field_->structure_extent(keep[i]) > 0.0) static_ids_.push_back(ids[i]);
  std::sort(static_ids_.begin(), static_ids_.end());
  return Update::kBuilt;
}

bool StaticStructure::stands_for(int64_t id) const {
  return std::binary_search(static_ids_.begin(), static_ids_.end(), id);
}

void StaticStructure::apply(double x0, double y0, double decay, Problem* pb) const {
  if (!field_) return;
  auto& obs = pb->obstacles;
  obs.erase(std::remove_if(obs.begin(), obs.end(), [&](const ObstacleTrack& o) { return stands_for(o.id); }),
            obs.end());
  double gx, gy;
  if (field_->distance(x0, y0, &gx, &gy) >= p_.max_distance_m - 1e-3) return;  // flat here
  obs.insert(obs.begin(), field_track(field_, x0, y0, pb->N, decay));
}

}  // namespace evade::planning
