// The global path. The paper gets its reference path from a global planner
// (PF-RRT*); evade takes it from the robot configuration or a scenario's
// waypoints and repeats it on ROUTE so that a planner started late, or
// restarted, has it within one period.
#pragma once

#include <vector>

#include "bus/core.h"
#include "config/config.h"
#include "evade/path_t.hpp"

namespace evade::route {

struct RouteParams {
  std::vector<std::vector<double>> waypoints;  // m, [[x, y], ...] in the odometry/world frame
  double publish_period_s = 1.0;               // s between ROUTE messages

  // Reads the `route:` section; errors name file, line and key.
  static RouteParams from_config(const config::Node& section);
};

// Checks a polyline: at least two points, finite, no zero-length segment.
// Returns an empty string when valid, else the reason.
std::string validate_route(const std::vector<std::vector<double>>& waypoints);

class RoutePublisher : public bus::Core {
 public:
  explicit RoutePublisher(const RouteParams& params);
  const evade::path_t& path() const { return path_; }

 private:
  evade::path_t path_{};
};

}  // namespace evade::route
