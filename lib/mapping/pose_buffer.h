// A short history of 2D odometry poses, to ask "where was the robot at time
// t" for a point cloud whose revolution started at t (and for each slice of
// the sweep, to undo the robot's motion during the revolution).
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

namespace evade::mapping {

struct Pose2 {
  double x = 0.0;    // m, odometry frame
  double y = 0.0;    // m
  double yaw = 0.0;  // rad
};

struct OdometrySample {
  int64_t utime = 0;
  Pose2 pose;
  double v = 0.0;      // m/s along the heading
  double omega = 0.0;  // rad/s
};

double wrap_angle(double a);  // to [-pi, pi)

class PoseBuffer {
 public:
  // Keeps samples newer than `newest - history_us`.
  explicit PoseBuffer(int64_t history_us) : history_us_(history_us) {}

  enum class AddResult { kAdded, kOutOfOrder, kReset };
  // A sample older than the newest is dropped (kOutOfOrder), unless it is
  // older by more than the whole history (a log loop or a restarted base):
  // then the buffer starts again from it (kReset).
  AddResult add(const OdometrySample& s);

  // Pose at `utime`: interpolated between the two samples around it (yaw on
  // the shortest arc), or extrapolated along the unicycle model with the
  // nearest sample's v and omega when utime lies at most `max_extrapolation_us`
  // outside the buffer. nullopt when empty or too far outside.
  std::optional<Pose2> at(int64_t utime, int64_t max_extrapolation_us) const;

  size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  int64_t newest_utime() const { return samples_.empty() ? 0 : samples_.back().utime; }

 private:
  int64_t history_us_;
  std::deque<OdometrySample> samples_;
};

// Unicycle motion with constant v, omega for dt seconds (dt may be negative).
Pose2 integrate_unicycle(const Pose2& p, double v, double omega, double dt_s);

}  // namespace evade::mapping
