#include "planning/input_checks.h"

#include <cmath>
#include <limits>

#include "planning/obstacles.h"

namespace evade::planning {

int64_t age_us(int64_t now, int64_t utime) {
  int64_t age;
  if (!__builtin_sub_overflow(now, utime, &age)) return age;
  return utime < 0 ? std::numeric_limits<int64_t>::max() : -std::numeric_limits<int64_t>::max();
}

Arrival arrival(int64_t now, int64_t utime, int64_t max_age_us) {
  const int64_t age = age_us(now, utime);
  if (age > max_age_us) return Arrival::kLate;
  if (age < -max_age_us) return Arrival::kFuture;
  return Arrival::kOnTime;
}

bool invalid_track_near(const evade::prediction_list_t& m, double x, double y, double radius_m) {
  for (const auto& t : m.tracks) {
    if (valid_track(t)) continue;
    if (t.x.empty() || t.y.empty() || !std::isfinite(t.x[0]) || !std::isfinite(t.y[0])) return true;
    if (std::hypot(t.x[0] - x, t.y[0] - y) <= radius_m) return true;
  }
  return false;
}

bool invalid_observed_near(const evade::obstacle_list_t& m, double x, double y, double radius_m) {
  for (const auto& o : m.obstacles) {
    if (valid_observed(o)) continue;
    if (!std::isfinite(o.x) || !std::isfinite(o.y)) return true;
    if (std::hypot(o.x - x, o.y - y) <= radius_m) return true;
  }
  return false;
}

}  // namespace evade::planning
