#include "planning/manoeuvres.h"

#include <algorithm>

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

}  // namespace evade::planning
