#include "sim/robot.h"

#include <algorithm>
#include <cmath>

namespace evade::sim {
namespace {
// Below this yaw rate the arc is a straight line (v/omega would overflow).
constexpr double kStraightOmega = 1e-9;

// Moves `value` towards `target` by at most the rate allowed: `slow_down`
// while the magnitude is shrinking towards zero, `speed_up` otherwise.
double ramp(double value, double target, double speed_up, double slow_down, double dt_s) {
  double d = target - value;
  bool braking = (value > 0.0 && d < 0.0) || (value < 0.0 && d > 0.0);
  double limit = (braking ? slow_down : speed_up) * dt_s;
  double next = value + std::clamp(d, -limit, limit);
  // Braking through zero: stop at zero this step, the reverse ramp starts next.
  if (braking && ((value > 0.0 && next < 0.0) || (value < 0.0 && next > 0.0))) next = 0.0;
  return next;
}
}  // namespace

Pose2 integrate_arc(const Pose2& p, double v, double omega, double dt_s) {
  Pose2 q = p;
  if (std::abs(omega) < kStraightOmega) {
    q.x += v * std::cos(p.yaw) * dt_s;
    q.y += v * std::sin(p.yaw) * dt_s;
  } else {
    double yaw1 = p.yaw + omega * dt_s;
    q.x += v / omega * (std::sin(yaw1) - std::sin(p.yaw));
    q.y -= v / omega * (std::cos(yaw1) - std::cos(p.yaw));
    q.yaw = std::remainder(yaw1, 2.0 * M_PI);
  }
  return q;
}

UnicycleRobot::UnicycleRobot(const Pose2& start, const RobotLimits& limits, int64_t start_us)
    : limits_(limits), pose_(start), t_us_(start_us) {}

bool UnicycleRobot::commanded_recently(int64_t utime) const {
  return last_command_us_ >= 0 && utime - last_command_us_ <= limits_.command_timeout_us;
}

void UnicycleRobot::command(double v, double omega, int64_t utime) {
  advance_to(utime);
  cmd_v_ = v;
  cmd_omega_ = omega;
  last_command_us_ = utime;
}

void UnicycleRobot::step() {
  double dt = limits_.step_us * 1e-6;
  history_.push_back(GridState{t_us_, pose_, v_, omega_});
  if (history_.size() > kHistorySteps) history_.pop_front();
  pose_ = integrate_arc(pose_, v_, omega_, dt);
  t_us_ += limits_.step_us;
  bool live = commanded_recently(t_us_);
  if (live_ && !live) command_timeouts_++;
  live_ = live;
  double target_v = live ? cmd_v_ : 0.0;
  double target_omega = live ? cmd_omega_ : 0.0;
  v_ = ramp(v_, target_v, limits_.max_accel_mps2, limits_.max_decel_mps2, dt);
  omega_ = ramp(omega_, target_omega, limits_.max_alpha_radps2, limits_.max_alpha_radps2, dt);
  if (first_motion_us_ < 0 && (v_ != 0.0 || omega_ != 0.0)) first_motion_us_ = t_us_;
}

void UnicycleRobot::advance_to(int64_t utime) {
  while (t_us_ + limits_.step_us <= utime) step();
}

Pose2 UnicycleRobot::pose_at(int64_t utime) const {
  if (utime >= t_us_) return integrate_arc(pose_, v_, omega_, (utime - t_us_) * 1e-6);
  for (auto it = history_.rbegin(); it != history_.rend(); ++it)
    if (it->t_us <= utime) return integrate_arc(it->pose, it->v, it->omega, (utime - it->t_us) * 1e-6);
  return history_.empty() ? pose_ : history_.front().pose;
}

}  // namespace evade::sim
