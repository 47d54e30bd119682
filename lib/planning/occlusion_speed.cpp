#include "planning/occlusion_speed.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::planning {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The reference path from the start: (x0, y0), then ref[1..N], walked by
// arc length.
struct Path {
  std::vector<double> x, y, s;  // vertices and their arc length

  explicit Path(const Problem& pb) {
    x.push_back(pb.x0);
    y.push_back(pb.y0);
    s.push_back(0.0);
    for (size_t k = 1; k < pb.ref_x.size() && k < pb.ref_y.size(); ++k) {
      const double d = std::hypot(pb.ref_x[k] - x.back(), pb.ref_y[k] - y.back());
      if (d < 1e-9) continue;
      x.push_back(pb.ref_x[k]);
      y.push_back(pb.ref_y[k]);
      s.push_back(s.back() + d);
    }
  }

  // Position and heading at arc length t (held at the ends; the start's
  // heading when the path has no length).
  void at(double t, double yaw0, double* px, double* py, double* yaw) const {
    if (s.size() < 2) {
      *px = x[0], *py = y[0], *yaw = yaw0;
      return;
    }
    size_t i = size_t(std::upper_bound(s.begin(), s.end(), t) - s.begin());
    i = std::clamp<size_t>(i, 1, s.size() - 1);
    const double f = std::clamp((t - s[i - 1]) / (s[i] - s[i - 1]), 0.0, 1.0);
    *px = x[i - 1] + f * (x[i] - x[i - 1]);
    *py = y[i - 1] + f * (y[i] - y[i - 1]);
    *yaw = std::atan2(y[i] - y[i - 1], x[i] - x[i - 1]);
  }
};

// Nearest point of segment a-b to p, if it lies ahead along (hx, hy).
double ahead_distance(double ax, double ay, double bx, double by, double px, double py, double hx, double hy) {
  const double ux = bx - ax, uy = by - ay, len2 = ux * ux + uy * uy;
  const double f = len2 > 0 ? std::clamp(((px - ax) * ux + (py - ay) * uy) / len2, 0.0, 1.0) : 0.0;
  const double qx = ax + f * ux, qy = ay + f * uy;
  if ((qx - px) * hx + (qy - py) * hy <= 0.0) return kInf;
  return std::hypot(qx - px, qy - py);
}

double footprint_reach(const Footprint& f) {
  double r = 0.0;
  for (double o : f.offsets) r = std::max(r, std::fabs(o));
  return r + f.radius;
}

}  // namespace

double stopping_safe_speed(const OcclusionSpeedParams& p, double decel_mps2, double d) {
  const double t = std::max(0.0, d - p.clearance_m) / p.walking_speed_mps;
  return std::max(0.0, decel_mps2 * (t - p.reaction_s));
}

double distance_to_exit_ahead(const evade::hidden_region_t& r, double x, double y, double yaw) {
  const double hx = std::cos(yaw), hy = std::sin(yaw);
  double d = kInf;
  for (int i = 0; i < 2; ++i)
    d = std::min(d, ahead_distance(r.near_x[i], r.near_y[i], r.far_x[i], r.far_y[i], x, y, hx, hy));
  return d;
}

std::vector<double> occlusion_speed_caps(const OcclusionSpeedParams& p, const evade::hidden_region_list_t& regions,
                                         const Problem& pb) {
  std::vector<double> caps;
  if (regions.regions.empty() || pb.N <= 0) return caps;
  const Path path(pb);
  const double reach = footprint_reach(pb.footprint);
  const double floor = std::min(p.min_speed_mps, pb.lim.v_max);
  bool binds = false;
  double s = 0.0;
  caps.resize(size_t(pb.N), pb.lim.v_max);
  for (int k = 0; k < pb.N; ++k) {
    double x, y, yaw;
    path.at(s, pb.yaw0, &x, &y, &yaw);
    double d = kInf;
    for (const auto& r : regions.regions) d = std::min(d, distance_to_exit_ahead(r, x, y, yaw));
    double cap = std::isfinite(d) ? stopping_safe_speed(p, pb.lim.decel, d - reach) : pb.lim.v_max;
    cap = std::clamp(cap, floor, pb.lim.v_max);
    cap = cap_braking_can_meet(pb, k, cap);
    binds = binds || cap < pb.lim.v_max;
    caps[size_t(k)] = cap;
    s += cap * pb.dt;
  }
  if (!binds) caps.clear();
  return caps;
}

}  // namespace evade::planning
