#include "mapping/pose_buffer.h"

#include <algorithm>
#include <cmath>

namespace evade::mapping {

double wrap_angle(double a) {
  const double two_pi = 2.0 * M_PI;
  a = std::fmod(a + M_PI, two_pi);
  if (a < 0.0) a += two_pi;
  return a - M_PI;
}

Pose2 integrate_unicycle(const Pose2& p, double v, double omega, double dt_s) {
  Pose2 out = p;
  const double dyaw = omega * dt_s;
  if (std::abs(dyaw) < 1e-9) {
    out.x += v * dt_s * std::cos(p.yaw);
    out.y += v * dt_s * std::sin(p.yaw);
  } else {
    // exact arc of radius v / omega
    const double r = v / omega;
    out.x += r * (std::sin(p.yaw + dyaw) - std::sin(p.yaw));
    out.y += -r * (std::cos(p.yaw + dyaw) - std::cos(p.yaw));
  }
  out.yaw = wrap_angle(p.yaw + dyaw);
  return out;
}

PoseBuffer::AddResult PoseBuffer::add(const OdometrySample& s) {
  AddResult result = AddResult::kAdded;
  if (!samples_.empty() && s.utime <= samples_.back().utime) {
    if (s.utime >= samples_.back().utime - history_us_) return AddResult::kOutOfOrder;
    samples_.clear();
    result = AddResult::kReset;
  }
  samples_.push_back(s);
  while (!samples_.empty() && samples_.front().utime < s.utime - history_us_) samples_.pop_front();
  return result;
}

std::optional<Pose2> PoseBuffer::at(int64_t utime, int64_t max_extrapolation_us) const {
  if (samples_.empty()) return std::nullopt;
  const OdometrySample& first = samples_.front();
  const OdometrySample& last = samples_.back();
  if (utime <= first.utime) {
    if (first.utime - utime > max_extrapolation_us) return std::nullopt;
    return integrate_unicycle(first.pose, first.v, first.omega, (utime - first.utime) * 1e-6);
  }
  if (utime >= last.utime) {
    if (utime - last.utime > max_extrapolation_us) return std::nullopt;
    return integrate_unicycle(last.pose, last.v, last.omega, (utime - last.utime) * 1e-6);
  }
  auto hi = std::lower_bound(samples_.begin(), samples_.end(), utime,
                             [](const OdometrySample& s, int64_t t) { return s.utime < t; });
  auto lo = hi - 1;
  const double f = double(utime - lo->utime) / double(hi->utime - lo->utime);
  Pose2 p;
  p.x = lo->pose.x + f * (hi->pose.x - lo->pose.x);
  p.y = lo->pose.y + f * (hi->pose.y - lo->pose.y);
  p.yaw = wrap_angle(lo->pose.yaw + f * wrap_angle(hi->pose.yaw - lo->pose.yaw));
  return p;
}

}  // namespace evade::mapping
