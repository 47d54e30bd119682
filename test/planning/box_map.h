// The ELEVATION_MAP of boxes standing in the world, as the elevation map
// marks them, for the static-structure tests: 0.1 m cells over
// [-2, 10] x [-6, 6] m (odometry frame), every cell a box overlaps an
// obstacle cell of elevation `height_m`, every other cell free at 0.
#pragma once

#include <cstdint>
#include <vector>

#include "evade/grid_map_t.hpp"

namespace evade::planning::testing {

// A box [x0, x1] x [y0, y1] (m).
struct Box {
  double x0, x1, y0, y1;
};

evade::grid_map_t box_map(const std::vector<Box>& boxes, int64_t utime, float height_m);

}  // namespace evade::planning::testing
