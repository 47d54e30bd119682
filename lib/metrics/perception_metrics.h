// Perception measured against the simulator's truth (issue 23): tracking by
// CLEAR MOT (clear_mot.h) and prediction by displacement error and
// calibration, from one run log with SIM_TRUTH, ODOMETRY, OBSTACLES and
// OBSTACLE_PREDICTIONS. `perception_rules()` states every rule; it is what
// `perception-metrics --help` prints.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "bus/log.h"
#include "config/config.h"
#include "config/fields.h"
#include "metrics/clear_mot.h"
#include "metrics/ellipse_calibration.h"

namespace evade::metrics {

struct PerceptionParams {
  double range_m = 8.0;               // objects and tracks farther from the robot are not scored
  int min_returns = 3;                // an object is visible with at least this many LiDAR returns per revolution
  double match_gate_m = 1.0;          // a track matches an object within this of its shape
  double max_object_size_m = 6.0;     // larger objects (walls) are not scored as one object
  double min_track_age_s = 0.5;       // calibration is judged on tracks at least this old
  double walker_max_radius_m = 0.35;  // a walker: a cylinder no wider ...
  double walker_max_speed_mps = 2.0;  // ... and no faster than this
  double static_max_speed_mps = 0.3;  // a track on a static object published faster than this moves falsely

  template <class V>
  void fields(V& v) {
    v.field("range_m", range_m, config::positive());
    v.field("min_returns", min_returns, config::between(1, 100000));
    v.field("match_gate_m", match_gate_m, config::positive());
    v.field("max_object_size_m", max_object_size_m, config::positive());
    v.field("min_track_age_s", min_track_age_s, config::between(0.0, 60.0));
    v.field("walker_max_radius_m", walker_max_radius_m, config::positive());
    v.field("walker_max_speed_mps", walker_max_speed_mps, config::positive());
    v.field("static_max_speed_mps", static_max_speed_mps, config::positive());
  }
  static PerceptionParams from_config(const config::Node& section);
};

// Per step of the prediction horizon.
struct StepScore {
  int64_t n = 0, inside = 0;                    // tracks at least min_track_age_s old
  int64_t n_all = 0, inside_all = 0;            // every track
  double error_sum_m = 0.0, area_sum_m2 = 0.0;  // over every track
};

struct PerceptionMetrics {
  MotTotals mot;
  double dt_s = 0.0;             // the predictions' step
  std::vector<StepScore> steps;  // index 0 = now
  int64_t predictions = 0;       // (prediction list, track) pairs scored
  // Displacement errors (mean over the scored predictions), null when the
  // horizon is shorter.
  std::optional<double> ade_1s_m, fde_1s_m, ade_2_5s_m, fde_2_5s_m, walker_ade_1s_m;
  int64_t walker_predictions = 0;
  // Where the walkers' error comes from (the same predictions as
  // walker_ade_1s_m): the step-0 centre error, its component along the
  // robot -> walker direction (negative: towards the robot), the published
  // velocity's error, and the 1 s ADE of a constant-velocity extrapolation
  // of the true centre and velocity (what scripted turns and speed changes
  // cost a predictor that knew the state exactly).
  std::optional<double> walker_centre_error_m, walker_centre_radial_m, walker_velocity_error_mps,
      walker_ade_1s_cv_truth_m;
  int64_t untruthful_frames = 0;  // OBSTACLES with no SIM_TRUTH around their time
  // False motion of static structure: published tracks (step 0 of the
  // predictions) on an object that has not moved for a second, with no
  // moving object near, and how many of them are published faster than
  // static_max_speed_mps (the ids that ever were: static_moving_tracks).
  int64_t static_track_frames = 0, static_moving_frames = 0, static_moving_tracks = 0;
  double static_speed_sum_mps = 0.0;
  // The published ellipses by object class and track age (ellipse_calibration.h).
  EllipseCalibration ellipses;
};

// Throws std::runtime_error when the log has no SIM_TRUTH.
PerceptionMetrics compute_perception(const std::vector<bus::LogEvent>& events, const PerceptionParams& p,
                                     const std::string& obstacles_channel = "OBSTACLES",
                                     const std::string& predictions_channel = "OBSTACLE_PREDICTIONS");
std::string perception_json(const PerceptionMetrics& m, const PerceptionParams& p);
const char* perception_rules();

}  // namespace evade::metrics
