#include "health_board.h"

#include <algorithm>
#include <cstdio>
#include <set>

namespace evade::health {

HealthBoardParams HealthBoardParams::from_config(const config::Node& s) { return config::load<HealthBoardParams>(s); }

void HealthBoard::add(const evade::health_t& msg, int64_t received_utime) {
  auto it = latest_.find(msg.name);
  if (it != latest_.end() && it->second.received_utime > received_utime) return;
  latest_[msg.name] = Heartbeat{msg, received_utime};
}

namespace {

double age_s(const Heartbeat& h, int64_t now) { return double(now - h.received_utime) * 1e-6; }

bool is_stale(const Heartbeat& h, int64_t now, const HealthBoardParams& p) { return age_s(h, now) > p.stale_after_s; }

// A number in a column of `width`, or ">max" when it does not fit.
std::string num(double v, int decimals, int width) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  if (int(std::string(buf).size()) <= width) return buf;
  return ">" + std::string(size_t(width - 1), '9');
}

std::string clip(const std::string& s, size_t n) { return s.size() <= n ? s : s.substr(0, n - 1) + "~"; }

std::string row(const std::string& name, const std::string& beat, const std::string& rate, const std::string& mean,
                const std::string& max, const std::string& input, const std::string& input_age) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%-16s %6s %7s %7s %7s  %-16s %7s", clip(name, 16).c_str(), beat.c_str(), rate.c_str(),
                mean.c_str(), max.c_str(), clip(input, 16).c_str(), input_age.c_str());
  return buf;
}

// The input with the largest age; one never heard counts as the oldest.
void oldest_input(const evade::health_t& m, std::string* name, std::string* age) {
  const evade::health_channel_t* worst = nullptr;
  for (const auto& in : m.inputs) {
    if (!worst || (in.age_us < 0 && worst->age_us >= 0) || (in.age_us > worst->age_us && worst->age_us >= 0))
      worst = &in;
  }
  if (!worst) {
    *name = "-";
    *age = "-";
    return;
  }
  *name = worst->channel;
  *age = worst->age_us < 0 ? "never" : num(double(worst->age_us) * 1e-6, 2, 7);
}

// Non-zero counters as "name=value", wrapped into indented lines.
std::vector<std::string> counter_lines(const evade::health_t& m) {
  const std::string indent = "    ";
  std::vector<std::string> lines;
  std::string line;
  for (const auto& c : m.counters) {
    if (c.value == 0) continue;
    std::string item = clip(c.name + "=" + std::to_string(c.value), size_t(kTableWidth) - indent.size());
    if (!line.empty() && line.size() + 2 + item.size() > size_t(kTableWidth)) {
      lines.push_back(line);
      line.clear();
    }
    line += line.empty() ? indent + item : "  " + item;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

constexpr const char* kRed = "\033[31m";
constexpr const char* kReset = "\033[0m";

}  // namespace

Verdict judge(const HealthBoard& board, const std::vector<std::string>& expected, int64_t now,
              const HealthBoardParams& p) {
  Verdict v;
  for (const auto& [name, h] : board.processes())
    if (is_stale(h, now, p)) v.stale.push_back(name);
  for (const auto& name : expected)
    if (!board.processes().count(name)) v.missing.push_back(name);
  return v;
}

bool parse_input_wanted(const std::string& text, InputWanted* out, std::string* why) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size() ||
      text.find(':', colon + 1) != std::string::npos) {
    *why = "'" + text + "' is not PROCESS:CHANNEL";
    return false;
  }
  *out = InputWanted{text.substr(0, colon), text.substr(colon + 1)};
  return true;
}

std::vector<std::string> inputs_not_received(const HealthBoard& board, const std::vector<InputWanted>& wanted) {
  std::vector<std::string> out;
  for (const auto& w : wanted) {
    auto it = board.processes().find(w.process);
    bool got = false;
    if (it != board.processes().end())
      for (const auto& in : it->second.msg.inputs) got |= (in.channel == w.channel && in.received > 0);
    if (!got) out.push_back(w.process + ":" + w.channel);
  }
  return out;
}

std::vector<std::string> render_table(const HealthBoard& board, const std::vector<std::string>& expected, int64_t now,
                                      const HealthBoardParams& p, bool colour) {
  std::vector<std::string> out;
  out.push_back(row("PROCESS", "BEAT s", "OUT Hz", "LAT ms", "MAX ms", "OLDEST INPUT", "AGE s"));
  for (const auto& [name, h] : board.processes()) {
    std::string input, input_age;
    oldest_input(h.msg, &input, &input_age);
    std::string line =
        row(name, num(age_s(h, now), 1, 6), num(h.msg.output_rate_hz, 1, 7), num(h.msg.latency_us_mean * 1e-3, 2, 7),
            num(h.msg.latency_us_max * 1e-3, 2, 7), input, input_age);
    if (is_stale(h, now, p)) line = colour ? kRed + line + kReset : line + " STALE";
    out.push_back(line);
    for (auto& c : counter_lines(h.msg)) out.push_back(c);
  }
  std::set<std::string> seen;
  for (const auto& name : expected) {
    if (board.processes().count(name) || !seen.insert(name).second) continue;
    const std::string line = row(name, "-", "-", "-", "-", "(never heard)", "-");
    out.push_back(colour ? kRed + line + kReset : line);
  }
  return out;
}

}  // namespace evade::health
