// The parameters of the hidden regions (hidden_regions.h), section
// `elevation_map.hidden_regions` of config/robot.yaml.
#pragma once

#include "config/fields.h"

namespace evade::mapping {

struct HiddenRegionParams {
  bool enabled = true;          // publish OCCLUSIONS
  double min_height_m = 0.6;    // an occluder's highest cell: above the sensor, so it blocks the level beams
  double min_width_m = 1.0;     // an occluder's width across the line of sight (a person is narrower)
  double link_radius_m = 0.25;  // obstacle cells this close belong to one occluder (the sparse rings leave gaps)
  double depth_m = 4.0;         // the shadow's side edges run this far beyond the silhouette
  double max_range_m = 8.0;     // occluders farther from the sensor are left out
  double settle_s = 1.5;        // an occluder's cells have been obstacles this long (walkers never settle)
  double gap_s = 0.3;           // a cell missed in maps for longer than this starts settling again

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("min_height_m", min_height_m, config::between(0.0, 10.0));
    v.field("min_width_m", min_width_m, config::between(0.0, 100.0));
    v.field("link_radius_m", link_radius_m, config::between(0.0, 2.0));
    v.field("depth_m", depth_m, config::between(0.1, 100.0));
    v.field("max_range_m", max_range_m, config::between(0.1, 1000.0));
    v.field("settle_s", settle_s, config::between(0.0, 60.0));
    v.field("gap_s", gap_s, config::between(0.0, 60.0));
  }
};

}  // namespace evade::mapping
