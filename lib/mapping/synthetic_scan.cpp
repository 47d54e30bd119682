#include "mapping/synthetic_scan.h"

#include <cmath>
#include <limits>
#include <random>

namespace evade::mapping {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxRange = 100.0;

double ground_z(const SynthWorld& w, double x) {
  return x > w.ramp_start_x ? w.ground_slope_x * (x - w.ramp_start_x) : 0.0;
}

// first hit distance along o + t d (|d| = 1), t > 0
double hit_ground(const SynthWorld& w, const double o[3], const double d[3]) {
  if (w.ground_slope_x == 0.0) {
    if (d[2] >= 0.0) return kInf;
    return -o[2] / d[2];
  }
  // march, then bisect (the ground is piecewise planar)
  double prev = 0.0;
  for (double t = 0.05; t < kMaxRange; t += 0.05) {
    const double x = o[0] + t * d[0];
    if (o[2] + t * d[2] <= ground_z(w, x)) {
      double lo = prev, hi = t;
      for (int k = 0; k < 30; ++k) {
        const double mid = 0.5 * (lo + hi);
        if (o[2] + mid * d[2] <= ground_z(w, o[0] + mid * d[0]))
          hi = mid;
        else
          lo = mid;
      }
      return hi;
    }
    prev = t;
  }
  return kInf;
}

double hit_cylinder(const SynthCylinder& c, const double o[3], const double d[3]) {
  double best = kInf;
  const double ox = o[0] - c.x, oy = o[1] - c.y;
  const double a = d[0] * d[0] + d[1] * d[1];
  if (a > 1e-12) {
    const double b = 2.0 * (ox * d[0] + oy * d[1]);
    const double cc = ox * ox + oy * oy - c.radius * c.radius;
    const double disc = b * b - 4.0 * a * cc;
    if (disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / (2.0 * a);
      const double z = o[2] + t * d[2];
      if (t > 0.0 && z >= 0.0 && z <= c.height) best = t;
    }
  }
  if (std::abs(d[2]) > 1e-12) {  // top cap
    const double t = (c.height - o[2]) / d[2];
    const double x = ox + t * d[0], y = oy + t * d[1];
    if (t > 0.0 && x * x + y * y <= c.radius * c.radius) best = std::min(best, t);
  }
  return best;
}

double hit_box(const SynthBox& b, const double o[3], const double d[3]) {
  const double cy = std::cos(b.yaw), sy = std::sin(b.yaw);
  const double lo_[3] = {cy * (o[0] - b.x) + sy * (o[1] - b.y), -sy * (o[0] - b.x) + cy * (o[1] - b.y), o[2]};
  const double ld[3] = {cy * d[0] + sy * d[1], -sy * d[0] + cy * d[1], d[2]};
  const double mn[3] = {-b.length / 2, -b.width / 2, 0.0}, mx[3] = {b.length / 2, b.width / 2, b.height};
  double t0 = 0.0, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(ld[k]) < 1e-12) {
      if (lo_[k] < mn[k] || lo_[k] > mx[k]) return kInf;
      continue;
    }
    double ta = (mn[k] - lo_[k]) / ld[k], tb = (mx[k] - lo_[k]) / ld[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return kInf;
  }
  return t0 > 0.0 ? t0 : kInf;
}

}  // namespace

SynthCloud synth_vlp16(const SynthWorld& world, const SynthScanOptions& opt) {
  SynthCloud out;
  const size_t cap = size_t(opt.azimuth_steps) * 16;
  out.x.reserve(cap);
  out.y.reserve(cap);
  out.z.reserve(cap);
  out.time_offset.reserve(cap);
  std::mt19937 rng(opt.seed);
  std::normal_distribution<double> noise(0.0, opt.range_noise_std_m > 0 ? opt.range_noise_std_m : 1.0);
  for (int k = 0; k < opt.azimuth_steps; ++k) {
    const int64_t offset = int64_t(k) * opt.sweep_us / opt.azimuth_steps;
    const Pose2 robot = integrate_unicycle(opt.robot_start, opt.v, opt.omega, offset * 1e-6);
    const double az = 2.0 * M_PI * k / opt.azimuth_steps;  // sensor frame
    const double o[3] = {robot.x, robot.y, opt.mount_height_m};
    for (int ring = 0; ring < 16; ++ring) {
      const double el = (-15.0 + 2.0 * ring) * M_PI / 180.0;
      const double ds[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
      const double cy = std::cos(robot.yaw), sy = std::sin(robot.yaw);
      const double d[3] = {cy * ds[0] - sy * ds[1], sy * ds[0] + cy * ds[1], ds[2]};
      double t = hit_ground(world, o, d);
      for (const auto& c : world.cylinders) t = std::min(t, hit_cylinder(c, o, d));
      for (const auto& b : world.boxes) t = std::min(t, hit_box(b, o, d));
      if (!(t < kMaxRange)) continue;
      if (opt.range_noise_std_m > 0) t += noise(rng);
      out.x.push_back(float(t * ds[0]));
      out.y.push_back(float(t * ds[1]));
      out.z.push_back(float(t * ds[2]));
      out.time_offset.push_back(int32_t(offset));
    }
  }
  return out;
}

CloudView view_of(const SynthCloud& cloud, int64_t utime, double mount_z_m) {
  CloudView v;
  v.utime = utime;
  v.n = cloud.x.size();
  v.x = cloud.x.data();
  v.y = cloud.y.data();
  v.z = cloud.z.data();
  v.time_offset = cloud.time_offset.data();
  v.mount_z = mount_z_m;
  return v;
}

}  // namespace evade::mapping
