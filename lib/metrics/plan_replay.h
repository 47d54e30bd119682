// The planner run again over a run log's recorded inputs, optionally with
// some perception tracks left out: the counterfactual behind the reaction
// time (metrics_rules()).
//
// The planner core is built from PlannerParams and fed the logged messages
// of every channel it subscribes to (whatever those are: the core says),
// each when it arrived (its logged time), as the recorded planner was:
// a planning cycle keeps it busy for the compute time
// base_us + per_iteration_us * (its Ceres iterations), fitted by least
// squares to the log's PLANs (solve_time_us against iterations, those
// with solve_time_us > 0: exact for a lockstep run's iterations model);
// what arrives meanwhile waits, and of each channel in
// PlannerCore::conflated_inputs() only the newest waiting message is kept
// (as the planner process and lib/closedloop do). Tracks are left out of every message whose type
// is obstacle_list_t or prediction_list_t, on any channel. Latency
// measurement is off and the compute time modelled, so a replay is
// deterministic.
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "bus/log.h"
#include "evade/plan_t.hpp"
#include "planning/params.h"

namespace evade::metrics {

// Whether to leave track `id` out of a message whose utime is `utime`.
using TrackFilter = std::function<bool(int64_t utime, int64_t id)>;

class PlanReplay {
 public:
  // `log`: the run log (every channel; only the planner's inputs are kept).
  PlanReplay(planning::PlannerParams params, const std::vector<bus::LogEvent>& log);

  struct ComputeModel {
    double base_us = 0.0;
    double per_iteration_us = 0.0;
  };
  const ComputeModel& compute_model() const { return model_; }

  // Runs a fresh planner over the inputs with the tracks `remove` picks
  // left out (none when empty) and calls on_plan with each PLAN it
  // publishes, in order, until on_plan returns false or the inputs end.
  void run(const TrackFilter& remove, const std::function<bool(const evade::plan_t&)>& on_plan) const;
  // Every PLAN of a run with nothing removed.
  std::vector<evade::plan_t> plans() const;

 private:
  planning::PlannerParams params_;
  std::vector<bus::LogEvent> inputs_;
  std::set<std::string> channels_;
  ComputeModel model_;
};

// Leaves the tracks `remove` picks (by the message's utime and their id)
// out of an obstacle_list_t or prediction_list_t message (recognised by
// its type fingerprint); other bytes come back as they are. Returns true
// when the message is of one of those types.
bool strip_tracks(std::vector<uint8_t>* data, const TrackFilter& remove);
// The same for a fixed set of ids.
bool strip_tracks(std::vector<uint8_t>* data, const std::set<int64_t>& removed);

// Largest distance between the planned positions of two plans at the same
// step over the horizon (m); infinity when their horizons differ.
double plan_distance_m(const evade::plan_t& a, const evade::plan_t& b);

}  // namespace evade::metrics
