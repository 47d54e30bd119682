#include "bus/log_replay.h"

#include <algorithm>

#include "bus/memory_bus.h"

namespace evade::bus {
namespace {

bool wanted(const ReplayOptions& o, const std::string& ch) {
  return o.channels.empty() || std::find(o.channels.begin(), o.channels.end(), ch) != o.channels.end();
}

template <class Source, class Emit>
void run(const std::vector<Core*>& cores, const ReplayOptions& options, Source&& source, Emit&& emit) {
  MemoryBus bus;
  for (Core* c : cores) {
    c->set_measure_latency(false);
    bus.add(*c);
  }
  auto flush = [&] {
    for (auto& e : bus.take_published())
      if (options.keep_health || e.channel != kHealthChannel) emit(std::move(e));
  };
  source([&](const LogEvent& e) {
    if (!wanted(options, e.channel)) return;
    bus.inject(e.channel, e.data, e.timestamp);
    flush();
  });
}

}  // namespace

std::vector<LogEvent> replay(const std::vector<Core*>& cores, const std::vector<LogEvent>& input,
                             const ReplayOptions& options) {
  std::vector<LogEvent> out;
  run(
      cores, options,
      [&](auto&& fn) {
        for (const auto& e : input) fn(e);
      },
      [&](LogEvent e) { out.push_back(std::move(e)); });
  return out;
}

int64_t replay_file(const std::vector<Core*>& cores, const std::string& input_log, const std::string& output_log,
                    const ReplayOptions& options) {
  LogWriter writer(output_log);
  int64_t n = 0;
  run(
      cores, options, [&](auto&& fn) { for_each_event(input_log, fn); },
      [&](LogEvent e) {
        writer.write(e);
        ++n;
      });
  return n;
}

}  // namespace evade::bus
