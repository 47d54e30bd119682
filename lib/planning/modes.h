// Planner modes (SPEC "Planner modes"). A mode is one row of a table: which
// obstacle input it reads, how an obstacle moves over the horizon, the
// constraint form and its gamma, and whether evade's own layers are on.
// The paper's five modes (Table I) run the paper's planner: the route as
// the reference, the mode's constraint, and braking when the solve fails.
// `evade` is evade's full planner, the default.
#pragma once

#include <string>
#include <vector>

namespace evade::planning {

enum class Mode { kEvade, kDcbf, kMpc, kCbf, kKf, kCbfCurvefit };

// Where a mode's obstacles come from.
enum class ObstacleSource {
  kObserved,   // OBSTACLES: the tracker's minimum bounding ellipses as measured
  kPredicted,  // OBSTACLE_PREDICTIONS: the Kalman filter's uncertainty-inflated predictions
};

// How an obstacle's ellipse moves over the horizon.
enum class ObstacleMotion {
  kHeld,       // the current ellipse at every step
  kCurveFit,   // centres from a polynomial fit of the recent observed centres, shape held
  kPredicted,  // the predictor's sequence, aligned to the plan's steps
};

// The constraint on each obstacle at each step k = 0..N-1, h the barrier
// (distance beyond the ellipse minus d_safe_m).
enum class ConstraintForm {
  kDistance,  // h(X_k+1) >= 0
  kCbf,       // h(X_k+1) >= (1 - gamma) h(X_k)
};

// Which configured gamma a kCbf constraint uses.
enum class GammaKey {
  kPaper,  // planner.gamma (the paper's 0.15)
  kEvade,  // planner.evade_gamma
};

struct ModeSpec {
  Mode mode;
  const char* name;        // as in planner.mode, --mode and PLAN.mode
  const char* paper_name;  // its Table I row; "" when not in the paper
  ObstacleSource source;
  ObstacleMotion motion;
  ConstraintForm constraint;
  GammaKey gamma;  // used by kCbf only
  // evade's layers beyond the paper. Reference shaping: the detour round
  // settled obstacles, slow leaders and oncoming movers swept into its grid
  // (detour.h). When the hard solve fails: restarts from swerves, then one
  // fallback (the relaxed problem, else braking; PlannerCore::fallback).
  // Off: the route is the reference and a failed solve brakes at the
  // deceleration limits (STATUS_STOPPING).
  bool evade_layers;
};

// Every mode, the paper's five in Table I order, then evade.
const std::vector<ModeSpec>& all_modes();
const ModeSpec& mode_spec(Mode m);
// throws std::invalid_argument naming the modes
Mode parse_mode(const std::string& name);
const char* mode_name(Mode m);
std::vector<std::string> mode_names();

}  // namespace evade::planning
