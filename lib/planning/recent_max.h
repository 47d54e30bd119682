// The largest of a series of values over a sliding window of time: what
// passive safety takes as a mover's speed (passive_safety.h,
// speed_memory_s). A tracker's speed estimate of a walker that turns
// round passes through zero for a few hundred milliseconds, while the
// walker itself goes on at its walking speed, now towards the robot; the
// largest speed the track has shown lately is what it can still do.
#pragma once

#include <cstdint>
#include <deque>
#include <utility>

namespace evade::planning {

class RecentMax {
 public:
  // Adds value at utime (us) and forgets what is older than window_s
  // before utime (everything, when utime is before the last add's: a new
  // epoch). Non-finite values are not added.
  void add(int64_t utime, double value, double window_s);
  // The largest value added within the window of the last add (0 when none).
  double max() const { return q_.empty() ? 0.0 : q_.front().second; }

 private:
  std::deque<std::pair<int64_t, double>> q_;  // (utime, value), values decreasing front to back
};

}  // namespace evade::planning
