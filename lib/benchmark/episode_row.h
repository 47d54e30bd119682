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

// The counts of an episode's perception-metrics JSON that pool over
// episodes (lib/metrics/perception_metrics.h).
struct PerceptionCounts {
  int64_t objects = 0, matches = 0, misses = 0, false_positives = 0, splits = 0, merges = 0, id_switches = 0,
          fragmentations = 0;
  double centre_error_sum_m = 0, track_s = 0;
  int64_t predictions = 0;  // with a 2.5 s horizon scored: ade/fde weights
  std::optional<double> ade_1s_m, fde_2_5s_m, walker_ade_1s_m;
  int64_t walker_predictions = 0;
  // static structure's false motion (0 in rows from before these keys)
  int64_t static_track_frames = 0, static_moving_frames = 0;
  double static_speed_sum_mps = 0;
  double step_dt_s = 0;
  std::vector<int64_t> coverage_inside, coverage_n;  // per horizon step
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
  std::optional<PerceptionCounts> perception;  // when the row has "perception"
};

// The row (one line of JSON, no newline) for an episode whose run wrote
// metrics.json with this text. Throws std::runtime_error naming the key when
// a key of the metrics contract is missing or has the wrong type.
// With `perception_json_text` (perception-metrics output) the row gets a
// "perception" object with its poolable counts.
std::string make_row(const EpisodeId& id, const std::string& metrics_json_text,
                     const std::string& perception_json_text = "");
// The row for an episode that wrote no usable metrics.
std::string make_error_row(const EpisodeId& id, const std::string& error);

// Parses one row; throws std::runtime_error naming the key.
Episode parse_row(const std::string& line);
// Every row of a results.jsonl; errors name path:line. Blank lines are skipped.
std::vector<Episode> read_results(const std::string& path);

}  // namespace evade::benchmark
