// Regions hidden from the sensor behind large obstacles (OCCLUSIONS): from
// one map's obstacle layer and the sensor's position, each occluder (obstacle
// cells linked within link_radius_m, as tall as min_height_m somewhere and
// at least min_width_m wide as seen from the sensor) casts a shadow: the
// area beyond it between the rays from the sensor through its two extreme
// points in bearing. The region is that shadow cut depth_m beyond those
// points. Anything hidden in it comes into view across one of the two side
// edges, which start at the occluder's silhouette.
#pragma once

#include <vector>

#include "mapping/elevation_map.h"

namespace evade::mapping {

struct HiddenRegion {
  double near_x[2] = {0, 0}, near_y[2] = {0, 0};  // the silhouette points (smaller bearing first)
  double far_x[2] = {0, 0}, far_y[2] = {0, 0};    // the side rays cut depth_m beyond them
  double occluder_height_m = 0;
  int occluder_cells = 0;
};

// The hidden regions of one map seen from (sensor_x, sensor_y), in a fixed
// order (by the occluder's first cell, row-major). Occluders are built from
// the obstacle cells marked 1 in `occluder_cells` (one per cell of the map:
// the settled ones, settled_cells.h), or from every obstacle cell when it
// is null.
std::vector<HiddenRegion> hidden_regions(const HiddenRegionParams& p, const ElevationLayers& layers, double sensor_x,
                                         double sensor_y, const std::vector<uint8_t>* occluder_cells = nullptr);

}  // namespace evade::mapping
