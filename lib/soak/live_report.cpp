#include "soak/live_report.h"

#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "soak/report_text.h"

namespace evade::soak {
namespace {

using nlohmann::json;

std::map<int64_t, std::string> parse_pids(const std::string& text) {
  std::map<int64_t, std::string> out;
  for_each_line(text, true, [&](const std::string& line, int n) {
    std::istringstream ls(line);
    int64_t pid;
    std::string name;
    if (!(ls >> pid >> name)) throw std::runtime_error("pids.tsv line " + std::to_string(n) + ": want 'pid name'");
    out[pid] = name;
  });
  return out;
}

// The last HEALTH of each process: channel -> received.
std::map<std::string, std::map<std::string, int64_t>> last_health(const std::string& jsonl) {
  std::map<std::string, std::map<std::string, int64_t>> out;
  for_each_json_line(jsonl, "HEALTH ", [&](const json& record) {
    const json& msg = record.at("msg");
    auto& inputs = out[msg.at("name").get<std::string>()];
    inputs.clear();
    for (const auto& i : msg.at("inputs")) inputs[i.at("channel").get<std::string>()] = i.at("received").get<int64_t>();
  });
  return out;
}

void read_channels(LiveReport& r, const json& netem, const std::string& health_jsonl) {
  r.loss = netem.at("loss").get<double>();
  r.delay_ms = 1e3 * netem.at("delay_s").get<double>();
  r.jitter_ms = 1e3 * netem.at("jitter_s").get<double>();
  r.reorder = netem.at("reorder").get<bool>();
  const auto health = last_health(health_jsonl);
  for (const auto& [name, c] : netem.at("channels").items()) {
    ChannelLoss ch;
    ch.channel = name;
    ch.sent = c.at("messages").get<int64_t>();
    ch.dropped = c.at("messages_lost").get<int64_t>();
    ch.mean_delay_ms = c.at("mean_delay_ms").get<double>();
    ch.exempt = c.at("exempt").get<bool>();
    for (const auto& [proc, inputs] : health)
      if (auto it = inputs.find(name); it != inputs.end()) ch.received[proc] = it->second;
    r.channels.push_back(ch);
  }
}

void judge(LiveReport& r) {
  for (const auto& e : r.exits)
    if (is_crash(e))
      r.failures.push_back(e.name + (e.early ? " exited before the run ended" : " ended") + " with exit status " +
                           std::to_string(e.status));
  if (r.collisions_at_fault > 0) r.failures.push_back(std::to_string(r.collisions_at_fault) + " collision(s) at fault");
}

}  // namespace

std::vector<ProcessExit> parse_exits(const std::string& text) {
  std::vector<ProcessExit> out;
  for_each_line(text, true, [&](const std::string& line, int n) {
    std::istringstream ls(line);
    ProcessExit e;
    std::string status, early;
    if (!(ls >> e.name >> status >> early) || (early != "yes" && early != "no"))
      throw std::runtime_error("exit_status.tsv line " + std::to_string(n) + ": want 'name status yes|no', got '" +
                               line + "'");
    e.status = status == "unknown" ? -1 : std::stoi(status);
    e.early = early == "yes";
    out.push_back(e);
  });
  return out;
}

bool is_crash(const ProcessExit& e) { return e.status != 0 && e.status != 143; }

LiveReport make_live_report(const LiveFiles& f, double warmup_s) {
  LiveReport r;
  r.exits = parse_exits(f.exit_status_tsv);
  const auto names = parse_pids(f.pids_tsv);
  for (const auto& t : rss_trends(parse_rss_samples(f.rss_tsv), warmup_s)) {
    auto it = names.find(t.pid);
    r.rss.emplace_back(it == names.end() ? "pid " + std::to_string(t.pid) : it->second, t);
  }
  const json m = parse_json(f.metrics_json, "metrics.json");
  try {
    r.collisions_at_fault = m.at("collisions_at_fault").get<int>();
    r.collisions_not_at_fault = m.at("collisions_not_at_fault").get<int>();
    r.reached_goal = m.at("reached_goal").get<bool>();
    r.min_dist_m = m.at("min_dist_m").get<double>();
    r.duration_s = m.at("duration_s").get<double>();
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("metrics.json: ") + e.what());
  }
  read_channels(r, parse_json(f.netem_json, "netem stats"), f.health_jsonl);
  judge(r);
  return r;
}

std::string live_report_json(const LiveReport& r) {
  json exits = json::array(), rss = json::array(), channels = json::array();
  for (const auto& e : r.exits) exits.push_back({{"process", e.name}, {"exit_status", e.status}, {"early", e.early}});
  for (const auto& [name, t] : r.rss) {
    json trend = trend_json(t);
    trend["process"] = name;
    rss.push_back(trend);
  }
  for (const auto& c : r.channels)
    channels.push_back({{"channel", c.channel},
                        {"sent", c.sent},
                        {"dropped", c.dropped},
                        {"mean_delay_ms", c.mean_delay_ms},
                        {"exempt", c.exempt},
                        {"received", c.received}});
  return json{{"loss", r.loss},
              {"delay_ms", r.delay_ms},
              {"jitter_ms", r.jitter_ms},
              {"reorder", r.reorder},
              {"exits", exits},
              {"rss", rss},
              {"collisions_at_fault", r.collisions_at_fault},
              {"collisions_not_at_fault", r.collisions_not_at_fault},
              {"reached_goal", r.reached_goal},
              {"min_dist_m", r.min_dist_m},
              {"duration_s", r.duration_s},
              {"channels", channels},
              {"failures", r.failures},
              {"pass", r.failures.empty()}}
      .dump(2);
}

std::string live_report_text(const LiveReport& r) {
  std::ostringstream o;
  o << "netem-run: " << fmt("%.0f", r.duration_s) << " s of SIM_TRUTH, bus loss " << fmt("%.1f", 100 * r.loss)
    << " %, delay " << fmt("%.0f", r.delay_ms) << " +- " << fmt("%.0f", r.jitter_ms) << " ms"
    << (r.reorder ? " (packets reordered, as netem's jitter does)" : " (in order)") << "\n";
  o << "  collisions at fault " << r.collisions_at_fault << ", not at fault " << r.collisions_not_at_fault
    << ", min dist " << fmt("%.2f", r.min_dist_m) << " m, goal " << (r.reached_goal ? "reached" : "not reached")
    << "\n  processes:\n";
  for (const auto& e : r.exits)
    o << "    " << e.name << ": exit " << e.status << (e.early ? ", exited early" : "")
      << (is_crash(e) ? "  <- crash" : "") << "\n";
  o << "  RSS (MiB: start / max / end, growth per hour after the warm-up):\n";
  for (const auto& [name, t] : r.rss)
    o << "    " << name << ": " << fmt("%.1f", t.start_mib) << " / " << fmt("%.1f", t.max_mib) << " / "
      << fmt("%.1f", t.end_mib) << ", " << (t.growth_mib_per_h ? fmt("%+.1f", *t.growth_mib_per_h) : std::string("-"))
      << " MiB/h\n";
  o << "  bus (messages sent, dropped by netem; received per process from its last HEALTH):\n";
  for (const auto& c : r.channels) {
    o << "    " << c.channel << ": sent " << c.sent << ", dropped " << c.dropped
      << (c.sent > 0 ? " (" + fmt("%.1f", 100.0 * c.dropped / c.sent) + " %)" : "")
      << (c.exempt ? ", exempt" : ", mean delay " + fmt("%.1f", c.mean_delay_ms) + " ms");
    for (const auto& [proc, n] : c.received)
      o << "; " << proc << " got " << n << (c.sent > 0 ? " (" + fmt("%.1f", 100.0 * n / c.sent) + " %)" : "");
    o << "\n";
  }
  o << verdict_text(r.failures);
  return o.str();
}

}  // namespace evade::soak
