#include "route/route_publisher.h"

#include <cmath>
#include <stdexcept>

namespace evade::route {

RouteParams RouteParams::from_config(const config::Node& section) { return config::load<RouteParams>(section); }

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

std::string validate_route(const evade::path_t& path) {
  if (path.n < 0 || path.x.size() != static_cast<size_t>(path.n) || path.y.size() != static_cast<size_t>(path.n))
    return "n does not match x and y";
  std::vector<std::vector<double>> points;
  for (int32_t i = 0; i < path.n; ++i) points.push_back({path.x[i], path.y[i]});
  return validate_route(points);
}

evade::path_t make_path(const std::vector<std::vector<double>>& waypoints, int64_t utime) {
  evade::path_t path;
  path.utime = utime;
  path.n = static_cast<int32_t>(waypoints.size());
  for (const auto& p : waypoints) {
    path.x.push_back(p.at(0));
    path.y.push_back(p.at(1));
  }
  return path;
}

std::vector<std::vector<double>> route_to(double x0, double y0, double x, double y) {
  std::vector<std::vector<double>> points{{x0, y0}, {x, y}};
  const std::string why = validate_route(points);
  if (!why.empty()) throw std::invalid_argument("route from the robot to the goal: " + why);
  return points;
}

std::vector<std::vector<double>> load_route_file(const std::string& path) {
  const config::Node root = config::load_file(path);
  std::vector<std::vector<double>> points = root.get_points("route");
  const std::string why = validate_route(points);
  if (!why.empty()) root.fail("route", why);
  root.close();
  return points;
}

std::unique_ptr<RoutePublisher> RoutePublisher::from_config(
    const config::Node& root, const std::optional<std::vector<std::vector<double>>>& waypoints,
    const std::string& source) {
  RouteParams params = RouteParams::from_config(root.section("route"));
  if (waypoints) {
    params.waypoints = *waypoints;
    const std::string why = validate_route(params.waypoints);
    if (!why.empty()) throw config::ConfigError(source + ":0: key 'route': " + why);
  }
  return std::make_unique<RoutePublisher>(params);
}

RoutePublisher::RoutePublisher(const RouteParams& params) : Core("route") {
  path_ = make_path(params.waypoints, 0);
  subscribe<evade::path_t>("ROUTE", [this](const evade::path_t& msg) { on_route(msg); });
  every(static_cast<int64_t>(std::llround(params.publish_period_s * 1e6)), [this] {
    path_.utime = now();  // no input caused it: stamped with the bus time
    publish("ROUTE", path_);
  });
}

void RoutePublisher::on_route(const evade::path_t& msg) {
  if (msg.x == path_.x && msg.y == path_.y) return;  // ours, heard back
  const std::string why = validate_route(msg);
  if (!why.empty()) {
    count("route_rejected");
    return;
  }
  path_.n = msg.n;
  path_.x = msg.x;
  path_.y = msg.y;
  count("route_replaced");
}

}  // namespace evade::route
