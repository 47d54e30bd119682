// Log-playback regression, the way openpilot's process_replay does it: each
// process core is fed its logged inputs through the log adapter, and its
// outputs are compared with reference outputs kept in the repository, with
// documented float tolerances. References change only on purpose, with
// `process-replay --update-refs`.
//
// A case is a folder logs/<case>/ holding input.lcmlog (a few seconds of a
// simulator run: raw LiDAR packets as LIDAR_SCAN, ODOMETRY, ROUTE and the
// intermediate channels) and refs/<process>.lcmlog. The processes run with
// the repository's config/robot.yaml, so a change of parameters shows up as
// a behaviour change too.
#pragma once

#include <string>
#include <vector>

#include "bus/log.h"
#include "bus/log_diff.h"
#include "config/config.h"

namespace evade::replay {

struct ProcessCase {
  std::string process;              // e.g. "tracker"
  std::vector<std::string> inputs;  // channels of input.lcmlog it is fed
  bus::DiffOptions diff;            // how its outputs are compared
  std::string why;                  // one line: what is fed and compared
};

// Every replayed process, in pipeline order.
const std::vector<ProcessCase>& process_cases();

// Runs one process core over a case's input log (deterministic) and returns
// what it published, HEALTH left out. LIDAR_POINTS are thinned to every
// kPointStride-th point so references stay small.
std::vector<bus::LogEvent> run_process(const ProcessCase& pc, const std::vector<bus::LogEvent>& input,
                                       const config::Node& root);
inline constexpr int kPointStride = 64;

// Cuts a run log to [start_s, start_s + duration_s) after its first event,
// keeping the given channels, and repeats the last ROUTE before the window
// at its start (the route is published once a second).
std::vector<bus::LogEvent> cut_case(const std::vector<bus::LogEvent>& run, double start_s, double duration_s,
                                    const std::vector<std::string>& channels);

}  // namespace evade::replay
