// How long after a prediction list arrives the robot is told what to do
// about it: from an OBSTACLE_PREDICTIONS message's arrival (its log time,
// lcm-logger's receive time) to the CMD_VEL of the plan made from it (the
// first PLAN whose predictions_utime is the list's utime, and the CMD_VEL
// with that PLAN's utime logged after it). tools/plan-latency prints it.
//
// A log whose PLANs name no list (recorded before PLAN had
// predictions_utime, or migrated with it -1) is measured by the rule used
// before it existed: the first CMD_VEL logged after the list arrived
// (`by_first_cmd`), which leaves out a cycle already under way when the
// list arrived, so it may read shorter than the rule above.
#pragma once

#include <cstdint>
#include <vector>

#include "bus/log.h"

namespace evade::metrics {

struct PlanLatency {
  int64_t lists = 0;               // OBSTACLE_PREDICTIONS messages (a repeated utime counted once)
  int64_t planned = 0;             // lists with a latency below
  int64_t unplanned = 0;           // lists no plan's CMD_VEL answered (dropped while busy, stale, log ended)
  bool by_first_cmd = false;       // the log's PLANs name no list: the first CMD_VEL after arrival
  std::vector<double> latency_ms;  // per list planned from, in arrival order
  // Linear interpolation between the closest ranks, as metrics.json's
  // planner percentiles; 0 when there is no latency.
  double percentile_ms(double q) const;
};

PlanLatency plan_latency(const std::vector<bus::LogEvent>& log);

}  // namespace evade::metrics
