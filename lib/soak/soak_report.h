// The verdict of a soak (tools/soak): what its episodes, crashes and memory
// samples say, against its limits. Text in (the files the soak writes),
// JSON and a few lines of text out; no clock, no process.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "soak/rss_trend.h"
#include "soak/soak_episode.h"

namespace evade::soak {

// One line of episodes.jsonl: an episode's result, or the error that ended
// it (an exception out of the stack: counted as a crash).
struct EpisodeLine {
  EpisodeResult result;
  std::string error;     // empty: a result
  double wall_s = 0.0;   // the episode's wall time
  int64_t pid = 0;       // the soak process that ran it
  double t_s = 0.0;      // when it ended, seconds since that process started
  double rss_kib = 0.0;  // the process's VmRSS after it, freed memory returned (malloc_trim)
};
std::string episode_line_json(const EpisodeLine& e);
// Throws std::runtime_error naming the line when a line is not an episode.
std::vector<EpisodeLine> parse_episode_lines(const std::string& jsonl);

// A process of the soak that died: "t_s seed exit_status" per line of
// crashes.tsv (the seed the process was running; status 128 + N: signal N).
struct Crash {
  double t_s = 0.0;
  uint64_t seed = 0;
  int status = 0;
};
std::vector<Crash> parse_crashes(const std::string& text);  // throws std::runtime_error naming the line

struct SoakLimits {
  double max_growth_mib_per_h = 0.0;
  double warmup_s = 0.0;
};

struct SoakReport {
  std::string family;
  int episodes = 0, goal = 0, duration = 0, cap = 0, success = 0;
  double sim_s = 0.0, episode_wall_s = 0.0;
  uint64_t first_seed = 0, last_seed = 0;
  std::vector<Crash> crashes;            // processes that died
  std::vector<EpisodeLine> errors;       // episodes that threw
  std::vector<uint64_t> at_fault_seeds;  // episodes with a collision at fault
  int collisions_not_at_fault_episodes = 0;
  std::vector<RssTrend> rss;      // one per soak process: the sampler's /proc readings
  std::vector<RssTrend> settled;  // one per soak process: the RSS after each episode (judged)
  std::optional<double> load1_mean, load1_max;
  SoakLimits limits;
  std::vector<std::string> failures;  // why the soak fails; empty: it passes
};

SoakReport make_report(const std::vector<EpisodeLine>& episodes, const std::vector<Crash>& crashes,
                       const std::vector<RssSample>& rss, const SoakLimits& limits);
std::string report_json(const SoakReport& r);
std::string report_text(const SoakReport& r);

}  // namespace evade::soak
