// Differential-drive kinematics for the base driver: exact-arc pose
// integration and the velocity/acceleration limiter applied to CMD_VEL.
#pragma once

#include <cmath>

namespace evade::base {

struct Pose2 {
  double x = 0.0;    // m
  double y = 0.0;    // m
  double yaw = 0.0;  // rad
};

// Wraps an angle to [-pi, pi).
double wrap_angle(double a);

// Pose after moving for dt seconds at constant (v, omega): the exact arc of
// the unicycle model x' = v cos(yaw), y' = v sin(yaw), yaw' = omega, not an
// Euler step. The chord of the arc has length v*dt*sinc(omega*dt/2) and
// points along yaw + omega*dt/2, which is exact for every omega and, written
// with sinc, has no 1/omega singularity at omega = 0 (straight line).
Pose2 integrate_arc(const Pose2& start, double v, double omega, double dt);

// Limits of the base, from the shared `robot:` section of the configuration.
struct VelocityLimits {
  double min_v_mps = 0.0;
  double max_v_mps = 1.0;
  double max_omega_radps = 0.5;   // symmetric
  double max_accel_mps2 = 1.0;    // |v| growing
  double max_decel_mps2 = 1.5;    // |v| shrinking (braking)
  double max_alpha_radps2 = 3.0;  // yaw acceleration, either way
};

struct Twist {
  double v = 0.0;      // m/s
  double omega = 0.0;  // rad/s
};

// One step of the command shaper: clamps the target to the velocity limits,
// then moves `current` toward it by at most the acceleration limits times dt.
// Braking (|v| shrinking, including through zero up to zero) uses
// max_decel; speeding up uses max_accel.
Twist limit_step(const Twist& current, const Twist& target, const VelocityLimits& limits, double dt);

}  // namespace evade::base
