// plan-latency LOG: from each prediction list's arrival to the CMD_VEL of
// the plan made from it (lib/metrics/plan_latency.h), p50 / p99 / max over
// the log. Exit 0, 1 when the log has no latency to show, 2 on bad usage.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "bus/log.h"
#include "metrics/plan_latency.h"

int main(int argc, char** argv) {
  CLI::App app{"evade plan-latency: prediction list arrival -> CMD_VEL of the plan made from it"};
  std::string path;
  app.add_option("log", path, "an lcm-logger log (live or lockstep run, golden input)")
      ->required()
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  evade::metrics::PlanLatency r;
  try {
    r = evade::metrics::plan_latency(evade::bus::read_log(path));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "plan-latency: %s: %s\n", path.c_str(), e.what());
    return 2;
  }
  std::printf("%s: %lld prediction lists, %lld answered, %lld not (dropped, stale or at the log's end)\n", path.c_str(),
              static_cast<long long>(r.lists), static_cast<long long>(r.planned), static_cast<long long>(r.unplanned));
  if (r.latency_ms.empty()) {
    std::printf("no latency: no prediction list was followed by a CMD_VEL\n");
    return 1;
  }
  std::printf("arrival -> CMD_VEL (%s): p50 %.1f ms  p99 %.1f ms  max %.1f ms\n",
              r.by_first_cmd ? "PLANs name no list: the first CMD_VEL after arrival" : "of the plan made from it",
              r.percentile_ms(0.5), r.percentile_ms(0.99), r.percentile_ms(1.0));
  return 0;
}
