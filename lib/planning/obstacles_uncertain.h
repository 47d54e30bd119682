// The obstacle module's treatment of uncertain predicted steps
// (bound_uncertain, obstacles.h): its parameters, `planner.uncertain:`.
#pragma once

#include "config/fields.h"

namespace evade::planning {

// How the planner treats a predicted step whose uncertainty is too large
// to be useful (a new track, whose velocity is not known yet, or a mover
// far into the horizon). Within reach_s: the published ellipse, or, where
// smaller, the disc the obstacle can reach from where it is now at its
// size class's maximum speed. Beyond reach_s: the ellipse of the last step
// within reach_s or certain enough, held (the planner plans again every
// cycle, long before then).
struct UncertainParams {
  bool enabled = true;               // false: every step's published ellipse as it is
  double max_sigma_m = 1.0;          // a step whose uncertainty radius (sigma) exceeds this is too uncertain
  double reach_s = 0.5;              // uncertain steps later than this hold the last step within it
  double small_max_axis_m = 0.5;     // a body (a - sigma now) at most this long is small: walker, dog, ball
  double small_max_speed_mps = 3.0;  // a small body's maximum speed (a jogger, a dog)
  double large_max_speed_mps = 5.0;  // any other's (a bike)

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("max_sigma_m", max_sigma_m, config::between(0.0, 100.0));
    v.field("reach_s", reach_s, config::between(0.0, 10.0));
    v.field("small_max_axis_m", small_max_axis_m, config::between(0.0, 100.0));
    v.field("small_max_speed_mps", small_max_speed_mps, config::between(0.0, 100.0));
    v.field("large_max_speed_mps", large_max_speed_mps, config::between(0.0, 100.0));
  }
};

}  // namespace evade::planning
