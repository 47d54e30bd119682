#include "soak/soak_report.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "soak/report_text.h"

namespace evade::soak {
namespace {

using nlohmann::json;

std::string seed_list(const std::vector<uint64_t>& seeds) {
  std::string s;
  for (uint64_t k : seeds) s += (s.empty() ? "" : ", ") + std::to_string(k);
  return s;
}

EpisodeLine from_json(const json& j) {
  EpisodeLine e;
  EpisodeResult& r = e.result;
  r.family = j.at("family").get<std::string>();
  r.seed = j.at("seed").get<uint64_t>();
  e.wall_s = j.at("wall_s").get<double>();
  e.rss_kib = j.at("rss_kib").get<double>();
  e.pid = j.at("pid").get<int64_t>();
  e.t_s = j.at("t_s").get<double>();
  if (j.contains("error")) {
    e.error = j.at("error").get<std::string>();
    return e;
  }
  r.outcome = j.at("outcome").get<std::string>();
  if (r.outcome != "goal" && r.outcome != "duration" && r.outcome != "cap")
    throw std::runtime_error("outcome '" + r.outcome + "' is not goal, duration or cap");
  r.sim_s = j.at("sim_s").get<double>();
  r.events = j.at("events").get<int64_t>();
  r.reached_goal = j.at("reached_goal").get<bool>();
  r.timed_out = j.at("timed_out").get<bool>();
  r.success = j.at("success").get<bool>();
  r.collisions_at_fault = j.at("collisions_at_fault").get<int>();
  r.collisions_not_at_fault = j.at("collisions_not_at_fault").get<int>();
  r.min_dist_m = j.at("min_dist_m").get<double>();
  return e;
}

void count_episode(SoakReport& r, const EpisodeLine& e) {
  const EpisodeResult& x = e.result;
  if (r.episodes == 0 && r.errors.empty()) r.family = x.family, r.first_seed = x.seed;
  r.first_seed = std::min(r.first_seed, x.seed);
  r.last_seed = std::max(r.last_seed, x.seed);
  r.episode_wall_s += e.wall_s;
  if (!e.error.empty()) {
    r.errors.push_back(e);
    return;
  }
  ++r.episodes;
  r.sim_s += x.sim_s;
  r.goal += x.outcome == "goal";
  r.duration += x.outcome == "duration";
  r.cap += x.outcome == "cap";
  r.success += x.success;
  if (x.collisions_at_fault > 0) r.at_fault_seeds.push_back(x.seed);
  r.collisions_not_at_fault_episodes += x.collisions_not_at_fault > 0;
}

void judge(SoakReport& r) {
  if (!r.crashes.empty()) r.failures.push_back(std::to_string(r.crashes.size()) + " process crash(es)");
  if (!r.errors.empty()) r.failures.push_back(std::to_string(r.errors.size()) + " episode(s) ended in an error");
  if (!r.at_fault_seeds.empty())
    r.failures.push_back("collision at fault in " + std::to_string(r.at_fault_seeds.size()) + " episode(s): seeds " +
                         seed_list(r.at_fault_seeds));
  for (const auto& t : r.settled) {
    if (!t.growth_mib_per_h)
      r.failures.push_back("pid " + std::to_string(t.pid) + ": too few memory samples after the warm-up to fit");
    else if (*t.growth_mib_per_h > r.limits.max_growth_mib_per_h)
      r.failures.push_back("pid " + std::to_string(t.pid) + ": memory grows " + fmt("%.2f", *t.growth_mib_per_h) +
                           " MiB/h, above the bound " + fmt("%.2f", r.limits.max_growth_mib_per_h));
  }
  if (r.settled.empty()) r.failures.push_back("no memory samples");
  if (r.episodes == 0) r.failures.push_back("no episode finished");
}

}  // namespace

std::string episode_line_json(const EpisodeLine& e) {
  const EpisodeResult& r = e.result;
  json j = {{"family", r.family}, {"seed", r.seed}, {"wall_s", e.wall_s},
            {"pid", e.pid},       {"t_s", e.t_s},   {"rss_kib", e.rss_kib}};
  if (!e.error.empty()) {
    j["error"] = e.error;
    return j.dump();
  }
  j.update({{"outcome", r.outcome},
            {"sim_s", r.sim_s},
            {"events", r.events},
            {"reached_goal", r.reached_goal},
            {"timed_out", r.timed_out},
            {"success", r.success},
            {"collisions_at_fault", r.collisions_at_fault},
            {"collisions_not_at_fault", r.collisions_not_at_fault},
            {"min_dist_m", r.min_dist_m}});
  return j.dump();
}

std::vector<EpisodeLine> parse_episode_lines(const std::string& jsonl) {
  std::vector<EpisodeLine> out;
  for_each_json_line(jsonl, "", [&](const json& record) { out.push_back(from_json(record)); });
  return out;
}

std::vector<Crash> parse_crashes(const std::string& text) {
  std::vector<Crash> out;
  for_each_line(text, true, [&](const std::string& line, int n) {
    std::istringstream ls(line);
    Crash c;
    std::string extra;
    if (!(ls >> c.t_s >> c.seed >> c.status) || (ls >> extra))
      throw std::runtime_error("line " + std::to_string(n) + ": want 't_s seed exit_status', got '" + line + "'");
    out.push_back(c);
  });
  return out;
}

SoakReport make_report(const std::vector<EpisodeLine>& episodes, const std::vector<Crash>& crashes,
                       const std::vector<RssSample>& rss, const SoakLimits& limits) {
  SoakReport r;
  r.limits = limits;
  r.crashes = crashes;
  for (const auto& e : episodes) count_episode(r, e);
  r.rss = rss_trends(rss, limits.warmup_s);
  std::vector<RssSample> after;
  for (const auto& e : episodes) after.push_back({e.t_s, e.pid, e.rss_kib, 0.0});
  r.settled = rss_trends(after, limits.warmup_s);
  if (!rss.empty()) {
    double sum = 0, mx = 0;
    for (const auto& s : rss) sum += s.load1, mx = std::max(mx, s.load1);
    r.load1_mean = sum / rss.size();
    r.load1_max = mx;
  }
  judge(r);
  return r;
}

std::string report_json(const SoakReport& r) {
  const auto trends = [](const std::vector<RssTrend>& ts) {
    json out = json::array();
    for (const auto& t : ts) {
      json trend = trend_json(t);
      trend["samples"] = t.samples;
      out.push_back(trend);
    }
    return out;
  };
  json crashes = json::array();
  for (const auto& c : r.crashes) crashes.push_back({{"t_s", c.t_s}, {"seed", c.seed}, {"exit_status", c.status}});
  json errors = json::array();
  for (const auto& e : r.errors) errors.push_back({{"seed", e.result.seed}, {"error", e.error}});
  json j = {{"family", r.family},
            {"episodes", r.episodes},
            {"first_seed", r.first_seed},
            {"last_seed", r.last_seed},
            {"goal", r.goal},
            {"duration", r.duration},
            {"cap", r.cap},
            {"success", r.success},
            {"sim_s", r.sim_s},
            {"episode_wall_s", r.episode_wall_s},
            {"crashes", crashes},
            {"episode_errors", errors},
            {"at_fault_seeds", r.at_fault_seeds},
            {"episodes_with_contact_not_at_fault", r.collisions_not_at_fault_episodes},
            {"rss_sampled", trends(r.rss)},
            {"rss_after_episodes", trends(r.settled)},
            {"load1_mean", r.load1_mean ? json(*r.load1_mean) : json(nullptr)},
            {"load1_max", r.load1_max ? json(*r.load1_max) : json(nullptr)},
            {"max_growth_mib_per_h", r.limits.max_growth_mib_per_h},
            {"warmup_s", r.limits.warmup_s},
            {"failures", r.failures},
            {"pass", r.failures.empty()}};
  return j.dump(2);
}

std::string report_text(const SoakReport& r) {
  std::ostringstream o;
  o << "soak: " << r.family << ", " << r.episodes << " episodes (seeds " << r.first_seed << "-" << r.last_seed << "), "
    << fmt("%.0f", r.sim_s) << " s simulated in " << fmt("%.0f", r.episode_wall_s) << " s of episodes\n";
  o << "  outcomes: goal " << r.goal << ", duration passed " << r.duration << ", safety cap " << r.cap << "; success "
    << r.success << "\n";
  o << "  crashes: " << r.crashes.size() << " process(es) died, " << r.errors.size() << " episode error(s)\n";
  o << "  collisions at fault: " << r.at_fault_seeds.size() << " episode(s)"
    << (r.at_fault_seeds.empty() ? "" : " (seeds " + seed_list(r.at_fault_seeds) + ")") << "; contacts not at fault in "
    << r.collisions_not_at_fault_episodes << "\n";
  const auto growth = [](const RssTrend& t) {
    return t.growth_mib_per_h ? fmt("%+.2f", *t.growth_mib_per_h) : std::string("-");
  };
  for (const auto& t : r.rss)
    o << "  RSS sampled, pid " << t.pid << ": start " << fmt("%.1f", t.start_mib) << " MiB, max "
      << fmt("%.1f", t.max_mib) << ", end " << fmt("%.1f", t.end_mib) << " over " << fmt("%.0f", t.span_s) << " s ("
      << t.samples << " samples; fit " << growth(t) << " MiB/h)\n";
  for (const auto& t : r.settled)
    o << "  RSS after each episode, pid " << t.pid << ": first " << fmt("%.1f", t.start_mib) << " MiB, max "
      << fmt("%.1f", t.max_mib) << ", last " << fmt("%.1f", t.end_mib) << "; growth " << growth(t) << " MiB/h (fit of "
      << t.fitted << " episodes after " << fmt("%.0f", r.limits.warmup_s) << " s; bound "
      << fmt("%.2f", r.limits.max_growth_mib_per_h) << ")\n";
  if (r.load1_mean)
    o << "  host load (1-min average): mean " << fmt("%.2f", *r.load1_mean) << ", max " << fmt("%.2f", *r.load1_max)
      << "\n";
  o << verdict_text(r.failures);
  return o.str();
}

}  // namespace evade::soak
