// Compares a process's replayed outputs with reference outputs, message by
// message and field by field (through the generic schema decoder), the way
// openpilot's process_replay does: integers and strings exactly, floating
// point within |a - b| <= abs_tol + rel_tol * |b| (NaN equals NaN), arrays
// by length then element. The first differences are reported with their
// path, e.g. "PLAN#12.v[3]: 0.51 vs 0.52".
#pragma once

#include <map>
#include <string>
#include <vector>

#include "bus/log.h"

namespace evade::bus {

struct Tolerance {
  double abs_tol = 1e-9;
  double rel_tol = 1e-9;
};

struct DiffOptions {
  Tolerance default_tolerance;
  std::map<std::string, Tolerance> per_channel;
  std::vector<std::string> ignore_channels = {"HEALTH"};
  // Fields never compared, e.g. wall-clock solve times: "PLAN.solve_time_us".
  std::vector<std::string> ignore_fields;
  size_t max_reports = 20;
};

struct DiffReport {
  size_t compared_messages = 0;
  size_t differing_messages = 0;
  std::vector<std::string> lines;  // human-readable, at most max_reports
  bool same() const { return differing_messages == 0 && lines.empty(); }
};

DiffReport diff_logs(const std::vector<LogEvent>& actual, const std::vector<LogEvent>& reference,
                     const DiffOptions& options);

}  // namespace evade::bus
