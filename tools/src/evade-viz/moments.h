// The moments of a simulated run worth a picture (evade-viz
// --snapshot-moments): each obstacle's first sight, when it enters the
// metrics' local map window (metrics.local_map_size_m around the robot,
// the reaction-time rule), and the closest approach (the metrics'
// min_dist_m sample). Times are seconds from the log's first event, as
// --at takes them.
#pragma once

#include <string>
#include <vector>

#include "bus/log.h"
#include "metrics/run_metrics.h"

namespace evade::viz {

struct Moment {
  std::string name;  // "closest", "obstacle_<id>"
  double t_s;        // seconds into the log
};

// Throws std::runtime_error when the log has no SIM_TRUTH.
std::vector<Moment> key_moments(const std::vector<bus::LogEvent>& events, const metrics::MetricsParams& p);

}  // namespace evade::viz
