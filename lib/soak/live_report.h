// The verdict of a live run on a degraded bus (tools/netem-run): crashes
// (run_scenario's exit_status.tsv), collisions at fault (metrics.json), the
// memory of every process (the sampler's rss.tsv and pids.tsv), and what
// the bus lost: per channel the messages sent and dropped (bus-netem's
// counts) and what each receiver says it got in its last HEALTH. Text in,
// JSON and text out.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "soak/rss_trend.h"

namespace evade::soak {

struct ProcessExit {
  std::string name;
  int status = -1;     // -1: unknown
  bool early = false;  // had exited before the run ended
};
// "name status early" lines ('#' comments skipped); throws naming the line.
std::vector<ProcessExit> parse_exits(const std::string& text);
// A crash: an exit status other than 0 and 143 (SIGTERM, which
// run_scenario sends at the end; 137: killed after not stopping on it; -1:
// unknown). Exiting early with 0 is not one (sim ends at the scenario's
// duration, sometimes before the run monitor does).
bool is_crash(const ProcessExit& e);

struct LiveFiles {
  std::string exit_status_tsv, rss_tsv, pids_tsv, metrics_json, netem_json, health_jsonl;
};

struct ChannelLoss {
  std::string channel;
  int64_t sent = 0, dropped = 0;  // messages, as bus-netem saw them
  double mean_delay_ms = 0.0;
  bool exempt = false;
  std::map<std::string, int64_t> received;  // per receiving process (last HEALTH)
};

struct LiveReport {
  std::vector<ProcessExit> exits;
  std::vector<std::pair<std::string, RssTrend>> rss;  // per process name
  int collisions_at_fault = 0, collisions_not_at_fault = 0;
  bool reached_goal = false;
  double min_dist_m = 0.0, duration_s = 0.0;
  double loss = 0.0, delay_ms = 0.0, jitter_ms = 0.0;
  bool reorder = true;
  std::vector<ChannelLoss> channels;
  std::vector<std::string> failures;
};

// Throws std::runtime_error naming the file and what is wrong.
LiveReport make_live_report(const LiveFiles& f, double warmup_s);
std::string live_report_json(const LiveReport& r);
std::string live_report_text(const LiveReport& r);

}  // namespace evade::soak
