// PlannerCore's static structure (static_structure.h), kept apart from the
// planning itself: the elevation maps' arrival and the field of each cycle.
#include <cmath>

#include "evade/grid_map_t.hpp"
#include "planning/input_checks.h"
#include "planning/planner_core.h"

namespace evade::planning {
namespace {

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
    static_.keep_map(m);
  });
}

void PlannerCore::update_static_field(const evade::odometry_t& odom) {
  detour_.set_field(nullptr, 0.0);
  if (!uses_field(mode_, p_)) return;
  StaticStructure::Inputs in;
  in.odometry_utime = odom.utime;
  in.predictions = predictions_ ? &*predictions_ : nullptr;
  in.observed = observed_ ? &*observed_ : nullptr;
  in.track_age_s = [&](int64_t id) { return track_age_s(id, odom.utime); };
  switch (static_.update(in)) {
    case StaticStructure::Update::kStale:
      count("static_map_stale");  // every track by its ellipse, as without the field
      return;
    case StaticStructure::Update::kInvalid:
      count("static_map_invalid");
      return;
    case StaticStructure::Update::kBuilt:
      break;
  }
  count("static_field");
  detour_.set_field(static_.field(), p_.footprint.radius);
}

}  // namespace evade::planning
