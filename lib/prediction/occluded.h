// Tracks that leave the field of view behind an occluder (OCCLUSIONS,
// lib/mapping/hidden_regions.h). A track missing from the obstacle list
// whose last seen centre lies inside a hidden region is kept past
// coast_max_s: it may stand or walk behind the occluder. What is known of
// it is where it was last seen and how fast it can go, so it is published
// there with both axes grown by max_speed_mps times the time since it was
// last seen (at each step of the horizon, that time at the step), with no
// cap. It is dropped once its last centre is in view (the regions no longer
// hold it: had it stayed, it would be seen), once it has been unseen for
// max_s, or once it could no longer reach the sensor's position within
// the horizon at max_speed_mps. Only a mover is kept so: a track whose
// speed estimate is below min_speed_mps (a piece of the occluder itself,
// which the tracker may tile and lose inside its own shadow) coasts for
// coast_max_s like one that vanishes in plain view.
#pragma once

#include <cstdint>

#include "config/fields.h"
#include "evade/hidden_region_list_t.hpp"
#include "evade/track_prediction_t.hpp"

namespace evade::prediction {

struct OccludedParams {
  bool enabled = false;        // keep tracks that vanish inside a hidden region
  double max_speed_mps = 1.6;  // how fast something hidden may move: a walking person
  double max_s = 3.0;          // longest time a hidden track is kept
  double min_speed_mps = 0.3;  // a track slower than this is not kept hidden (a piece of the occluder)
  double max_age_s = 0.3;      // OCCLUSIONS this much older or newer than the obstacle list are not used

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("max_speed_mps", max_speed_mps, config::between(0.0, 20.0));
    v.field("max_s", max_s, config::between(0.0, 60.0));
    v.field("min_speed_mps", min_speed_mps, config::between(0.0, 20.0));
    v.field("max_age_s", max_age_s, config::positive());
  }
};

// Whether (x, y) lies inside the region's quadrilateral near[0], near[1],
// far[1], far[0].
bool inside(const evade::hidden_region_t& r, double x, double y);

// Whether a track last seen at (x, y) with semi-major axis a, moving at
// speed_mps (its estimate), unseen for unseen_s, is kept as hidden by
// `regions`, its prediction reaching horizon_s ahead.
bool keep_hidden(const OccludedParams& p, const evade::hidden_region_list_t& regions, double x, double y, double a,
                 double speed_mps, double unseen_s, double horizon_s);

// The published prediction of such a track: its last seen ellipse held,
// both axes grown by max_speed_mps (unseen_s + k dt), velocity zero.
void hidden_prediction(const OccludedParams& p, int64_t id, double x, double y, double a, double b, double theta,
                       double unseen_s, int steps, double dt, evade::track_prediction_t* out);

}  // namespace evade::prediction
