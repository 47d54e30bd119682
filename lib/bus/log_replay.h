// Runs cores over an lcm-logger log in process: deterministic, as fast as
// the CPU allows. Every input event is delivered at its logged timestamp;
// timers fire on that clock; what the cores publish is stamped with the bus
// time it was published at and collected (or written to a new log).
// Latency measurement is off, so the same log gives byte-identical output.
#pragma once

#include <string>
#include <vector>

#include "bus/core.h"
#include "bus/log.h"

namespace evade::bus {

struct ReplayOptions {
  // Channels of the input log to deliver; empty = every channel.
  std::vector<std::string> channels;
  // Keep HEALTH heartbeats in the output.
  bool keep_health = true;
};

// In memory: returns everything the cores published.
std::vector<LogEvent> replay(const std::vector<Core*>& cores, const std::vector<LogEvent>& input,
                             const ReplayOptions& options = {});
// File to file, streaming. Returns the number of events written.
int64_t replay_file(const std::vector<Core*>& cores, const std::string& input_log, const std::string& output_log,
                    const ReplayOptions& options = {});

}  // namespace evade::bus
