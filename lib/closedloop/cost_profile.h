// Calibrating lockstep.costs: from the CPU time each callback of a
// profiled lockstep run took (LockstepRun::cpu_clock), the per-callback
// and per-item costs as config/robot.yaml holds them. CPU time, not wall
// time: the wait for a core is what the Cpu model adds.
#pragma once

#include <string>
#include <vector>

#include "closedloop/closed_loop.h"

namespace evade::closedloop {

struct CostFit {
  double base_s = 0.0;   // a callback of size 0
  double per_k_s = 0.0;  // more per unit of size (0 when every sample has the same size)
  size_t n = 0;          // samples
};

// Least-squares line cpu_s = base_s + per_k_s * k; both clamped at 0.
CostFit fit_cost(const std::vector<CpuSample>& samples);

// The `lockstep` keys a profiled run suggests, as YAML lines: costs.<p>
// for every process and the simulator, planner_base_s and
// planner_per_iteration_s (the planner's PLAN cycles less its callback_s).
std::string suggested_costs(const LockstepResult& profiled);

}  // namespace evade::closedloop
