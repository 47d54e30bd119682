#include "metrics/plan_replay.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "bus/memory_bus.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "metrics/fingerprint.h"
#include "planning/planner_core.h"

namespace evade::metrics {
namespace {

template <class Msg, class List, class Count>
bool strip(std::vector<uint8_t>* data, const TrackFilter& remove, List Msg::*list, Count Msg::*count) {
  Msg m;
  if (!bus::decode(data->data(), data->size(), &m)) return true;  // malformed: the core counts it
  auto& items = m.*list;
  const size_t before = items.size();
  items.erase(std::remove_if(items.begin(), items.end(), [&](const auto& t) { return remove(m.utime, t.id); }),
              items.end());
  if (items.size() == before) return true;
  m.*count = static_cast<Count>(items.size());
  *data = bus::encode(m);
  return true;
}

}  // namespace

bool strip_tracks(std::vector<uint8_t>* data, const TrackFilter& remove) {
  if (is_type<evade::obstacle_list_t>(*data))
    return !remove ||
           strip(data, remove, &evade::obstacle_list_t::obstacles, &evade::obstacle_list_t::num_obstacles);
  if (is_type<evade::prediction_list_t>(*data))
    return !remove || strip(data, remove, &evade::prediction_list_t::tracks, &evade::prediction_list_t::num_tracks);
  return false;
}

bool strip_tracks(std::vector<uint8_t>* data, const std::set<int64_t>& removed) {
  return strip_tracks(data, [&](int64_t, int64_t id) { return removed.count(id) > 0; });
}

double plan_distance_m(const evade::plan_t& a, const evade::plan_t& b) {
  if (a.num_states != b.num_states) return std::numeric_limits<double>::infinity();
  double d = 0.0;
  for (int k = 0; k < a.num_states; ++k) d = std::max(d, std::hypot(a.x[k] - b.x[k], a.y[k] - b.y[k]));
  return d;
}

PlanReplay::PlanReplay(planning::PlannerParams params, const std::vector<bus::LogEvent>& log)
    : params_(std::move(params)) {
  planning::PlannerCore probe(params_);
  const std::vector<std::string> channels = probe.channels();
  for (const auto& e : log)
    if (std::find(channels.begin(), channels.end(), e.channel) != channels.end()) inputs_.push_back(e);
}

void PlanReplay::run(const TrackFilter& remove, const std::function<bool(const evade::plan_t&)>& on_plan) const {
  planning::PlannerCore core(params_);
  core.set_measure_latency(false);
  bus::MemoryBus bus;
  bus.add(core);
  std::vector<uint8_t> data;
  for (const auto& e : inputs_) {
    data = e.data;
    strip_tracks(&data, remove);
    bus.inject(e.channel, data, e.timestamp);
    for (const auto& out : bus.take_published()) {
      if (out.channel != "PLAN") continue;
      evade::plan_t p;
      if (bus::decode(out.data.data(), out.data.size(), &p) && !on_plan(p)) return;
    }
  }
}

std::vector<evade::plan_t> PlanReplay::plans() const {
  std::vector<evade::plan_t> out;
  run(nullptr, [&](const evade::plan_t& p) {
    out.push_back(p);
    return true;
  });
  return out;
}

}  // namespace evade::metrics
