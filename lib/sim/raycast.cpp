#include "sim/raycast.h"

#include <algorithm>
#include <cmath>

namespace evade::sim {
namespace {
// Hits closer than this to the origin are ignored: a ray starting on a
// surface (the sensor on the ground, say) does not hit that surface.
constexpr double kMinT = 1e-9;
// Direction components below this are parallel to the plane in question.
constexpr double kParallel = 1e-12;
}  // namespace

double hit_ground(const Ray& r) {
  if (r.dir.z > -kParallel) return kNoHit;
  double t = -r.origin.z / r.dir.z;
  return t > kMinT ? t : kNoHit;
}

double hit_cylinder(const Ray& r, double cx, double cy, double radius, double height) {
  double best = kNoHit;
  double ox = r.origin.x - cx, oy = r.origin.y - cy;
  auto z_at = [&](double t) { return r.origin.z + t * r.dir.z; };
  // Side wall: |o + t d|^2 = radius^2 in the horizontal plane.
  double a = r.dir.x * r.dir.x + r.dir.y * r.dir.y;
  if (a > kParallel) {
    double b = 2.0 * (ox * r.dir.x + oy * r.dir.y);
    double c = ox * ox + oy * oy - radius * radius;
    double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      double sq = std::sqrt(disc);
      // Numerically stable roots.
      double q = -0.5 * (b + std::copysign(sq, b));
      double t1 = q / a, t2 = (q != 0.0) ? c / q : t1;
      for (double t : {std::min(t1, t2), std::max(t1, t2)}) {
        if (t > kMinT && t < best) {
          double z = z_at(t);
          if (z >= 0.0 && z <= height) best = t;
        }
      }
    }
  }
  // Flat top at z = height.
  if (std::abs(r.dir.z) > kParallel) {
    double t = (height - r.origin.z) / r.dir.z;
    if (t > kMinT && t < best) {
      double x = ox + t * r.dir.x, y = oy + t * r.dir.y;
      if (x * x + y * y <= radius * radius) best = t;
    }
  }
  return best;
}

double hit_box(const Ray& r, double cx, double cy, double yaw, double length, double width, double height) {
  // Into the box frame: x along `yaw`, origin at the box centre on the ground.
  double c = std::cos(yaw), s = std::sin(yaw);
  double px = r.origin.x - cx, py = r.origin.y - cy;
  double o[3] = {c * px + s * py, -s * px + c * py, r.origin.z};
  double d[3] = {c * r.dir.x + s * r.dir.y, -s * r.dir.x + c * r.dir.y, r.dir.z};
  double lo[3] = {-0.5 * length, -0.5 * width, 0.0};
  double hi[3] = {0.5 * length, 0.5 * width, height};
  // Slab method: the ray is inside the box for t in [t_enter, t_exit].
  double t_enter = -kNoHit, t_exit = kNoHit;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d[i]) < kParallel) {
      if (o[i] < lo[i] || o[i] > hi[i]) return kNoHit;
      continue;
    }
    double ta = (lo[i] - o[i]) / d[i], tb = (hi[i] - o[i]) / d[i];
    if (ta > tb) std::swap(ta, tb);
    t_enter = std::max(t_enter, ta);
    t_exit = std::min(t_exit, tb);
  }
  if (t_enter > t_exit) return kNoHit;
  if (t_enter > kMinT) return t_enter;
  if (t_exit > kMinT) return t_exit;  // origin inside the box: its inner wall
  return kNoHit;
}

double hit_solid(const Ray& r, const Solid& s) {
  return s.shape == Shape::kCylinder ? hit_cylinder(r, s.x, s.y, s.radius, s.height)
                                     : hit_box(r, s.x, s.y, s.yaw, s.length, s.width, s.height);
}

double cast(const Ray& r, const std::vector<Solid>& solids, double max_range_m) {
  double best = hit_ground(r);
  for (const Solid& s : solids) best = std::min(best, hit_solid(r, s));
  return best <= max_range_m ? best : kNoHit;
}

}  // namespace evade::sim
