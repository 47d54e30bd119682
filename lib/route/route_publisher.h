// The global path. The paper gets its reference path from a global planner
// (PF-RRT*); evade takes it from the robot configuration or a scenario's
// waypoints and repeats it on ROUTE so that a planner started late, or
// restarted, has it within one period. A valid ROUTE that somebody else
// publishes (tools/goto) replaces it: the last route on the bus is the one
// repeated. An invalid one is counted (`route_rejected`) and ignored.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus/core.h"
#include "config/config.h"
#include "config/fields.h"
#include "evade/path_t.hpp"

namespace evade::route {

// Checks a polyline: at least two points, finite, no zero-length segment.
// Returns an empty string when valid, else the reason.
std::string validate_route(const std::vector<std::vector<double>>& waypoints);
std::string validate_route(const evade::path_t& path);

struct RouteParams {
  std::vector<std::vector<double>> waypoints{{0.0, 0.0}, {20.0, 0.0}};  // m, [[x, y], ...] in the odometry/world frame
  double publish_period_s = 1.0;                                        // s between ROUTE messages

  template <class V>
  void fields(V& v) {
    v.field("waypoints", waypoints);
    const std::string why = validate_route(waypoints);
    v.rule(why.empty(), "waypoints", why);
    v.field("publish_period_s", publish_period_s, config::between(0.01, 60.0));
  }

  // Reads the `route:` section; errors name file, line and key.
  static RouteParams from_config(const config::Node& section);
};

// A ROUTE message of these waypoints (not validated).
evade::path_t make_path(const std::vector<std::vector<double>>& waypoints, int64_t utime);
// tools/goto X Y: the straight route from the robot's position (x0, y0) to
// (x, y); throws std::invalid_argument when it is not a valid route.
std::vector<std::vector<double>> route_to(double x0, double y0, double x, double y);
// A route file: YAML with the one key `route: [[x, y], ...]` (metres, the
// odometry/world frame), read strictly; errors (ConfigError) name file,
// line and key.
std::vector<std::vector<double>> load_route_file(const std::string& path);

class RoutePublisher : public bus::Core {
 public:
  explicit RoutePublisher(const RouteParams& params);
  // The core of the whole configuration (the `route:` section). Given
  // `waypoints` (a scenario's route, read from `source`), they replace
  // route.waypoints; invalid ones throw ConfigError "source:0: key 'route':
  // reason".
  static std::unique_ptr<RoutePublisher> from_config(
      const config::Node& root, const std::optional<std::vector<std::vector<double>>>& waypoints = std::nullopt,
      const std::string& source = "");
  const evade::path_t& path() const { return path_; }

 private:
  void on_route(const evade::path_t& msg);
  evade::path_t path_{};
};

}  // namespace evade::route
