// PlannerCore's static structure (static_field.h), kept apart from the
// planning itself: the elevation maps it keeps and the distance field each
// cycle of mode evade builds from them.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "planning/input_checks.h"
#include "planning/planner_core.h"
#include "planning/static_field.h"

namespace evade::planning {
namespace {

constexpr size_t kMapsKept = 3;  // a map and the predictions made from it arrive about 1 ms apart

bool uses_field(const ModeSpec& m, const PlannerParams& p) { return m.evade_layers && p.static_field.enabled; }

}  // namespace

void PlannerCore::subscribe_static_map() {
  if (!uses_field(mode_, p_)) return;
  subscribe<evade::grid_map_t>("ELEVATION_MAP", [this](const evade::grid_map_t& m) {
    switch (arrival(now(), m.utime, std::llround(p_.static_field.map_max_age_s * 1e6))) {
      case Arrival::kLate:
        count("static_map_late");
        return;
      case Arrival::kFuture:
        count("static_map_future");
        return;
      case Arrival::kOnTime:
        break;
    }
    if (epoch_start_utime_ >= 0 && m.utime < epoch_start_utime_) {
      count("static_map_before_epoch");  // built in the old odometry frame
      return;
    }
    maps_.push_back(m);
    while (maps_.size() > kMapsKept) maps_.pop_front();
  });
}

bool PlannerCore::static_now(const evade::track_prediction_t& t, int64_t utime) const {
  if (moved_ids_.count(t.id)) return false;  // a walker turning round is slow for a moment
  if (!is_static_track(t, track_age_s(t.id, utime), p_.static_field)) return false;
  if (!observed_) return false;
  return std::any_of(observed_->obstacles.begin(), observed_->obstacles.end(),
                     [&](const evade::obstacle_t& o) { return o.id == t.id; });
}

void PlannerCore::remember_movers() {
  std::set<int64_t> now;
  if (predictions_)
    for (const auto& t : predictions_->tracks)
      if (moved_ids_.count(t.id) || std::hypot(t.vx, t.vy) > p_.static_field.max_speed_mps) now.insert(t.id);
  moved_ids_ = std::move(now);  // ids gone from the list are forgotten
}

void PlannerCore::update_static_field(const evade::odometry_t& odom) {
  static_field_.reset();
  static_ids_.clear();
  detour_.set_field(nullptr, 0.0);
  if (!uses_field(mode_, p_)) return;
  // the map of the scan the predictions come from (else the nearest in time)
  const int64_t want = predictions_ ? predictions_->utime : odom.utime;
  const evade::grid_map_t* map = nullptr;
  for (const auto& m : maps_)
    if (!map || std::llabs(m.utime - want) < std::llabs(map->utime - want)) map = &m;
  if (!map || age_us(odom.utime, map->utime) > std::llround(p_.static_field.map_max_age_s * 1e6)) {
    count("static_map_stale");  // every track by its ellipse, as without the field
    return;
  }
  std::vector<Ellipse> movers, keep;
  std::vector<int64_t> ids;
  remember_movers();
  if (predictions_) {
    const double shift_s = (map->utime - predictions_->utime) * 1e-6;
    for (const auto& t : predictions_->tracks) {
      if (!valid_track(t)) continue;
      const bool still = static_now(t, odom.utime);
      const Ellipse e{t.x[0] + (still ? 0.0 : t.vx * shift_s), t.y[0] + (still ? 0.0 : t.vy * shift_s), t.a[0], t.b[0],
                      t.theta[0]};
      (still ? keep : movers).push_back(e);
      if (still) ids.push_back(t.id);
    }
  }
  static_field_ = StaticField::build(*map, movers, keep, p_.static_field);
  if (!static_field_) {
    count("static_map_invalid");
    return;
  }
  // a static track stands for its cells only where the map holds some in
  // its ellipse (else, hidden or missing from this scan, its ellipse stays)
  // in a patch of structure: a person, a bin or a post standing alone is
  // still its ellipse (a person standing may walk off)
  for (size_t i = 0; i < ids.size(); ++i)
    if (static_field_->structure_extent(keep[i]) >= p_.static_field.min_structure_m) static_ids_.push_back(ids[i]);
  count("static_field");
  detour_.set_field(static_field_, p_.footprint.radius);
}

void PlannerCore::apply_static_field(const evade::odometry_t& odom, Problem* pb) {
  if (!static_field_) return;
  auto& obs = pb->obstacles;
  obs.erase(std::remove_if(obs.begin(), obs.end(),
                           [&](const ObstacleTrack& o) {
                             return std::find(static_ids_.begin(), static_ids_.end(), o.id) != static_ids_.end();
                           }),
            obs.end());
  obs.insert(obs.begin(), field_track(static_field_, odom.x, odom.y, pb->N, p_.constraint_decay()));
}

}  // namespace evade::planning
