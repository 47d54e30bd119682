#include "metrics/plan_replay.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>

#include "bus/memory_bus.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/plan_t.hpp"
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
    return !remove || strip(data, remove, &evade::obstacle_list_t::obstacles, &evade::obstacle_list_t::num_obstacles);
  if (is_type<evade::prediction_list_t>(*data))
    return !remove || strip(data, remove, &evade::prediction_list_t::tracks, &evade::prediction_list_t::num_tracks);
  return false;
}

bool strip_tracks(std::vector<uint8_t>* data, const std::set<int64_t>& removed) {
  return strip_tracks(data, [&](int64_t, int64_t id) { return removed.count(id) > 0; });
}

double plan_distance_m(const evade::plan_t& a, const evade::plan_t& b, double dt_s) {
  const double offset = (a.utime - b.utime) * 1e-6 / dt_s;  // a's step 0 in b's steps
  const int n_a = std::min<int>(a.num_states, std::min(a.x.size(), a.y.size()));
  const int n_b = std::min<int>(b.num_states, std::min(b.x.size(), b.y.size()));
  double d = -1.0;
  for (int k = 0; k < n_a; ++k) {
    const double s = offset + k;
    if (s < -1e-9 || s > n_b - 1 + 1e-9) continue;
    const int i = std::clamp(static_cast<int>(std::floor(s + 1e-9)), 0, n_b - 1);
    const int j = std::min(i + 1, n_b - 1);
    const double f = std::clamp(s - i, 0.0, 1.0);
    const double bx = b.x[i] + f * (b.x[j] - b.x[i]), by = b.y[i] + f * (b.y[j] - b.y[i]);
    d = std::max(d, std::hypot(a.x[k] - bx, a.y[k] - by));
  }
  return d < 0 ? std::numeric_limits<double>::infinity() : d;
}

namespace {

// Least squares of solve_time_us = base + per_iteration * iterations over
// the log's PLANs that went through the solver (solve_time_us > 0); one
// iteration count only: its mean time, per_iteration 0; none: 0.
PlanReplay::ComputeModel fit_compute_model(const std::vector<bus::LogEvent>& log) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const auto& e : log) {
    evade::plan_t p;
    if (!is_type<evade::plan_t>(e.data) || !bus::decode(e.data.data(), e.data.size(), &p) || p.solve_time_us <= 0)
      continue;
    const double x = p.iterations, y = static_cast<double>(p.solve_time_us);
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  PlanReplay::ComputeModel m;
  if (n == 0) return m;
  const double var = n * sxx - sx * sx;
  m.per_iteration_us = var > 1e-9 * n * n ? std::max(0.0, (n * sxy - sx * sy) / var) : 0.0;
  m.base_us = std::max(0.0, (sy - m.per_iteration_us * sx) / n);
  return m;
}

}  // namespace

PlanReplay::PlanReplay(planning::PlannerParams params, const std::vector<bus::LogEvent>& log)
    : params_(std::move(params)), model_(fit_compute_model(log)) {
  planning::PlannerCore probe(params_);
  for (const auto& ch : probe.channels()) channels_.insert(ch);
  for (const auto& e : log)
    if (channels_.count(e.channel)) inputs_.push_back(e);
}

void PlanReplay::run(const TrackFilter& remove, const std::function<bool(const evade::plan_t&)>& on_plan) const {
  planning::PlannerCore core(params_);
  core.set_measure_latency(false);
  const ComputeModel m = model_;
  core.set_solve_time_model([m](int iterations, double) { return m.base_us + m.per_iteration_us * iterations; });
  bus::MemoryBus bus;
  bus.add(core);
  int64_t free_at = std::numeric_limits<int64_t>::min();
  bool stop = false;
  std::vector<uint8_t> data;
  // One callback: the message at bus time t; busy until its plan's compute time has passed.
  auto handle = [&](const bus::LogEvent& e, int64_t t) {
    data = e.data;
    strip_tracks(&data, remove);
    bus.inject(e.channel, data, t);
    int64_t busy_us = 0;
    for (const auto& out : bus.take_published()) {
      evade::plan_t p;
      if (out.channel != "PLAN" || !bus::decode(out.data.data(), out.data.size(), &p)) continue;
      busy_us = std::max(busy_us, p.solve_time_us);
      if (!on_plan(p)) stop = true;
    }
    free_at = t + busy_us;
  };
  std::deque<const bus::LogEvent*> waiting;
  const auto conflated_list = planning::PlannerCore::conflated_inputs();
  const std::set<std::string> conflated(conflated_list.begin(), conflated_list.end());
  auto run_waiting_until = [&](int64_t t) {
    while (!stop && !waiting.empty() && free_at <= t) {
      const bus::LogEvent* w = waiting.front();
      waiting.pop_front();
      handle(*w, std::max(free_at, w->timestamp));
    }
  };
  for (const auto& e : inputs_) {
    run_waiting_until(e.timestamp);
    if (stop) return;
    if (free_at <= e.timestamp && waiting.empty()) {
      handle(e, e.timestamp);
      if (stop) return;
      continue;
    }
    if (conflated.count(e.channel)) {
      auto same = [&](const bus::LogEvent* w) { return w->channel == e.channel; };
      waiting.erase(std::remove_if(waiting.begin(), waiting.end(), same), waiting.end());
    }
    waiting.push_back(&e);
  }
  run_waiting_until(std::numeric_limits<int64_t>::max());
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
