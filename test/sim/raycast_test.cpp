// Ray casting against analytic answers.
#include "sim/raycast.h"

#include <gtest/gtest.h>

#include <cmath>

namespace evade::sim {
namespace {

constexpr double kTol = 1e-12;

Ray ray(double ox, double oy, double oz, double dx, double dy, double dz) {
  double n = std::sqrt(dx * dx + dy * dy + dz * dz);
  return Ray{Vec3{ox, oy, oz}, Vec3{dx / n, dy / n, dz / n}};
}

TEST(Raycast, GroundPlane) {
  double el = -15.0 * M_PI / 180.0;
  Ray r = ray(0, 0, 0.5, std::cos(el), 0, std::sin(el));
  EXPECT_NEAR(hit_ground(r), 0.5 / std::sin(15.0 * M_PI / 180.0), kTol);
  EXPECT_EQ(hit_ground(ray(0, 0, 0.5, 1, 0, 0)), kNoHit);    // horizontal
  EXPECT_EQ(hit_ground(ray(0, 0, 0.5, 1, 0, 0.1)), kNoHit);  // upward
}

TEST(Raycast, CylinderSide) {
  EXPECT_NEAR(hit_cylinder(ray(0, 0, 0.5, 1, 0, 0), 5, 0, 0.25, 1.0), 4.75, kTol);
  EXPECT_NEAR(hit_cylinder(ray(0, 0.1, 0.5, 1, 0, 0), 5, 0, 0.25, 1.0), 5.0 - std::sqrt(0.0625 - 0.01), kTol);
  // Along -y from the far side, from a rotated origin.
  EXPECT_NEAR(hit_cylinder(ray(3, 7, 0.2, 0, -1, 0), 3, 2, 0.5, 1.0), 4.5, kTol);
  // Passing beside it.
  EXPECT_EQ(hit_cylinder(ray(0, 0.26, 0.5, 1, 0, 0), 5, 0, 0.25, 1.0), kNoHit);
  // Behind the origin.
  EXPECT_EQ(hit_cylinder(ray(0, 0, 0.5, -1, 0, 0), 5, 0, 0.25, 1.0), kNoHit);
}

TEST(Raycast, CylinderHeightIsFinite) {
  // Sensor at 0.5 m, cylinder 0.4 m tall: a horizontal ray passes over it.
  EXPECT_EQ(hit_cylinder(ray(0, 0, 0.5, 1, 0, 0), 5, 0, 0.25, 0.4), kNoHit);
  // A ray aimed at the centre of the top disc hits the top.
  EXPECT_NEAR(hit_cylinder(ray(0, 0, 2.0, 5, 0, -1.0), 5, 0, 0.25, 1.0), std::sqrt(25.0 + 1.0), kTol);
  // A ray entering the side below the top: x = 4.75 at z = 2 - 4.75 / 5 * 1.8 = 0.29.
  double t = hit_cylinder(ray(0, 0, 2.0, 5, 0, -1.8), 5, 0, 0.25, 1.0);
  EXPECT_NEAR(t, 4.75 * std::sqrt(25.0 + 1.8 * 1.8) / 5.0, kTol);
}

TEST(Raycast, CylinderFromInsideHitsItsWall) {
  EXPECT_NEAR(hit_cylinder(ray(5, 0, 0.5, 1, 0, 0), 5, 0, 0.25, 1.0), 0.25, kTol);
}

TEST(Raycast, BoxAxisAligned) {
  EXPECT_NEAR(hit_box(ray(0, 0, 0.5, 1, 0, 0), 4, 0, 0, 2, 1, 1), 3.0, kTol);
  EXPECT_NEAR(hit_box(ray(4, -5, 0.5, 0, 1, 0), 4, 0, 0, 2, 1, 1), 4.5, kTol);
  EXPECT_EQ(hit_box(ray(0, 0.6, 0.5, 1, 0, 0), 4, 0, 0, 2, 1, 1), kNoHit);
  EXPECT_EQ(hit_box(ray(0, 0, 1.2, 1, 0, 0), 4, 0, 0, 2, 1, 1), kNoHit);  // over the top
  // Down onto the top face at (4, 0, 1) from (0, 0, 3).
  EXPECT_NEAR(hit_box(ray(0, 0, 3, 4, 0, -2), 4, 0, 0, 2, 1, 1), std::sqrt(20.0), kTol);
}

TEST(Raycast, BoxRotated) {
  // 2 x 2 box turned 45 deg: its corner points at the origin, sqrt(2) from the centre.
  const double q = M_PI / 4;
  EXPECT_NEAR(hit_box(ray(0, 0, 0.5, 1, 0, 0), 4, 0, q, 2, 2, 1), 4.0 - std::sqrt(2.0), kTol);
  // 0.1 m off-axis the 45-degree face is 0.1 m farther.
  EXPECT_NEAR(hit_box(ray(0, 0.1, 0.5, 1, 0, 0), 4, 0, q, 2, 2, 1), 4.0 - std::sqrt(2.0) + 0.1, 1e-9);
  EXPECT_NEAR(hit_box(ray(0, -0.1, 0.5, 1, 0, 0), 4, 0, q, 2, 2, 1), 4.0 - std::sqrt(2.0) + 0.1, 1e-9);
  // A long thin box turned 90 deg blocks the x axis with its long side.
  EXPECT_NEAR(hit_box(ray(0, 1.5, 0.5, 1, 0, 0), 4, 0, M_PI / 2, 4, 0.5, 1), 3.75, 1e-9);
}

TEST(Raycast, BoxFromInsideHitsItsWall) { EXPECT_NEAR(hit_box(ray(4, 0, 0.5, 1, 0, 0), 4, 0, 0, 2, 1, 1), 1.0, kTol); }

TEST(Raycast, CastTakesTheNearestWithinRange) {
  std::vector<Solid> solids(2);
  solids[0] = Solid{Shape::kCylinder, 8, 0, 0, 0.5, 0, 0, 1};
  solids[1] = Solid{Shape::kBox, 4, 0, 0, 0, 1, 1, 1};
  EXPECT_NEAR(cast(ray(0, 0, 0.5, 1, 0, 0), solids, 100.0), 3.5, kTol);
  // Ground only, with a range limit.
  double el = -1.0 * M_PI / 180.0;
  Ray r = ray(0, 0, 0.5, 0, std::cos(el), std::sin(el));
  EXPECT_NEAR(cast(r, {}, 100.0), 0.5 / std::sin(1.0 * M_PI / 180.0), 1e-9);  // 28.6 m
  EXPECT_EQ(cast(r, {}, 20.0), kNoHit);
  EXPECT_NEAR(cast(ray(0, 0, 0.5, 1, 0, 0.01), solids, 100.0), 3.5 * std::sqrt(1.0 + 1e-4), kTol);  // slightly up
  EXPECT_EQ(cast(ray(0, 0, 0.5, -1, 0, 0.01), solids, 100.0), kNoHit);                              // sky
}

}  // namespace
}  // namespace evade::sim
