// The trajectory picture of a run: robot path coloured by speed, obstacles'
// paths, the route, start and goal, and the closest approach marked.
#pragma once

#include <string>

#include "metrics/run_metrics.h"

namespace evade::metrics {

// Writes a PNG; throws std::runtime_error if it cannot be written.
void plot_trajectory(const RunMetrics& m, const std::string& png_path);

}  // namespace evade::metrics
