// planner: Ceres MPC with discrete-time D-CBF constraints: evade's planner
// (mode evade) and the paper's Table I modes (lib/planning/modes.h). Reads
// ODOMETRY, ROUTE, OBSTACLES, OBSTACLE_PREDICTIONS; writes PLAN and CMD_VEL.
// `--mode` overrides planner.mode of the configuration.
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "bus/process_main.h"
#include "planning/planner_core.h"

int main(int argc, char** argv) {
  std::string mode;
  // The planner judges other hosts' stamps (the predictions' age):
  // it measures the clock offset to the others (lib/bus/clock_sync.h).
  evade::bus::ProcessOptions options{evade::planning::PlannerCore::conflated_inputs()};
  options.clock_sync_requests = true;
  return evade::bus::process_main(
      argc, argv, "planner",
      [&](CLI::App& app) {
        app.add_option("--mode", mode,
                       "planner mode: evade (evade's planner) | the paper's mpc | cbf | kf | cbf_curvefit | dcbf "
                       "(default: config planner.mode)")
            ->check(CLI::IsMember(evade::planning::mode_names()));
      },
      [&](const evade::config::Node& root) { return evade::planning::PlannerCore::from_config(root, mode); }, options);
}
