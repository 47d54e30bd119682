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

#include "config/config.h"

namespace evade::closedloop {

enum class PlannerCompute { kFixed, kIterations, kMeasured };

struct ProcessCost {
  double callback_s = 0.0;
  double publish_s = 0.0;  // the evade processes: a callback that published
  double packet_s = 0.0;   // the simulator: each VLP-16 packet made
};

struct LockstepParams {
  int64_t start_utime_us = 0;  // bus time of the run's start
  double bus_latency_s = 0.0;  // LCM publish to delivery on the host
  double udp_latency_s = 0.0;  // LiDAR packet to the driver's socket
  double goal_margin_s = 0.5;  // the run ends this long after the goal is reached
  PlannerCompute planner_compute = PlannerCompute::kIterations;
  double planner_fixed_s = 0.0;
  double planner_base_s = 0.0;
  double planner_per_iteration_s = 0.0;
  double planner_measured_scale = 1.0;
  double cpu_cores = 2.0;                    // cores the processes and the simulator share (0: one each)
  double background_load_cores = 0.0;        // threads of other programs, always runnable, at the stack's weight
  std::map<std::string, ProcessCost> costs;  // by process name (the evade processes and "sim")

  static LockstepParams from_config(const config::Node& root);
  // The compute time of a planner cycle of `iterations` Ceres iterations
  // that took measured_us of steady-clock time here.
  double planner_cycle_us(int iterations, double measured_us) const;
};

// Parses "fixed" | "iterations" | "measured"; throws std::invalid_argument.
PlannerCompute parse_planner_compute(const std::string& name);

}  // namespace evade::closedloop
