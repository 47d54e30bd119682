#include "planning/recent_max.h"

#include <algorithm>
#include <cmath>

namespace evade::planning {

void RecentMax::add(int64_t utime, double value, double window_s) {
  if (!q_.empty() && utime < q_.back().first) q_.clear();  // time went back: a new epoch
  const int64_t oldest = utime - std::llround(std::max(0.0, window_s) * 1e6);
  while (!q_.empty() && q_.front().first < oldest) q_.pop_front();
  if (!std::isfinite(value)) return;
  while (!q_.empty() && q_.back().second <= value) q_.pop_back();
  q_.emplace_back(utime, value);
}

}  // namespace evade::planning
