#include "box_map.h"

namespace evade::planning::testing {

evade::grid_map_t box_map(const std::vector<Box>& boxes, int64_t utime, float height_m) {
  constexpr double kRes = 0.1, kOriginX = -2.0, kOriginY = -6.0;
  constexpr int kW = 120, kH = 120;
  evade::grid_map_t m{};
  m.utime = utime;
  m.origin[0] = kOriginX;
  m.origin[1] = kOriginY;
  m.resolution = kRes;
  m.width = kW;
  m.height = kH;
  m.elevation.assign(kH, std::vector<float>(kW, 0.0f));
  m.obstacle.assign(kH, std::vector<int8_t>(kW, 0));
  for (int r = 0; r < kH; ++r)
    for (int c = 0; c < kW; ++c) {
      const double x0 = kOriginX + c * kRes, y0 = kOriginY + r * kRes;
      for (const Box& b : boxes)
        if (x0 < b.x1 - 1e-9 && x0 + kRes > b.x0 + 1e-9 && y0 < b.y1 - 1e-9 && y0 + kRes > b.y0 + 1e-9) {
          m.obstacle[r][c] = 1;
          m.elevation[r][c] = height_m;
        }
    }
  return m;
}

}  // namespace evade::planning::testing
