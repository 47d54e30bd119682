#include "route/route_publisher.h"

#include <cmath>

namespace evade::route {

RouteParams RouteParams::from_config(const config::Node& section) {
  RouteParams p;
  p.waypoints = section.get_points("waypoints");
  std::string why = validate_route(p.waypoints);
  if (!why.empty()) section.fail("waypoints", why);
  p.publish_period_s = section.get_double("publish_period_s", 0.01, 60.0);
  section.close();
  return p;
}

std::string validate_route(const std::vector<std::vector<double>>& waypoints) {
  if (waypoints.size() < 2) return "a route needs at least two points";
  for (size_t i = 0; i < waypoints.size(); ++i) {
    if (waypoints[i].size() != 2 || !std::isfinite(waypoints[i][0]) || !std::isfinite(waypoints[i][1]))
      return "point " + std::to_string(i) + " is not a finite [x, y]";
    if (i > 0 && std::hypot(waypoints[i][0] - waypoints[i - 1][0], waypoints[i][1] - waypoints[i - 1][1]) < 1e-6)
      return "points " + std::to_string(i - 1) + " and " + std::to_string(i) + " coincide";
  }
  return "";
}

RoutePublisher::RoutePublisher(const RouteParams& params) : Core("route") {
  path_.utime = 0;
  path_.n = static_cast<int32_t>(params.waypoints.size());
  for (const auto& p : params.waypoints) {
    path_.x.push_back(p[0]);
    path_.y.push_back(p[1]);
  }
  every(static_cast<int64_t>(std::llround(params.publish_period_s * 1e6)), [this] {
    path_.utime = now();  // no input caused it: stamped with the bus time
    publish("ROUTE", path_);
  });
}

}  // namespace evade::route
