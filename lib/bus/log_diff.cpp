#include "bus/log_diff.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bus/lcm_schema.h"

namespace evade::bus {
namespace {

struct Walker {
  Tolerance tol;
  const std::vector<std::string>* ignore;
  std::string channel;
  std::vector<std::string>* out;
  size_t max;
  bool differs = false;

  void report(const std::string& path, const std::string& what) {
    differs = true;
    if (out->size() < max) out->push_back(path + ": " + what);
  }
  bool ignored(const std::string& field) const {
    return std::find(ignore->begin(), ignore->end(), channel + "." + field) != ignore->end();
  }
  void walk(const std::string& path, const std::string& field, const Value& a, const Value& b) {
    if (!field.empty() && ignored(field)) return;
    if (a.kind != b.kind) {
      report(path, "kind differs");
      return;
    }
    switch (a.kind) {
      case Value::Kind::Int:
        if (a.i != b.i) report(path, std::to_string(a.i) + " vs " + std::to_string(b.i));
        break;
      case Value::Kind::Bool:
        if (a.b != b.b) report(path, std::string(a.b ? "true" : "false") + " vs " + (b.b ? "true" : "false"));
        break;
      case Value::Kind::String:
        if (a.s != b.s) report(path, "\"" + a.s + "\" vs \"" + b.s + "\"");
        break;
      case Value::Kind::Float: {
        bool both_nan = std::isnan(a.f) && std::isnan(b.f);
        if (!both_nan && !(std::fabs(a.f - b.f) <= tol.abs_tol + tol.rel_tol * std::fabs(b.f))) {
          char buf[96];
          std::snprintf(buf, sizeof buf, "%.9g vs %.9g", a.f, b.f);
          report(path, buf);
        }
        break;
      }
      case Value::Kind::Array:
        if (a.items.size() != b.items.size()) {
          report(path, "length " + std::to_string(a.items.size()) + " vs " + std::to_string(b.items.size()));
          return;
        }
        for (size_t i = 0; i < a.items.size(); ++i)
          walk(path + "[" + std::to_string(i) + "]", field, a.items[i], b.items[i]);
        break;
      case Value::Kind::Struct:
        for (size_t i = 0; i < a.fields.size() && i < b.fields.size(); ++i) {
          const std::string& name = a.fields[i].first;
          std::string sub = field.empty() ? name : field + "." + name;
          walk(path + "." + name, sub, a.fields[i].second, b.fields[i].second);
        }
        break;
    }
  }
};

}  // namespace

DiffReport diff_logs(const std::vector<LogEvent>& actual, const std::vector<LogEvent>& reference,
                     const DiffOptions& options) {
  DiffReport rep;
  auto skip = [&](const std::string& ch) {
    return std::find(options.ignore_channels.begin(), options.ignore_channels.end(), ch) !=
           options.ignore_channels.end();
  };
  std::map<std::string, std::vector<const LogEvent*>> a, b;
  for (const auto& e : actual)
    if (!skip(e.channel)) a[e.channel].push_back(&e);
  for (const auto& e : reference)
    if (!skip(e.channel)) b[e.channel].push_back(&e);
  std::vector<std::string> channels;
  for (const auto& [ch, v] : a) channels.push_back(ch);
  for (const auto& [ch, v] : b)
    if (!a.count(ch)) channels.push_back(ch);
  const auto& schema = LcmSchema::evade();
  for (const auto& ch : channels) {
    const auto& va = a[ch];
    const auto& vb = b[ch];
    if (va.size() != vb.size() && rep.lines.size() < options.max_reports)
      rep.lines.push_back(ch + ": " + std::to_string(va.size()) + " messages vs " + std::to_string(vb.size()) +
                          " in the reference");
    auto tol_it = options.per_channel.find(ch);
    Tolerance tol = tol_it == options.per_channel.end() ? options.default_tolerance : tol_it->second;
    for (size_t i = 0; i < std::min(va.size(), vb.size()); ++i) {
      ++rep.compared_messages;
      std::string path = ch + "#" + std::to_string(i);
      if (va[i]->data == vb[i]->data) continue;
      auto da = schema.decode(va[i]->data.data(), va[i]->data.size());
      auto db = schema.decode(vb[i]->data.data(), vb[i]->data.size());
      Walker w{tol, &options.ignore_fields, ch, &rep.lines, options.max_reports};
      if (!da || !db) {
        w.report(path, "undecodable message");
      } else {
        w.walk(path, "", *da, *db);
      }
      if (w.differs) ++rep.differing_messages;
    }
    if (va.size() != vb.size()) ++rep.differing_messages;
  }
  return rep;
}

}  // namespace evade::bus
