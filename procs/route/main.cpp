// route: publishes the reference path on ROUTE, from the `route:` section of
// the configuration or, with --scenario, from the scenario's `route:`.
#include <cstdio>

#include "bus/process_main.h"
#include "route/route_publisher.h"
#include "sim/scenario.h"

int main(int argc, char** argv) {
  std::string scenario;
  return evade::bus::process_main(
      argc, argv, "route",
      [&](CLI::App& app) { app.add_option("--scenario", scenario, "take the route from this scenario file"); },
      [&](const evade::config::Node& root) {
        auto params = evade::route::RouteParams::from_config(root.section("route"));
        if (!scenario.empty()) {
          evade::sim::Scenario sc = evade::sim::load_scenario(scenario);
          params.waypoints.clear();
          for (const auto& p : sc.route) params.waypoints.push_back({p.x, p.y});
          std::string why = evade::route::validate_route(params.waypoints);
          if (!why.empty()) throw evade::config::ConfigError(scenario + ":0: key 'route': " + why);
        }
        std::fprintf(stderr, "route: %zu points\n", params.waypoints.size());
        return std::make_unique<evade::route::RoutePublisher>(params);
      },
      evade::bus::ProcessOptions{{}, /*publishes_signed=*/true});
}
