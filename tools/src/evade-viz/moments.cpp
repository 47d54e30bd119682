#include "moments.h"

#include <algorithm>

#include "bus/core.h"
#include "evade/sim_truth_t.hpp"

namespace evade::viz {

std::vector<Moment> key_moments(const std::vector<bus::LogEvent>& events, const metrics::MetricsParams& p) {
  const metrics::RunMetrics m = metrics::compute_metrics(events, p);
  int64_t log_start = events.empty() ? 0 : events.front().timestamp;
  for (const auto& e : events) log_start = std::min(log_start, e.timestamp);
  // SIM_TRUTH time -> log time: the log timestamp of the first sample at or after it.
  std::vector<std::pair<int64_t, int64_t>> truth;  // (msg utime, log timestamp)
  for (const auto& e : events) {
    evade::sim_truth_t t;
    if (e.channel == "SIM_TRUTH" && bus::decode(e.data.data(), e.data.size(), &t))
      truth.push_back({t.utime, e.timestamp});
  }
  std::sort(truth.begin(), truth.end());
  if (truth.empty()) return {};
  const int64_t t0 = truth.front().first;  // the metrics' time base
  auto log_time = [&](double since_t0_s) {
    const int64_t want = t0 + int64_t(since_t0_s * 1e6);
    auto it = std::lower_bound(truth.begin(), truth.end(), std::make_pair(want, int64_t(0)));
    if (it == truth.end()) --it;
    return double(it->second - log_start) * 1e-6;
  };
  std::vector<Moment> out;
  for (const auto& o : m.obstacles)
    if (o.t_enter_s) out.push_back({"obstacle_" + std::to_string(o.id), log_time(*o.t_enter_s)});
  if (m.closest_sample >= 0 && m.closest_sample < int(m.robot_t_s.size()))
    out.push_back({"closest", log_time(m.robot_t_s[size_t(m.closest_sample)])});
  return out;
}

}  // namespace evade::viz
