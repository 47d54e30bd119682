// Ray casting against the simulated world: the ground plane z = 0, vertical
// cylinders standing on the ground (finite height, flat top) and boxes
// standing on the ground with a yaw. Each function returns the distance
// along a unit-direction ray to the first surface hit, or +infinity.
#pragma once

#include <limits>
#include <vector>

#include "sim/scenario.h"

namespace evade::sim {

inline constexpr double kNoHit = std::numeric_limits<double>::infinity();

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

struct Ray {
  Vec3 origin;
  Vec3 dir;  // unit length
};

// A solid at one instant (shape and size from the scenario, pose from its motion).
struct Solid {
  Shape shape = Shape::kCylinder;
  double x = 0.0, y = 0.0, yaw = 0.0;
  double radius = 0.0;               // cylinders
  double length = 0.0, width = 0.0;  // boxes
  double height = 0.0;               // both, z in [0, height]
};

double hit_ground(const Ray& r);
double hit_cylinder(const Ray& r, double cx, double cy, double radius, double height);
double hit_box(const Ray& r, double cx, double cy, double yaw, double length, double width, double height);
double hit_solid(const Ray& r, const Solid& s);

// Nearest hit over the ground and every solid; kNoHit if none within max_range_m.
double cast(const Ray& r, const std::vector<Solid>& solids, double max_range_m);

}  // namespace evade::sim
