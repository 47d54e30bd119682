#include "benchmark/benchmark_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <stdexcept>
#include <tuple>

namespace evade::benchmark {
namespace {

using Json = nlohmann::ordered_json;

void remember(std::vector<std::string>& order, const std::string& name) {
  if (std::find(order.begin(), order.end(), name) == order.end()) order.push_back(name);
}

GroupSummary summarize_group(const std::string& family, const std::string& mode,
                             const std::vector<const Episode*>& rows) {
  GroupSummary g;
  g.family = family;
  g.mode = mode;
  std::vector<double> min_dist, times;
  for (const Episode* e : rows) {
    if (!e->error.empty()) {
      ++g.errors;
      continue;
    }
    ++g.episodes;
    g.successes += e->success;
    g.reached_goal += e->reached_goal;
    g.at_fault += e->collisions_at_fault > 0 || e->at_fault;
    g.not_at_fault += e->collisions_not_at_fault > 0;
    g.contacts_at_fault += e->collisions_at_fault;
    g.contacts_not_at_fault += e->collisions_not_at_fault;
    g.timeouts += e->timed_out;
    if (e->min_dist_m) min_dist.push_back(*e->min_dist_m);
    if (e->reached_goal && e->time_to_goal_s) times.push_back(*e->time_to_goal_s);
    if (e->planner_cycle_ms_p99)
      g.planner_cycle_ms_p99_max = std::max(g.planner_cycle_ms_p99_max.value_or(0.0), *e->planner_cycle_ms_p99);
  }
  g.success_ci = wilson_interval(g.successes, g.episodes);
  if (!min_dist.empty()) {
    g.min_dist_p5_m = percentile(min_dist, 0.05);
    g.min_dist_p50_m = percentile(min_dist, 0.5);
  }
  if (auto t = mean_sd(times)) g.mean_time_to_goal_s = t->mean;
  g.perception = pool_perception(rows);
  return g;
}

Json opt(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

std::string fmt(const std::optional<double>& v, const char* f) {
  if (!v) return "-";
  char b[48];
  std::snprintf(b, sizeof b, f, *v);
  return b;
}

std::string count_rate(int count, const GroupSummary& g) {
  char b[48];
  std::snprintf(b, sizeof b, "%d (%.0f %%)", count, 100.0 * g.rate(count));
  return b;
}

}  // namespace

Interval wilson_interval(int k, int n, double z) {
  if (n < 0 || k < 0 || k > n) throw std::invalid_argument("wilson_interval: need 0 <= k <= n");
  if (n == 0) return {0.0, 1.0};
  double p = static_cast<double>(k) / n;
  double z2 = z * z;
  double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  double half = z / (1.0 + z2 / n) * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) throw std::invalid_argument("percentile of no values");
  if (!(p >= 0.0 && p <= 1.0)) throw std::invalid_argument("percentile: p outside [0, 1]");
  std::sort(v.begin(), v.end());
  double pos = p * static_cast<double>(v.size() - 1);
  size_t lo = static_cast<size_t>(std::floor(pos));
  size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::optional<MeanSd> mean_sd(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  MeanSd s;
  s.n = static_cast<int>(values.size());
  for (double v : values) s.mean += v;
  s.mean /= s.n;
  if (s.n > 1) {
    double ss = 0;
    for (double v : values) ss += (v - s.mean) * (v - s.mean);
    s.sd = std::sqrt(ss / (s.n - 1));
  }
  return s;
}

void check_rows(const std::vector<Episode>& rows) {
  std::set<std::tuple<std::string, int64_t, std::string>> seen;
  std::map<std::pair<std::string, int64_t>, std::pair<std::string, std::string>> scenario;  // hash, mode
  for (const Episode& e : rows) {
    const EpisodeId& id = e.id;
    if (!seen.insert({id.family, id.seed, id.mode}).second)
      throw std::runtime_error("episode " + id.family + " seed " + std::to_string(id.seed) + " mode " + id.mode +
                               " appears twice");
    if (id.scenario_sha256.empty()) continue;
    auto [it, fresh] = scenario.insert({{id.family, id.seed}, {id.scenario_sha256, id.mode}});
    if (!fresh && it->second.first != id.scenario_sha256)
      throw std::runtime_error(id.family + " seed " + std::to_string(id.seed) + ": mode " + id.mode +
                               " ran another scenario than mode " + it->second.second +
                               " (scenario_sha256 differs): the modes are not paired");
  }
}

std::vector<GroupSummary> summarize(const std::vector<Episode>& rows) {
  std::vector<std::string> families, modes;
  for (const Episode& e : rows) {
    remember(families, e.id.family);
    remember(modes, e.id.mode);
  }
  std::vector<GroupSummary> out;
  for (const auto& f : families)
    for (const auto& m : modes) {
      std::vector<const Episode*> group;
      for (const Episode& e : rows)
        if (e.id.family == f && e.id.mode == m) group.push_back(&e);
      if (!group.empty()) out.push_back(summarize_group(f, m, group));
    }
  if (families.size() > 1)
    for (const auto& m : modes) {
      std::vector<const Episode*> group;
      for (const Episode& e : rows)
        if (e.id.mode == m) group.push_back(&e);
      out.push_back(summarize_group("all", m, group));
    }
  return out;
}

std::string summary_json(const std::vector<GroupSummary>& groups) {
  Json arr = Json::array();
  for (const auto& g : groups) {
    Json j;
    j["family"] = g.family;
    j["mode"] = g.mode;
    j["episodes"] = g.episodes;
    j["errors"] = g.errors;
    j["successes"] = g.successes;
    j["success_rate"] = g.rate(g.successes);
    j["success_ci95"] = {g.success_ci.lo, g.success_ci.hi};
    j["reached_goal"] = g.reached_goal;
    j["at_fault"] = g.at_fault;
    j["at_fault_rate"] = g.rate(g.at_fault);
    j["not_at_fault"] = g.not_at_fault;
    j["not_at_fault_rate"] = g.rate(g.not_at_fault);
    j["contacts_at_fault"] = g.contacts_at_fault;
    j["contacts_not_at_fault"] = g.contacts_not_at_fault;
    j["timeouts"] = g.timeouts;
    j["timeout_rate"] = g.rate(g.timeouts);
    j["min_dist_p5_m"] = opt(g.min_dist_p5_m);
    j["min_dist_p50_m"] = opt(g.min_dist_p50_m);
    j["mean_time_to_goal_s"] = opt(g.mean_time_to_goal_s);
    j["planner_cycle_ms_p99_max"] = opt(g.planner_cycle_ms_p99_max);
    if (g.perception) {
      const PerceptionPool& p = *g.perception;
      Json q;
      q["episodes"] = p.episodes;
      q["objects"] = p.sum.objects;
      q["mota"] = p.mota();
      q["motp_m"] = opt(p.motp_m());
      q["false_positives"] = p.sum.false_positives;
      q["splits"] = p.sum.splits;
      q["merges"] = p.sum.merges;
      q["id_switches"] = p.sum.id_switches;
      q["id_switches_per_100_track_s"] = opt(p.id_switches_per_100_track_s());
      q["fragmentations"] = p.sum.fragmentations;
      q["ade_1s_m"] = opt(p.sum.ade_1s_m);
      q["fde_2_5s_m"] = opt(p.sum.fde_2_5s_m);
      q["walker_ade_1s_m"] = opt(p.sum.walker_ade_1s_m);
      q["coverage_min_2_5s"] = opt(p.coverage_min(2.5));
      q["static_track_frames"] = p.sum.static_track_frames;
      q["static_moving_fraction"] = opt(p.static_moving_fraction());
      q["static_speed_mean_mps"] = opt(p.static_speed_mean_mps());
      j["perception"] = q;
    }
    arr.push_back(j);
  }
  Json root;
  root["groups"] = arr;
  return root.dump(2) + "\n";
}

std::string perception_markdown_table(const std::vector<GroupSummary>& groups) {
  std::string s;
  for (const auto& g : groups) {
    if (!g.perception) continue;
    const PerceptionPool& p = *g.perception;
    if (s.empty())
      s = "| family | mode | episodes | MOTA | MOTP (m) | id switches /100 track-s | splits /100 objects | ADE 1 s (m) "
          "| "
          "FDE 2.5 s (m) | walker ADE 1 s (m) | coverage, worst step to 2.5 s | static moving share | static "
          "speed (m/s) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    s += "| " + g.family + " | " + g.mode + " | " + std::to_string(p.episodes) + " | " + fmt(p.mota(), "%.3f") + " | " +
         fmt(p.motp_m(), "%.3f") + " | " + fmt(p.id_switches_per_100_track_s(), "%.2f") + " | " +
         fmt(p.sum.objects ? std::optional<double>(100.0 * p.sum.splits / p.sum.objects) : std::nullopt, "%.2f") +
         " | " + fmt(p.sum.ade_1s_m, "%.3f") + " | " + fmt(p.sum.fde_2_5s_m, "%.3f") + " | " +
         fmt(p.sum.walker_ade_1s_m, "%.3f") + " | " + fmt(p.coverage_min(2.5), "%.3f") + " | " +
         fmt(p.static_moving_fraction(), "%.3f") + " | " + fmt(p.static_speed_mean_mps(), "%.3f") + " |\n";
  }
  return s;
}

std::string markdown_table(const std::vector<GroupSummary>& groups) {
  std::string s =
      "| family | mode | episodes | success (95 % CI) | at-fault | not-at-fault | timeouts | min dist p5/p50 (m) | "
      "mean time (s) |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& g : groups) {
    char success[96];
    std::snprintf(success, sizeof success, "%.0f %% (%.0f-%.0f %%)", 100.0 * g.rate(g.successes),
                  100.0 * g.success_ci.lo, 100.0 * g.success_ci.hi);
    std::string episodes = std::to_string(g.episodes);
    if (g.errors > 0) episodes += " (+" + std::to_string(g.errors) + " errors)";
    s += "| " + g.family + " | " + g.mode + " | " + episodes + " | " + success + " | " + count_rate(g.at_fault, g) +
         " | " + count_rate(g.not_at_fault, g) + " | " + count_rate(g.timeouts, g) + " | " +
         fmt(g.min_dist_p5_m, "%.2f") + " / " + fmt(g.min_dist_p50_m, "%.2f") + " | " +
         fmt(g.mean_time_to_goal_s, "%.1f") + " |\n";
  }
  return s;
}

std::vector<ModeStats> mode_stats(const std::vector<Episode>& rows) {
  std::vector<std::string> modes;
  for (const Episode& e : rows) remember(modes, e.id.mode);
  std::vector<ModeStats> out;
  for (const auto& m : modes) {
    ModeStats s;
    s.mode = m;
    std::vector<double> dist, time, reaction, var;
    for (const Episode& e : rows) {
      if (e.id.mode != m) continue;
      if (!e.error.empty()) {
        ++s.errors;
        continue;
      }
      ++s.runs;
      s.reached_goal += e.reached_goal;
      s.runs_at_fault += e.collisions_at_fault > 0 || e.at_fault;
      s.runs_not_at_fault += e.collisions_not_at_fault > 0;
      if (e.min_dist_m) dist.push_back(*e.min_dist_m);
      if (e.reached_goal && e.time_to_goal_s) time.push_back(*e.time_to_goal_s);
      if (e.reaction_time_s) reaction.push_back(*e.reaction_time_s);
      if (e.speed_var) var.push_back(*e.speed_var);
    }
    s.min_dist_m = mean_sd(dist);
    s.time_to_goal_s = mean_sd(time);
    s.reaction_time_s = mean_sd(reaction);
    s.speed_var = mean_sd(var);
    out.push_back(s);
  }
  return out;
}

}  // namespace evade::benchmark

namespace evade::benchmark {

double PerceptionPool::mota() const {
  if (sum.objects == 0) return 1.0;
  return 1.0 -
         static_cast<double>(sum.misses + sum.false_positives + sum.id_switches) / static_cast<double>(sum.objects);
}

std::optional<double> PerceptionPool::motp_m() const {
  if (sum.matches == 0) return std::nullopt;
  return sum.centre_error_sum_m / static_cast<double>(sum.matches);
}

std::optional<double> PerceptionPool::static_moving_fraction() const {
  if (sum.static_track_frames == 0) return std::nullopt;
  return double(sum.static_moving_frames) / double(sum.static_track_frames);
}

std::optional<double> PerceptionPool::static_speed_mean_mps() const {
  if (sum.static_track_frames == 0) return std::nullopt;
  return sum.static_speed_sum_mps / double(sum.static_track_frames);
}

std::optional<double> PerceptionPool::id_switches_per_100_track_s() const {
  if (sum.track_s <= 0.0) return std::nullopt;
  return 100.0 * static_cast<double>(sum.id_switches) / sum.track_s;
}

std::optional<double> PerceptionPool::coverage_min(double horizon_s) const {
  std::optional<double> worst;
  for (size_t k = 1; k < sum.coverage_n.size() && k * sum.step_dt_s <= horizon_s + 1e-9; ++k)
    if (sum.coverage_n[k] > 0)
      worst = std::min(worst.value_or(1.0), static_cast<double>(sum.coverage_inside[k]) / sum.coverage_n[k]);
  return worst;
}

namespace {

// Weighted mean of an optional value over episodes.
struct Weighted {
  double sum = 0.0;
  int64_t weight = 0;
  void add(const std::optional<double>& v, int64_t w) {
    if (!v || w <= 0) return;
    sum += *v * static_cast<double>(w);
    weight += w;
  }
  std::optional<double> mean() const { return weight ? std::optional<double>(sum / weight) : std::nullopt; }
};

void add_steps(const PerceptionCounts& c, PerceptionCounts* s) {
  if (s->coverage_n.size() < c.coverage_n.size()) {
    s->coverage_n.resize(c.coverage_n.size(), 0);
    s->coverage_inside.resize(c.coverage_n.size(), 0);
  }
  for (size_t k = 0; k < c.coverage_n.size(); ++k) {
    s->coverage_n[k] += c.coverage_n[k];
    s->coverage_inside[k] += c.coverage_inside[k];
  }
  if (s->step_dt_s == 0.0) s->step_dt_s = c.step_dt_s;
}

}  // namespace

std::optional<PerceptionPool> pool_perception(const std::vector<const Episode*>& rows) {
  PerceptionPool p;
  Weighted ade, fde, walker;
  for (const Episode* e : rows) {
    if (!e->error.empty() || !e->perception) continue;
    const PerceptionCounts& c = *e->perception;
    ++p.episodes;
    p.sum.objects += c.objects;
    p.sum.matches += c.matches;
    p.sum.misses += c.misses;
    p.sum.false_positives += c.false_positives;
    p.sum.splits += c.splits;
    p.sum.merges += c.merges;
    p.sum.id_switches += c.id_switches;
    p.sum.fragmentations += c.fragmentations;
    p.sum.centre_error_sum_m += c.centre_error_sum_m;
    p.sum.track_s += c.track_s;
    p.sum.predictions += c.predictions;
    p.sum.walker_predictions += c.walker_predictions;
    p.sum.static_track_frames += c.static_track_frames;
    p.sum.static_moving_frames += c.static_moving_frames;
    p.sum.static_speed_sum_mps += c.static_speed_sum_mps;
    ade.add(c.ade_1s_m, c.predictions);
    fde.add(c.fde_2_5s_m, c.predictions);
    walker.add(c.walker_ade_1s_m, c.walker_predictions);
    add_steps(c, &p.sum);
  }
  if (p.episodes == 0) return std::nullopt;
  p.sum.ade_1s_m = ade.mean();
  p.sum.fde_2_5s_m = fde.mean();
  p.sum.walker_ade_1s_m = walker.mean();
  return p;
}

}  // namespace evade::benchmark
