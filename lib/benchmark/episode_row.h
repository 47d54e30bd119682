// One benchmark episode as one line of results.jsonl (docs/benchmark.md,
// "Row schema"): made from an episode's metrics.json, read back for the
// summary.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace evade::benchmark {

// What the episode runner knows besides the metrics.
struct EpisodeId {
  std::string family;
  int64_t seed = 0;
  std::string mode;  // "default": the planner mode from the config
  std::string host;  // GNU parallel's sshlogin (":" = this machine)
  std::string scenario_sha256;
  int exit_code = 0;  // run_scenario's
  double wall_s = 0;  // wall-clock seconds the episode took
  std::string dir;    // where its files are kept, relative to the benchmark's DIR
};

struct Episode {
  EpisodeId id;
  std::string error;  // non-empty: the episode produced no metrics (why)
  bool success = false;
  bool reached_goal = false;
  bool collided = false;
  bool at_fault = false;
  bool timed_out = false;
  int collisions_at_fault = 0;
  int collisions_not_at_fault = 0;
  std::optional<double> min_dist_m;
  std::optional<double> time_to_goal_s;
  std::optional<double> planner_cycle_ms_p99;
  std::optional<double> reaction_time_s;
  std::optional<double> speed_var;
};

// The row (one line of JSON, no newline) for an episode whose run wrote
// metrics.json with this text. Throws std::runtime_error naming the key when
// a key of the metrics contract is missing or has the wrong type.
std::string make_row(const EpisodeId& id, const std::string& metrics_json_text);
// The row for an episode that wrote no usable metrics.
std::string make_error_row(const EpisodeId& id, const std::string& error);

// Parses one row; throws std::runtime_error naming the key.
Episode parse_row(const std::string& line);
// Every row of a results.jsonl; errors name path:line. Blank lines are skipped.
std::vector<Episode> read_results(const std::string& path);

}  // namespace evade::benchmark
