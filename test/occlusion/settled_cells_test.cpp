// Occluders from settled cells only (lib/mapping/settled_cells.h): static
// structure casts a hidden region once it has stayed put for settle_s; a
// group walking abreast, wide enough to be an occluder, does not.
#include "mapping/settled_cells.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mapping/hidden_regions.h"

namespace evade::mapping {
namespace {

constexpr int64_t kT0 = 1'000'000;
constexpr int64_t kDtUs = 100'000;  // a map per LiDAR revolution, 10 Hz

// A 10 x 10 m ground map at 0.1 m with its corner at (ox, oy) (a lattice
// point: the map follows the robot, elevation_map.cpp).
ElevationLayers flat_map(double ox = -5.0, double oy = -5.0) {
  ElevationLayers l;
  l.reset(ox, oy, 0.1, 100, 100);
  std::fill(l.z_max.begin(), l.z_max.end(), 0.0f);
  return l;
}

// Marks the cells whose centres lie in [x0, x1] x [y0, y1] as obstacle
// cells 1.8 m tall; with `every_other`, only the cells of even column.
void box(ElevationLayers* l, double x0, double x1, double y0, double y1, bool every_other = false) {
  for (int r = 0; r < l->height; ++r)
    for (int c = 0; c < l->width; ++c) {
      const double x = l->origin_x + (c + 0.5) * l->resolution, y = l->origin_y + (r + 0.5) * l->resolution;
      if (x < x0 || x > x1 || y < y0 || y > y1 || (every_other && c % 2)) continue;
      l->obstacle[l->index(r, c)] = 1;
      l->z_max[l->index(r, c)] = 1.8f;
    }
}

struct Frame {
  size_t settled = 0;      // settled cells
  size_t regions = 0;      // regions from the settled cells
  size_t regions_any = 0;  // regions from every obstacle cell
};

Frame frame(SettledCells* s, const ElevationLayers& l, int64_t utime) {
  const HiddenRegionParams p;
  std::vector<uint8_t> mask;
  s->update(l, utime, p.settle_s, p.gap_s, &mask);
  Frame f;
  for (uint8_t m : mask) f.settled += m;
  f.regions = hidden_regions(p, l, 0.0, 0.0, &mask).size();
  f.regions_any = hidden_regions(p, l, 0.0, 0.0).size();
  return f;
}

TEST(SettledCells, AParkedVanCastsARegionOnceSettled) {
  const HiddenRegionParams p;
  ASSERT_GT(p.settle_s, 0.5);
  SettledCells s;
  for (int i = 0; i <= 30; ++i) {
    // The robot drives along +x at 1 m/s: the map's corner moves with it
    // (a cell at a time), the van's near face stays where it is.
    const double ox = -5.0 + 0.1 * i;
    ElevationLayers l = flat_map(ox);
    box(&l, 1.0, 4.0, 2.0, 2.1, /*every_other=*/i % 2 == 1);  // the sparse rings: half the cells every other map
    const Frame f = frame(&s, l, kT0 + i * kDtUs);
    const double t = 0.1 * i;
    if (t < p.settle_s - 1e-9)
      EXPECT_EQ(f.regions, 0u) << "t " << t;
    else
      EXPECT_EQ(f.regions, 1u) << "t " << t;
  }
}

TEST(SettledCells, AGroupWalkingAbreastCastsNone) {
  // Three walkers abreast, 1.4 m wide across the line of sight and 0.5 m
  // deep, walking away from the sensor from 1 m at 1 m/s or 0.6 m/s.
  for (const double speed : {1.0, 0.6}) {
    SettledCells s;
    size_t regions_any = 0;
    for (int i = 0; i <= 50; ++i) {
      const double y = 1.0 + speed * 0.1 * i;
      ElevationLayers l = flat_map();
      box(&l, -0.7, 0.7, y, y + 0.5);
      const Frame f = frame(&s, l, kT0 + i * kDtUs);
      EXPECT_EQ(f.regions, 0u) << speed << " m/s, t " << 0.1 * i;
      regions_any += f.regions_any;
    }
    EXPECT_GT(regions_any, 20u) << "from every obstacle cell the group hides a region";
  }
}

TEST(SettledCells, AStandingGroupSettles) {
  SettledCells s;
  Frame f;
  for (int i = 0; i <= 20; ++i) {  // 2 s standing
    ElevationLayers l = flat_map();
    box(&l, -0.7, 0.7, 3.0, 3.5);
    f = frame(&s, l, kT0 + i * kDtUs);
  }
  EXPECT_EQ(f.regions, 1u);
}

TEST(SettledCells, AGapLongerThanGapSStartsAgain) {
  const HiddenRegionParams p;
  SettledCells s;
  ElevationLayers wall = flat_map();
  box(&wall, 1.0, 4.0, 2.0, 2.1);
  const ElevationLayers empty = flat_map();
  int64_t t = kT0;
  for (; t <= kT0 + std::llround(p.settle_s * 1e6); t += kDtUs) frame(&s, wall, t);
  EXPECT_EQ(frame(&s, wall, t).regions, 1u);
  const int64_t gap_end = t + std::llround(p.gap_s * 1e6) + kDtUs;
  for (t += kDtUs; t <= gap_end; t += kDtUs) frame(&s, empty, t);  // hidden (by a passer-by) beyond gap_s
  EXPECT_EQ(frame(&s, wall, t).regions, 0u);
  // and a map stamped before the last forgets everything
  EXPECT_EQ(frame(&s, wall, kT0).settled, 0u);
}

TEST(SettledCells, AMapWithACornerOffTheLatticeSettlesNothingAndForgets) {
  const HiddenRegionParams p;
  SettledCells s;
  ElevationLayers wall = flat_map();
  box(&wall, 1.0, 4.0, 2.0, 2.1);
  int64_t t = kT0;
  for (; t <= kT0 + std::llround(p.settle_s * 1e6); t += kDtUs) frame(&s, wall, t);
  ASSERT_GT(frame(&s, wall, t).settled, 0u);
  for (const double corner : {std::nan(""), HUGE_VAL, -1e300, 2e8}) {
    ElevationLayers far = wall;
    far.origin_x = corner;
    t += kDtUs;
    EXPECT_EQ(frame(&s, far, t).settled, 0u) << corner;
    EXPECT_EQ(s.size(), 0u) << corner;
  }
  // back on the lattice, the wall settles again from the start
  t += kDtUs;
  EXPECT_EQ(frame(&s, wall, t).settled, 0u);
  EXPECT_GT(s.size(), 0u);
}

}  // namespace
}  // namespace evade::mapping
