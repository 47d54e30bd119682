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
        std::optional<std::vector<std::vector<double>>> waypoints;
        if (!scenario.empty()) waypoints = evade::sim::route_waypoints(evade::sim::load_scenario(scenario));
        auto core = evade::route::RoutePublisher::from_config(root, waypoints, scenario);
        std::fprintf(stderr, "route: %zu points\n", static_cast<size_t>(core->path().n));
        return core;
      },
      evade::bus::ProcessOptions{{}, /*publishes_signed=*/true});
}
