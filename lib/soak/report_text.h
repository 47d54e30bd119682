// Text helpers shared by the soak and netem-run reports: the line readers
// of their TSV and JSONL inputs (errors name the line), printf-style number
// formatting, and the JSON form of a memory trend.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "soak/rss_trend.h"

namespace evade::soak {

// One number through a printf format with one conversion ("%.1f").
std::string fmt(const char* format, double v);

// Calls `on_line(line, n)` for each non-empty line of `text` (n counts from
// 1). With `skip_comments`, lines starting with '#' are skipped too.
void for_each_line(const std::string& text, bool skip_comments,
                   const std::function<void(const std::string&, int)>& on_line);

// for_each_line over JSON lines: each parsed, handed to `on_record`; any
// error becomes std::runtime_error "PREFIXline N: reason".
void for_each_json_line(const std::string& jsonl, const std::string& prefix,
                        const std::function<void(const nlohmann::json&)>& on_record);

// A whole JSON document; a parse error becomes "WHAT: reason".
nlohmann::json parse_json(const std::string& text, const char* what);

// The fields of a memory trend both reports publish.
nlohmann::json trend_json(const RssTrend& t);

// "verdict: PASS|FAIL" and one "  - failure" line each.
std::string verdict_text(const std::vector<std::string>& failures);

}  // namespace evade::soak
