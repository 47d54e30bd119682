#include "base/kinematics.h"

#include <algorithm>

namespace evade::base {

double wrap_angle(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a < 0) a += 2.0 * M_PI;
  return a - M_PI;
}

namespace {
// sin(x)/x; below 1e-4 the Taylor series 1 - x^2/6 is exact to double
// precision (the next term, x^4/120, is < 1e-18).
double sinc(double x) {
  if (std::abs(x) < 1e-4) return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}

// Moves `from` toward `to` by at most `step` (step >= 0).
double approach(double from, double to, double step) {
  if (to > from) return std::min(to, from + step);
  return std::max(to, from - step);
}
}  // namespace

Pose2 integrate_arc(const Pose2& start, double v, double omega, double dt) {
  const double half_turn = 0.5 * omega * dt;
  const double chord = v * dt * sinc(half_turn);
  const double heading = start.yaw + half_turn;
  Pose2 out;
  out.x = start.x + chord * std::cos(heading);
  out.y = start.y + chord * std::sin(heading);
  out.yaw = wrap_angle(start.yaw + omega * dt);
  return out;
}

Twist limit_step(const Twist& current, const Twist& target, const VelocityLimits& limits, double dt) {
  Twist goal;
  goal.v = std::clamp(target.v, limits.min_v_mps, limits.max_v_mps);
  goal.omega = std::clamp(target.omega, -limits.max_omega_radps, limits.max_omega_radps);
  dt = std::max(dt, 0.0);

  Twist out;
  // Linear: braking toward zero may use the larger deceleration limit; any
  // part of the change that moves away from zero is an acceleration.
  const double v = current.v;
  if (v != 0.0 && (goal.v - v) * v < 0.0) {
    // Braking: first toward zero (or the goal, if it has the same sign).
    const double brake_goal = (goal.v * v > 0.0) ? goal.v : 0.0;
    const double braked = approach(v, brake_goal, limits.max_decel_mps2 * dt);
    if (braked == 0.0 && goal.v != 0.0 && goal.v * v < 0.0) {
      // Reached zero within this step: use what remains of dt to accelerate
      // the other way.
      const double t_brake = std::abs(v) / limits.max_decel_mps2;
      out.v = approach(0.0, goal.v, limits.max_accel_mps2 * std::max(dt - t_brake, 0.0));
    } else {
      out.v = braked;
    }
  } else {
    out.v = approach(v, goal.v, limits.max_accel_mps2 * dt);
  }
  out.omega = approach(current.omega, goal.omega, limits.max_alpha_radps2 * dt);
  return out;
}

}  // namespace evade::base
