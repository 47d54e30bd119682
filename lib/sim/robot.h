// The simulated differential-drive base: unicycle kinematics driven by the
// velocities the emulated Scout was commanded, through acceleration limits,
// with the Scout's command timeout: no motion command for
// `command_timeout_us` (the manual's receive timeout, 500 ms; lib/base/README.md
// "The base's own command timeout") -> the target becomes zero and the base
// brakes at its deceleration limit until the next command.
//
// Integration runs on a fixed time grid (step_us) so that a run does not
// depend on how often somebody asks for the pose. Over each step the
// velocities are constant and the pose follows the exact arc; the
// velocities then move towards the target, limited by the accelerations.
#pragma once

#include <cstdint>
#include <deque>

#include "sim/scenario.h"

namespace evade::sim {

struct RobotLimits {
  double max_accel_mps2 = 1.0;    // speeding up
  double max_decel_mps2 = 1.5;    // braking (speed magnitude decreasing)
  double max_alpha_radps2 = 3.0;  // yaw acceleration, either way
  int64_t command_timeout_us = 500'000;
  int64_t step_us = 1000;
};

// Pose after moving at (v, omega) for dt_s from `p`: the exact arc.
Pose2 integrate_arc(const Pose2& p, double v, double omega, double dt_s);

class UnicycleRobot {
 public:
  UnicycleRobot(const Pose2& start, const RobotLimits& limits, int64_t start_us);

  // A motion command received at `utime` (after advance_to(utime)).
  void command(double v, double omega, int64_t utime);
  // Integrates the grid steps up to `utime` (no-op if already there).
  void advance_to(int64_t utime);
  // Pose at `utime`: the last grid state at or before it moved on by that
  // state's velocities (exact, since they are constant between steps).
  // Times up to kHistorySteps steps in the past are exact too, so a LiDAR
  // packet can be cast after the robot has moved on; older times use the
  // oldest state kept.
  Pose2 pose_at(int64_t utime) const;
  static constexpr size_t kHistorySteps = 128;  // covers sim.lidar_max_lag_s at 1 ms steps

  const Pose2& pose() const { return pose_; }
  double v() const { return v_; }
  double omega() const { return omega_; }
  int64_t time() const { return t_us_; }
  bool commanded_recently(int64_t utime) const;
  // How often the command timeout has expired on a commanded base (a grid
  // step found the last command older than command_timeout_us).
  int64_t command_timeouts() const { return command_timeouts_; }
  // Grid time at which the velocity first became non-zero; -1 before.
  int64_t first_motion_us() const { return first_motion_us_; }

 private:
  struct GridState {
    int64_t t_us;
    Pose2 pose;
    double v, omega;
  };
  void step();
  RobotLimits limits_;
  std::deque<GridState> history_;  // previous grid states, oldest first
  Pose2 pose_;
  double v_ = 0.0, omega_ = 0.0;
  double cmd_v_ = 0.0, cmd_omega_ = 0.0;
  int64_t last_command_us_ = -1;
  int64_t t_us_;
  int64_t first_motion_us_ = -1;
  bool live_ = false;
  int64_t command_timeouts_ = 0;
};

}  // namespace evade::sim
