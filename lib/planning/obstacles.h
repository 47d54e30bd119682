// Obstacle sequences for the MPC constraints, per planner mode (modes.h):
// from OBSTACLES (the tracker's ellipses as observed) held or curve-fitted,
// or from OBSTACLE_PREDICTIONS aligned to the planning time.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <vector>

#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/params.h"
#include "planning/problem.h"

namespace evade::planning {

// True when a track's arrays are consistent, finite and its axes positive.
bool valid_track(const evade::track_prediction_t& t);
// True when an observed ellipse is finite and its axes positive.
bool valid_observed(const evade::obstacle_t& o);

// The track at plan steps k = 0..N, starting `offset_s` after the
// prediction's utime (t_plan - utime): linear interpolation between
// prediction steps (dt = pred_dt), constant-velocity extrapolation (the
// track's vx, vy) outside them; shape from the nearest step.
ObstacleTrack align_track(const evade::track_prediction_t& t, double pred_dt, double offset_s, int N, double plan_dt);

// An observed ellipse held for all steps.
ObstacleTrack hold_observed(const evade::obstacle_t& o, int N);

// cbf_curvefit: the planner's own history of each observed (OBSTACLES)
// ellipse's centre by track id, fitted by a polynomial in time and
// extrapolated.
class CurveFitHistory {
 public:
  CurveFitHistory(int degree, double window_s) : degree_(degree), window_us_(static_cast<int64_t>(window_s * 1e6)) {}
  void add(const evade::obstacle_list_t& msg);
  // The observed shape, centres from the fit at t_plan + k dt. With one
  // sample: held still.
  ObstacleTrack extrapolate(const evade::obstacle_t& o, int64_t t_plan_us, int N, double plan_dt) const;
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

// What a planning cycle knows of the obstacles: the last message of each
// input (null when none has arrived) and the observed centres' history.
struct ObstacleInputs {
  const evade::prediction_list_t* predictions = nullptr;
  const evade::obstacle_list_t* observed = nullptr;
  const CurveFitHistory* history = nullptr;
};

// Gives each of `obstacles` its measurement in `observed` (same id) as
// ObstacleTrack::measured; those without one keep none.
void attach_measurements(const evade::obstacle_list_t& observed, std::vector<ObstacleTrack>* obstacles);

// The constraint obstacles of one planning cycle, from the mode's input
// (ModeSpec::source) moved over the horizon as the mode says
// (ModeSpec::motion), with PlannerParams::constraint_decay(); nearest
// first, only those that come within the consider radius of the robot's
// start, at most max_obstacles. Invalid tracks or ellipses are skipped and
// counted in *invalid.
std::vector<ObstacleTrack> constraint_obstacles(const PlannerParams& p, const ObstacleInputs& in, int64_t t_plan_us,
                                                double px, double py, int* invalid);

}  // namespace evade::planning
