// Statistics over benchmark episodes (rows of results.jsonl): per family and
// mode, success rate with its 95 % Wilson interval, collision and timeout
// rates, min-distance percentiles; per mode, mean and standard deviation of
// the Table I metrics. The rules are in docs/benchmark.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "benchmark/episode_row.h"

namespace evade::benchmark {

struct Interval {
  double lo = 0, hi = 0;
};
// Wilson score interval for k successes in n trials; z = 1.96 gives 95 %.
// n = 0 gives [0, 1]. Throws std::invalid_argument unless 0 <= k <= n.
Interval wilson_interval(int k, int n, double z = 1.959963984540054);

// The p-th quantile (0 <= p <= 1) by linear interpolation between the closest
// ranks (position p * (n - 1) in the sorted values; numpy's default).
// Throws std::invalid_argument for no values or p outside [0, 1].
double percentile(std::vector<double> values, double p);

struct MeanSd {
  int n = 0;
  double mean = 0;
  double sd = 0;  // sample standard deviation (n - 1); 0 for n = 1
};
std::optional<MeanSd> mean_sd(const std::vector<double>& values);  // none for no values

// Perception pooled over a group's episodes that carry it: rates from the
// summed counts, displacement errors weighted by each episode's scored
// predictions, coverage per step from the summed counts.
struct PerceptionPool {
  int episodes = 0;
  PerceptionCounts sum;  // counts summed; ade/fde here are weighted means
  double mota() const;
  std::optional<double> motp_m() const;
  std::optional<double> id_switches_per_100_track_s() const;
  std::optional<double> coverage_min(double horizon_s) const;  // worst step in (0, horizon_s]
  // static structure's false motion: share of its track-frames published
  // faster than static_max_speed_mps, and their mean published speed
  std::optional<double> static_moving_fraction() const;
  std::optional<double> static_speed_mean_mps() const;
};
std::optional<PerceptionPool> pool_perception(const std::vector<const Episode*>& rows);

struct GroupSummary {
  std::string family;  // "all": every family together
  std::string mode;
  int episodes = 0;  // with metrics
  int errors = 0;    // without (the stack or the tools failed; not in any rate)
  int successes = 0;
  Interval success_ci;
  int reached_goal = 0;
  int at_fault = 0;      // episodes with a contact at fault
  int not_at_fault = 0;  // episodes with a contact not at fault
  int contacts_at_fault = 0, contacts_not_at_fault = 0;
  int timeouts = 0;
  std::optional<double> min_dist_p5_m, min_dist_p50_m;
  std::optional<double> mean_time_to_goal_s;  // over the episodes that reached the goal
  std::optional<double> planner_cycle_ms_p99_max;
  std::optional<PerceptionPool> perception;
  double rate(int count) const { return episodes > 0 ? static_cast<double>(count) / episodes : 0.0; }
};

// Throws std::runtime_error when one (family, seed, mode) appears twice, or
// when one (family, seed) was run on scenarios with different hashes (the
// paired comparison across modes would be void).
void check_rows(const std::vector<Episode>& rows);

// One group per family and mode, families and modes in order of first
// appearance; when there is more than one family, one "all" group per mode
// after them.
std::vector<GroupSummary> summarize(const std::vector<Episode>& rows);

std::string summary_json(const std::vector<GroupSummary>& groups);
// family | mode | episodes | success (95 % CI) | at-fault | not-at-fault |
// timeouts | min dist p5/p50 | mean time
std::string markdown_table(const std::vector<GroupSummary>& groups);
// family | mode | episodes | MOTA | MOTP | id switches /100 track-s | splits /100 objects |
// ADE 1 s | FDE 2.5 s | walker ADE 1 s | coverage (worst step to 2.5 s);
// empty when no group has perception.
std::string perception_markdown_table(const std::vector<GroupSummary>& groups);

// Table I over many runs: per mode (in order of first appearance).
struct ModeStats {
  std::string mode;
  int runs = 0, errors = 0, reached_goal = 0;
  int runs_at_fault = 0, runs_not_at_fault = 0;  // runs with at least one such contact
  std::optional<MeanSd> min_dist_m, time_to_goal_s, reaction_time_s, speed_var;
};
std::vector<ModeStats> mode_stats(const std::vector<Episode>& rows);

}  // namespace evade::benchmark
