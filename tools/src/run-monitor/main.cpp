// run-monitor [--lcm-url URL] [--margin-s S] [--stall-s S] [--quiet]
// Watches SIM_TRUTH and PLAN during a live scenario run: prints a progress
// line (time, distance to goal, speed, clearance, planner status) and exits
// when the goal is reached (0), when the scenario's duration has passed
// (1), or when SIM_TRUTH stops arriving for --stall-s (3). The rule is
// lib/closedloop/run_monitor.h, shared with the lockstep runner.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>

#include "bus/live_bus.h"
#include "closedloop/run_monitor.h"

int main(int argc, char** argv) {
  CLI::App app{"Progress of a scenario run; exits at the goal or the scenario's duration"};
  std::string url;
  evade::closedloop::RunMonitorParams p;
  app.add_option("--lcm-url", url, "LCM URL");
  app.add_option("--margin-s", p.margin_s, "keep watching this long after the goal is reached");
  app.add_option("--stall-s", p.stall_s, "give up when SIM_TRUTH is silent this long");
  app.add_flag("--quiet", p.quiet, "no progress line");
  CLI11_PARSE(app, argc, argv);
  p.tty = ::isatty(2) != 0;
  try {
    evade::bus::LiveBus bus(url.empty() ? evade::bus::default_lcm_url() : url);
    evade::closedloop::RunMonitor mon(p);
    bus.add(mon);
    const auto& stop = evade::bus::stop_on_signals();
    while (mon.result() < 0 && !stop.load()) bus.spin_once(50);
    return mon.result() < 0 ? 130 : mon.result();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "run-monitor: %s\n", e.what());
    return 2;
  }
}
