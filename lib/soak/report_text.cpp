#include "soak/report_text.h"

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace evade::soak {

std::string fmt(const char* format, double v) {
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

void for_each_line(const std::string& text, bool skip_comments,
                   const std::function<void(const std::string&, int)>& on_line) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty() || (skip_comments && line[0] == '#')) continue;
    on_line(line, n);
  }
}

void for_each_json_line(const std::string& jsonl, const std::string& prefix,
                        const std::function<void(const nlohmann::json&)>& on_record) {
  for_each_line(jsonl, false, [&](const std::string& line, int n) {
    try {
      on_record(nlohmann::json::parse(line));
    } catch (const std::exception& e) {
      throw std::runtime_error(prefix + "line " + std::to_string(n) + ": " + e.what());
    }
  });
}

nlohmann::json parse_json(const std::string& text, const char* what) {
  try {
    return nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(what) + ": " + e.what());
  }
}

nlohmann::json trend_json(const RssTrend& t) {
  return {{"pid", t.pid},
          {"span_s", t.span_s},
          {"start_mib", t.start_mib},
          {"max_mib", t.max_mib},
          {"end_mib", t.end_mib},
          {"fitted_samples", t.fitted},
          {"growth_mib_per_h", t.growth_mib_per_h ? nlohmann::json(*t.growth_mib_per_h) : nlohmann::json(nullptr)}};
}

std::string verdict_text(const std::vector<std::string>& failures) {
  std::string s = std::string("verdict: ") + (failures.empty() ? "PASS" : "FAIL") + "\n";
  for (const auto& f : failures) s += "  - " + f + "\n";
  return s;
}

}  // namespace evade::soak
