#include "closedloop/lockstep_params.h"

#include <stdexcept>

namespace evade::closedloop {

const std::vector<std::string>& cost_processes() {
  static const std::vector<std::string> names = {"lidar_driver", "elevation_map", "tracker",    "predictor",
                                                 "route",        "planner",       "base_driver"};
  return names;
}

PlannerCompute parse_planner_compute(const std::string& name) {
  if (name == "fixed") return PlannerCompute::kFixed;
  if (name == "iterations") return PlannerCompute::kIterations;
  if (name == "measured") return PlannerCompute::kMeasured;
  throw std::invalid_argument("planner compute model '" + name + "': expected fixed, iterations or measured");
}

LockstepParams LockstepParams::from_config(const config::Node& root) {
  return config::load<LockstepParams>(root.section("lockstep"));
}

double LockstepParams::planner_cycle_us(int iterations, double measured_us) const {
  switch (planner_compute) {
    case PlannerCompute::kFixed:
      return planner_fixed_s * 1e6;
    case PlannerCompute::kIterations:
      return (planner_base_s + planner_per_iteration_s * iterations) * 1e6;
    case PlannerCompute::kMeasured:
      return measured_us * planner_measured_scale;
  }
  return 0.0;
}

}  // namespace evade::closedloop
