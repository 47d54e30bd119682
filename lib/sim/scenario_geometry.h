// Plane geometry of scenario outlines: the robot's footprint rectangle,
// cylinders (discs) and boxes (rotated rectangles) seen from above, their
// clearances and line-of-sight tests. Used by the scenario generator's
// validity checks (scenario_check.h).
#pragma once

#include <vector>

#include "sim/scenario.h"

namespace evade::sim::geom {

// A convex outline seen from above: a disc (radius > 0, no corners) or a
// convex polygon (corners, counter-clockwise).
struct Outline {
  std::vector<Vec2> corners;
  Vec2 centre;
  double radius = 0.0;
};

Outline rectangle(double cx, double cy, double yaw, double length, double width);
Outline disc(double cx, double cy, double radius);
// The robot's footprint at `pose`.
Outline footprint(const Pose2& pose, double length, double width);
// Obstacle `o` with its centre at (x, y) (its yaw and size from `o`).
Outline obstacle_outline(const ObstacleSpec& o, double x, double y);

// Gap between two outlines, m; negative when they overlap (for two
// polygons: -1 whatever the depth).
double clearance(const Outline& a, const Outline& b);
// Distance from a point to an outline (0 inside a polygon, negative
// inside a disc).
double point_clearance(const Vec2& p, const Outline& o);
// True if the segment a-b crosses or touches the outline.
bool segment_hits(const Vec2& a, const Vec2& b, const Outline& o);

double norm(double dx, double dy);
double distance(const Vec2& a, const Vec2& b);
double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b);

}  // namespace evade::sim::geom
