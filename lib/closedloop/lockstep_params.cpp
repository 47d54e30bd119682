#include "closedloop/lockstep_params.h"

#include <stdexcept>

namespace evade::closedloop {

namespace {
const char* const kProcesses[] = {"lidar_driver", "elevation_map", "tracker",    "predictor",
                                  "route",        "planner",       "base_driver"};
}

PlannerCompute parse_planner_compute(const std::string& name) {
  if (name == "fixed") return PlannerCompute::kFixed;
  if (name == "iterations") return PlannerCompute::kIterations;
  if (name == "measured") return PlannerCompute::kMeasured;
  throw std::invalid_argument("planner compute model '" + name + "': expected fixed, iterations or measured");
}

LockstepParams LockstepParams::from_config(const config::Node& root) {
  const config::Node s = root.section("lockstep");
  LockstepParams p;
  p.start_utime_us = s.get<int64_t>("start_utime_us");
  if (p.start_utime_us < 0 || p.start_utime_us > (int64_t{1} << 60)) s.fail("start_utime_us", "out of range");
  p.bus_latency_s = s.get_double("bus_latency_s", 0.0, 0.1);
  p.udp_latency_s = s.get_double("udp_latency_s", 0.0, 0.1);
  p.goal_margin_s = s.get_double("goal_margin_s", 0.0, 10.0);
  p.planner_compute = parse_planner_compute(s.get_choice("planner_compute", {"fixed", "iterations", "measured"}));
  p.planner_fixed_s = s.get_double("planner_fixed_s", 0.0, 1.0);
  p.planner_base_s = s.get_double("planner_base_s", 0.0, 1.0);
  p.planner_per_iteration_s = s.get_double("planner_per_iteration_s", 0.0, 0.1);
  p.planner_measured_scale = s.get_double("planner_measured_scale", 0.0, 100.0);
  p.cpu_cores = s.get_double("cpu_cores", 0.0, 256.0);
  p.background_load_cores = s.get_double("background_load_cores", 0.0, 256.0);
  const config::Node costs = s.section("costs");
  for (const char* name : kProcesses) {
    const config::Node c = costs.section(name);
    p.costs[name] = ProcessCost{c.get_double("callback_s", 0.0, 1.0), c.get_double("publish_s", 0.0, 1.0)};
    c.close();
  }
  const config::Node sim = costs.section("sim");
  p.costs["sim"] = ProcessCost{sim.get_double("callback_s", 0.0, 1.0), 0.0, sim.get_double("packet_s", 0.0, 1.0)};
  sim.close();
  costs.close();
  s.close();
  return p;
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
