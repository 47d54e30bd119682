#include "planning/goal_approach.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::planning {

double goal_capture_speed(double x, double y, double yaw, double gx, double gy, double omega_max) {
  const double d = std::hypot(gx - x, gy - y);
  const double phi = wrap_angle(std::atan2(gy - y, gx - x) - yaw);
  // behind the beam: the tightest turn that still reaches it, d / 2
  const double s = std::fabs(phi) >= 0.5 * M_PI ? 1.0 : std::fabs(std::sin(phi));
  if (s <= 0.0) return std::numeric_limits<double>::infinity();
  return omega_max * d / (2.0 * s);
}

std::vector<double> goal_approach_caps(const GoalApproachParams& p, const Problem& pb, double gx, double gy,
                                       double route_left_m) {
  std::vector<double> caps;
  if (!p.enabled || pb.N <= 0) return caps;
  const double d = std::hypot(gx - pb.x0, gy - pb.y0);
  if (!(route_left_m <= p.max_route_ratio * d)) return caps;
  const double capture = goal_capture_speed(pb.x0, pb.y0, pb.yaw0, gx, gy, pb.lim.omega_max);
  const double bound = std::clamp(capture, std::min(p.min_speed_mps, pb.lim.v_max), pb.lim.v_max);
  if (!(bound < pb.lim.v_max)) return caps;
  caps.resize(size_t(pb.N));
  for (int k = 0; k < pb.N; ++k) caps[size_t(k)] = cap_braking_can_meet(pb, k, bound);
  return caps;
}

void tighten_caps(const std::vector<double>& more, std::vector<double>* caps) {
  if (more.empty()) return;
  if (caps->empty()) {
    *caps = more;
    return;
  }
  const size_t n = std::max(caps->size(), more.size());
  const double inf = std::numeric_limits<double>::infinity();
  caps->resize(n, inf);
  for (size_t k = 0; k < n; ++k) (*caps)[k] = std::min((*caps)[k], k < more.size() ? more[k] : inf);
}

}  // namespace evade::planning
