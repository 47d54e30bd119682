#include "planning/escape.h"

#include <algorithm>
#include <cmath>

namespace evade::planning {
namespace {

// x moved towards want by at most step.
double towards(double x, double want, double step) { return std::clamp(want, x - step, x + step); }

// Whether the footprint, stepping from `state` at (v, omega) and then
// braking the turn at alpha (v held), stays at or above `floor` of the
// field's h until the turn has stopped.
bool turn_stops_clear(const Problem& pb, const ObstacleTrack& field, const double* state, double v, double omega,
                      double floor) {
  double x[3] = {state[0], state[1], state[2]};
  const double dw = pb.lim.alpha * pb.dt;
  for (int i = 0; i < 100; ++i) {
    unicycle_step(v, omega, pb.dt, &x[0], &x[1], &x[2]);
    if (barrier_at(pb, field, 0, x).h < floor) return false;
    if (omega == 0.0) return true;
    omega = towards(omega, 0.0, dw);
  }
  return true;
}

}  // namespace

std::vector<double> turn_on_the_spot(const Problem& pb, double yaw_by, const std::vector<double>& brake, double omega0,
                                     const ObstacleTrack* field, double into_margin_m) {
  const Limits& lim = pb.lim;
  std::vector<double> u(brake);
  double state[3] = {pb.x0, pb.y0, pb.yaw0};
  const double floor = field ? std::min(0.0, barrier_at(pb, *field, 0, state).h) - into_margin_m : 0.0;
  const double dw = lim.alpha * pb.dt;
  double omega = omega0;
  for (int k = 0; k < pb.N; ++k) {
    const double v = brake[2 * static_cast<size_t>(k)];
    double turn = towards(omega, std::clamp(yaw_by / pb.dt, -lim.omega_max, lim.omega_max), dw);
    if (field && !turn_stops_clear(pb, *field, state, v, turn, floor)) turn = towards(omega, 0.0, dw);
    double lo = omega - dw, hi = omega + dw;  // a step at alpha from the last
    narrow_to_turn_bounds(pb, k, &lo, &hi);
    turn = std::clamp(turn, lo, hi);
    omega = turn;
    u[2 * static_cast<size_t>(k) + 1] = omega;
    yaw_by -= omega * pb.dt;
    unicycle_step(v, omega, pb.dt, &state[0], &state[1], &state[2]);
  }
  return u;
}

}  // namespace evade::planning
