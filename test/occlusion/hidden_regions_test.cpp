// The region hidden behind a box seen from a point (lib/mapping/hidden_regions.h).
#include "mapping/hidden_regions.h"

#include <gtest/gtest.h>

#include <cmath>

namespace evade::mapping {
namespace {

// A 10 x 10 m map at 0.1 m with its corner at (-5, -5), all ground.
ElevationLayers flat_map() {
  ElevationLayers l;
  l.reset(-5.0, -5.0, 0.1, 100, 100);
  std::fill(l.z_max.begin(), l.z_max.end(), 0.0f);
  std::fill(l.obstacle.begin(), l.obstacle.end(), int8_t(0));
  return l;
}

// Marks the cells whose centres lie in [x0, x1] x [y0, y1] as obstacle
// cells of height z.
void box(ElevationLayers* l, double x0, double x1, double y0, double y1, float z) {
  for (int r = 0; r < l->height; ++r)
    for (int c = 0; c < l->width; ++c) {
      const double x = l->origin_x + (c + 0.5) * l->resolution, y = l->origin_y + (r + 0.5) * l->resolution;
      if (x < x0 || x > x1 || y < y0 || y > y1) continue;
      l->obstacle[l->index(r, c)] = 1;
      l->z_max[l->index(r, c)] = z;
    }
}

TEST(HiddenRegions, BoxSeenFromAPointCastsItsShadow) {
  // The near face of a parked van (what the LiDAR sees of it): x in [1, 4],
  // y = 1, seen from the origin.
  ElevationLayers l = flat_map();
  box(&l, 1.0, 4.0, 1.0, 1.1, 1.8f);
  HiddenRegionParams p;
  const auto regions = hidden_regions(p, l, 0.0, 0.0);
  ASSERT_EQ(regions.size(), 1u);
  const HiddenRegion& h = regions[0];
  // The silhouette points are the face's ends (cell corners), smaller bearing first.
  EXPECT_NEAR(h.near_x[0], 4.0, 0.11);
  EXPECT_NEAR(h.near_y[0], 1.0, 0.11);
  EXPECT_NEAR(h.near_x[1], 1.0, 0.11);
  EXPECT_NEAR(h.near_y[1], 1.1, 0.11);
  // The side edges run away from the sensor, depth_m long.
  for (int i = 0; i < 2; ++i) {
    const double nx = h.near_x[i], ny = h.near_y[i], fx = h.far_x[i], fy = h.far_y[i];
    EXPECT_NEAR(std::hypot(fx - nx, fy - ny), p.depth_m, 1e-9);
    EXPECT_NEAR(std::atan2(fy, fx), std::atan2(ny, nx), 1e-9);  // on the ray from the sensor
    EXPECT_GT(std::hypot(fx, fy), std::hypot(nx, ny));
  }
  EXPECT_NEAR(h.occluder_height_m, 1.8, 1e-6);
  EXPECT_GT(h.occluder_cells, 25);
}

TEST(HiddenRegions, SmallLowOrFarObstaclesHideNoOne) {
  ElevationLayers l = flat_map();
  box(&l, 2.0, 2.4, 1.0, 1.4, 1.8f);    // a person: too narrow
  box(&l, 1.0, 4.0, -2.0, -1.9, 0.4f);  // a low wall: a person behind it is seen above it
  HiddenRegionParams p;
  EXPECT_TRUE(hidden_regions(p, l, 0.0, 0.0).empty());
  p.max_range_m = 0.5;
  box(&l, -4.0, -1.0, 3.0, 3.1, 1.8f);  // tall and wide, but beyond max_range_m
  EXPECT_TRUE(hidden_regions(p, l, 0.0, 0.0).empty());
  p.max_range_m = 8.0;
  EXPECT_EQ(hidden_regions(p, l, 0.0, 0.0).size(), 1u);
}

TEST(HiddenRegions, GapsOfTheSparseRingsDoNotSplitAnOccluder) {
  // A face seen as every other cell: one occluder within link_radius_m.
  ElevationLayers l = flat_map();
  for (int i = 0; i < 15; ++i) box(&l, 1.0 + 0.2 * i, 1.1 + 0.2 * i, 1.0, 1.1, 1.5f);
  HiddenRegionParams p;
  const auto regions = hidden_regions(p, l, 0.0, 0.0);
  ASSERT_EQ(regions.size(), 1u);
  p.link_radius_m = 0.1;  // the 8 neighbours only: every piece alone, each too narrow
  EXPECT_TRUE(hidden_regions(p, l, 0.0, 0.0).empty());
}

}  // namespace
}  // namespace evade::mapping
