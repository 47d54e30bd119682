// 2D clearance between the robot's footprint rectangle and obstacle shapes,
// exact, for the metrics (SPEC: "smallest clearance between the robot
// footprint and any obstacle surface, 2D"). Negative = penetration depth
// lower bound (0 or less means a collision).
#pragma once

#include <array>

namespace evade::metrics {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

// An oriented rectangle: centre, heading, full length (along yaw), full width.
struct OrientedRect {
  Vec2 centre;
  double yaw = 0.0;
  double length = 0.0;
  double width = 0.0;
  std::array<Vec2, 4> corners() const;
};

// Signed distance from a point to a rectangle (negative inside).
double signed_distance(const OrientedRect& r, Vec2 p);
// Clearance between a rectangle and a circle (negative when they overlap).
double clearance(const OrientedRect& r, Vec2 centre, double radius);
// Clearance between two rectangles: 0 or less when they overlap.
double clearance(const OrientedRect& a, const OrientedRect& b);
// The closest points of the two shapes (for the picture).
void closest_points(const OrientedRect& r, Vec2 centre, double radius, Vec2* on_r, Vec2* on_circle);
void closest_points(const OrientedRect& a, const OrientedRect& b, Vec2* on_a, Vec2* on_b);

}  // namespace evade::metrics
