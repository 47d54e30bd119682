#include "planning/manoeuvres.h"

#include <algorithm>
#include <cmath>

namespace evade::planning {

std::vector<double> swerve_controls(const Problem& pb, double side) {
  std::vector<double> u(pb.num_controls());
  for (int k = 0; k < pb.N; ++k) {
    u[2 * k] = pb.v_prev;
    u[2 * k + 1] = (k < pb.N / 2 ? side : -side) * pb.lim.omega_max;
  }
  return u;
}

std::vector<double> dash_controls(const Problem& pb, double side) {
  std::vector<double> u(pb.num_controls());
  double v = pb.v_prev;
  for (int k = 0; k < pb.N; ++k) {
    v = std::min(pb.lim.v_max, v + pb.lim.accel * pb.dt);
    u[2 * k] = v;
    u[2 * k + 1] = k < pb.N / 2 ? side * pb.lim.omega_max : 0.0;
  }
  return u;
}

std::vector<double> pull_over_controls(const Problem& pb, double side, double offset, double ahead) {
  // the lane `offset` to one side of the reference's line (its first point,
  // its heading), followed by pure pursuit `lookahead` ahead on it, braking
  // to stand `ahead` along from the robot
  const bool ref = !pb.ref_x.empty() && !pb.ref_yaw.empty();
  const double ry = ref ? pb.ref_yaw[0] : pb.yaw0, ox = ref ? pb.ref_x[0] : pb.x0, oy = ref ? pb.ref_y[0] : pb.y0;
  const double cr = std::cos(ry), sr = std::sin(ry);
  const double s0 = (pb.x0 - ox) * cr + (pb.y0 - oy) * sr;
  std::vector<double> u(pb.num_controls());
  double x = pb.x0, y = pb.y0, yaw = pb.yaw0, v = pb.v_prev, w = pb.omega_prev;
  for (int k = 0; k < pb.N; ++k) {
    const double s = (x - ox) * cr + (y - oy) * sr;   // along the reference's heading
    const double lookahead = std::max(0.6, 1.2 * v);  // m: the lane joined over about a second
    const double tx = ox + (s + lookahead) * cr - side * offset * sr;
    const double ty = oy + (s + lookahead) * sr + side * offset * cr;
    const double err = wrap_angle(std::atan2(ty - y, tx - x) - yaw);
    const double left = std::max(0.0, s0 + ahead - s);
    const bool there = left < 0.02;  // standing: no turning either
    const double want_w = there ? 0.0 : std::clamp(err / pb.dt, -pb.lim.omega_max, pb.lim.omega_max);
    w = std::clamp(want_w, w - pb.lim.alpha * pb.dt, w + pb.lim.alpha * pb.dt);
    const double want_v = there ? 0.0 : std::sqrt(2.0 * pb.lim.decel * left) * std::max(0.0, std::cos(err));
    const double lo = std::max(0.0, v - pb.lim.decel * pb.dt);
    v = std::clamp(std::min(want_v, pb.lim.v_max), lo, std::max(lo, v + pb.lim.accel * pb.dt));
    u[2 * k] = v;
    u[2 * k + 1] = w;
    unicycle_step(v, w, pb.dt, &x, &y, &yaw);
  }
  return u;
}

}  // namespace evade::planning
