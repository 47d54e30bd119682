// Parameters of the lockstep closed loop (config section `lockstep`): the
// simulated costs that stand in for time on the robot. Each process is
// charged callback_s for every callback and publish_s more when the
// callback published (HEALTH aside); the planner's PLAN cycles are charged
// by the planner compute model instead:
//   fixed:      planner_fixed_s per cycle that solves
//   iterations: planner_base_s + planner_per_iteration_s x Ceres iterations
//   measured:   the cycle's steady-clock solve time x planner_measured_scale
//               (not deterministic: the only model that is not)
// The simulator is charged callback_s per callback and packet_s per VLP-16
// packet it makes. These are CPU times: the processes and the simulator
// share cpu_cores cores with background_load_cores always-runnable threads
// (Cpu, cpu.h), so a callback takes longer than its charge when more are
// runnable than there are cores; cpu_cores 0 gives each its own core.
// Defaults and how they were measured: lib/closedloop/README.md.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "config/config.h"
#include "config/fields.h"

namespace evade::closedloop {

enum class PlannerCompute { kFixed, kIterations, kMeasured };

struct ProcessCost {
  double callback_s = 0.0;
  double publish_s = 0.0;  // the evade processes: a callback that published
  double packet_s = 0.0;   // the simulator: each VLP-16 packet made
};

// The evade processes that `lockstep.costs` names (besides `sim`).
const std::vector<std::string>& cost_processes();

// `lockstep.costs`: a section per process, keyed by its name.
struct CostTable {
  std::map<std::string, ProcessCost>& costs;
  struct Process {
    ProcessCost& c;
    template <class V>
    void fields(V& v) {
      v.field("callback_s", c.callback_s, config::between(0.0, 1.0));
      v.field("publish_s", c.publish_s, config::between(0.0, 1.0));
    }
  };
  struct Sim {
    ProcessCost& c;
    template <class V>
    void fields(V& v) {
      v.field("callback_s", c.callback_s, config::between(0.0, 1.0));
      v.field("packet_s", c.packet_s, config::between(0.0, 1.0));
    }
  };
  template <class V>
  void fields(V& v) {
    for (const auto& name : cost_processes()) {
      Process p{costs[name]};
      v.section(name.c_str(), p);
    }
    Sim s{costs["sim"]};
    v.section("sim", s);
  }
};

struct LockstepParams {
  int64_t start_utime_us = 1800000000000000;  // bus time of the run's start
  double bus_latency_s = 0.0002;              // LCM publish to delivery on the host
  double udp_latency_s = 0.0001;              // LiDAR packet to the driver's socket
  double goal_margin_s = 0.5;                 // the run ends this long after the goal is reached
  PlannerCompute planner_compute = PlannerCompute::kIterations;
  double planner_fixed_s = 0.005;
  double planner_base_s = 0.00063;
  double planner_per_iteration_s = 0.000099;
  double planner_measured_scale = 1.0;
  double cpu_cores = 2.0;              // cores the processes and the simulator share (0: one each)
  double background_load_cores = 0.0;  // threads of other programs, always runnable, at the stack's weight
  std::map<std::string, ProcessCost> costs{
      // by process name (the evade processes and "sim")
      {"lidar_driver", {0.0000245, 0.0003013, 0.0}}, {"elevation_map", {0.0001086, 0.0018003, 0.0}},
      {"tracker", {0.0004211, 0.0001787, 0.0}},      {"predictor", {0.0003811, 0.0000815, 0.0}},
      {"route", {0.0018923, 0.0000008, 0.0}},        {"planner", {0.0000642, 0.0, 0.0}},
      {"base_driver", {0.0000817, 0.0000003, 0.0}},  {"sim", {0.0000308, 0.0, 0.0000473}}};

  template <class V>
  void fields(V& v) {
    v.field("start_utime_us", start_utime_us, config::between(0.0, static_cast<double>(int64_t{1} << 60)));
    v.field("bus_latency_s", bus_latency_s, config::between(0.0, 0.1));
    v.field("udp_latency_s", udp_latency_s, config::between(0.0, 0.1));
    v.field("goal_margin_s", goal_margin_s, config::between(0.0, 10.0));
    v.choice("planner_compute", planner_compute,
             config::Choices<PlannerCompute>{{"fixed", PlannerCompute::kFixed},
                                             {"iterations", PlannerCompute::kIterations},
                                             {"measured", PlannerCompute::kMeasured}});
    v.field("planner_fixed_s", planner_fixed_s, config::between(0.0, 1.0));
    v.field("planner_base_s", planner_base_s, config::between(0.0, 1.0));
    v.field("planner_per_iteration_s", planner_per_iteration_s, config::between(0.0, 0.1));
    v.field("planner_measured_scale", planner_measured_scale, config::between(0.0, 100.0));
    v.field("cpu_cores", cpu_cores, config::between(0.0, 256.0));
    v.field("background_load_cores", background_load_cores, config::between(0.0, 256.0));
    CostTable table{costs};
    v.section("costs", table);
  }
  // root = the whole configuration; reads `lockstep:`.
  static LockstepParams from_config(const config::Node& root);
  // The compute time of a planner cycle of `iterations` Ceres iterations
  // that took measured_us of steady-clock time here.
  double planner_cycle_us(int iterations, double measured_us) const;
};

// Parses "fixed" | "iterations" | "measured"; throws std::invalid_argument.
PlannerCompute parse_planner_compute(const std::string& name);

}  // namespace evade::closedloop
