// Obstacle sequences for the MPC constraints, per planner mode (SPEC,
// paper Table I), from OBSTACLE_PREDICTIONS aligned to the planning time.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <vector>

#include "evade/prediction_list_t.hpp"
#include "planning/params.h"
#include "planning/problem.h"

namespace evade::planning {

// True when a track's arrays are consistent, finite and its axes positive.
bool valid_track(const evade::track_prediction_t& t);

// The track at plan steps k = 0..N, starting `offset_s` after the
// prediction's utime (t_plan - utime): linear interpolation between
// prediction steps (dt = pred_dt), constant-velocity extrapolation (the
// track's vx, vy) outside them; shape from the nearest step.
ObstacleTrack align_track(const evade::track_prediction_t& t, double pred_dt, double offset_s, int N, double plan_dt);

// Index 0 of the track (its measured position and shape) held for all steps.
ObstacleTrack hold_current(const evade::track_prediction_t& t, int N);

// cbf_curvefit: the planner's own history of each track's index-0 centre,
// fitted by a polynomial in time and extrapolated.
class CurveFitHistory {
 public:
  CurveFitHistory(int degree, double window_s) : degree_(degree), window_us_(static_cast<int64_t>(window_s * 1e6)) {}
  void add(const evade::prediction_list_t& msg);
  // Shape of index 0, centres from the fit at t_plan + k dt. With one
  // sample: held still.
  ObstacleTrack extrapolate(const evade::track_prediction_t& t, int64_t t_plan_us, int N, double plan_dt) const;
  size_t samples(int64_t id) const;

 private:
  struct Sample {
    int64_t utime;
    double x, y;
  };
  int degree_;
  int64_t window_us_;
  std::map<int64_t, std::deque<Sample>> history_;
};

// The constraint obstacles of one planning cycle: per mode, the aligned
// sequences with decay (1 - gamma for the CBF modes, 0 for distance
// constraints), nearest first, only those that come within the consider
// radius of the robot's start, at most max_obstacles.
std::vector<ObstacleTrack> constraint_obstacles(const PlannerParams& p, const evade::prediction_list_t& msg,
                                                const CurveFitHistory& history, int64_t t_plan_us, double px,
                                                double py, int* invalid_tracks);

}  // namespace evade::planning
