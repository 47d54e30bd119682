#include "metrics/plan_latency.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "bus/core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"

namespace evade::metrics {
namespace {

// Each list's utime -> its first arrival; in arrival order in *order.
std::map<int64_t, int64_t> arrivals(const std::vector<bus::LogEvent>& log, std::vector<int64_t>* order) {
  std::map<int64_t, int64_t> at;
  for (const auto& e : log) {
    evade::prediction_list_t m;
    if (e.channel != "OBSTACLE_PREDICTIONS" || !bus::decode(e.data.data(), e.data.size(), &m)) continue;
    if (at.emplace(m.utime, e.timestamp).second) order->push_back(m.utime);
  }
  return at;
}

// The rule of this module: list -> CMD_VEL of the first plan naming it.
// Empty when no PLAN names a list.
std::map<int64_t, double> by_plans(const std::vector<bus::LogEvent>& log, const std::map<int64_t, int64_t>& at) {
  std::map<int64_t, double> out;
  std::set<int64_t> named;                // lists some plan has named
  std::optional<evade::plan_t> awaiting;  // the first plan of a list, until its CMD_VEL
  for (const auto& e : log) {
    if (e.channel == "PLAN") {
      evade::plan_t p;
      if (!bus::decode(e.data.data(), e.data.size(), &p) || p.predictions_utime < 0) continue;
      if (named.insert(p.predictions_utime).second) awaiting = p;
    } else if (e.channel == "CMD_VEL" && awaiting) {
      evade::cmd_vel_t c;
      if (!bus::decode(e.data.data(), e.data.size(), &c) || c.utime != awaiting->utime) continue;
      auto it = at.find(awaiting->predictions_utime);
      if (it != at.end() && e.timestamp >= it->second) out[it->first] = (e.timestamp - it->second) * 1e-3;
      awaiting.reset();
    }
  }
  return out;
}

// The rule before PLAN named its list: the first CMD_VEL after arrival.
std::map<int64_t, double> by_first_cmd(const std::vector<bus::LogEvent>& log, const std::map<int64_t, int64_t>& at) {
  std::vector<int64_t> cmd_times;
  for (const auto& e : log)
    if (e.channel == "CMD_VEL") cmd_times.push_back(e.timestamp);
  std::sort(cmd_times.begin(), cmd_times.end());
  std::map<int64_t, double> out;
  for (const auto& [utime, t] : at) {
    auto it = std::upper_bound(cmd_times.begin(), cmd_times.end(), t);
    if (it != cmd_times.end()) out[utime] = (*it - t) * 1e-3;
  }
  return out;
}

}  // namespace

double PlanLatency::percentile_ms(double q) const {
  if (latency_ms.empty()) return 0.0;
  std::vector<double> v = latency_ms;
  std::sort(v.begin(), v.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

PlanLatency plan_latency(const std::vector<bus::LogEvent>& log) {
  PlanLatency r;
  std::vector<int64_t> order;
  const std::map<int64_t, int64_t> at = arrivals(log, &order);
  std::map<int64_t, double> lat = by_plans(log, at);
  bool any_named = false;
  for (const auto& e : log) {
    evade::plan_t p;
    if (e.channel == "PLAN" && bus::decode(e.data.data(), e.data.size(), &p) && p.predictions_utime >= 0) {
      any_named = true;
      break;
    }
  }
  if (!any_named) {
    r.by_first_cmd = true;
    lat = by_first_cmd(log, at);
  }
  r.lists = static_cast<int64_t>(order.size());
  for (int64_t utime : order) {
    auto it = lat.find(utime);
    if (it == lat.end()) continue;
    r.latency_ms.push_back(it->second);
  }
  r.planned = static_cast<int64_t>(r.latency_ms.size());
  r.unplanned = r.lists - r.planned;
  return r;
}

}  // namespace evade::metrics
