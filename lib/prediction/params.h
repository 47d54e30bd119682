// Parameters of the predictor (config/robot.yaml, section `predictor:`).
// Every key is listed once, in the fields() of its struct (config/fields.h);
// units are in the key names, the defaults are robot.yaml's.
#pragma once

#include <string>

#include "config/config.h"
#include "config/fields.h"
#include "prediction/occluded.h"

namespace evade::prediction {

struct FilterParams {
  // Initial state uncertainty of a new track: velocity and acceleration are
  // unknown at birth, so they start at zero with these standard deviations
  // (no two-point velocity spike from a single noisy frame difference).
  double init_speed_std_mps = 1.0;
  double init_accel_std_mps2 = 0.2;
  // Process noise Q, continuous-time spectral densities; discretised for the
  // actual frame interval (white jerk drives the (p, v, a) chain of each axis,
  // a random walk drives each shape parameter).
  double jerk_psd_m2ps5 = 0.00005;
  double axis_psd_m2ps = 0.002;
  double theta_psd_rad2ps = 0.05;
  // Measurement noise R for the shape part of the MBE (the position part is adaptive).
  double r_axis_m2 = 0.0025;
  double r_theta_rad2 = 0.01;
  // Orientation of a near-circular MBE is noise: its measurement variance
  // grows as (axis std / max(a - b, this))^2.
  double orientation_min_elongation_m = 0.02;
  // Aperture: an elongated MBE (a >= this times b; 0 = off) seen partly (an
  // end in a shadow, at the map's edge, at a tile's cut) moves its centre
  // along its major axis when the seen part changes. The stationary mode
  // explains the along-axis shift its predicted ellipse's ends do not share
  // by that change, as a known offset before its update (aperture_shift,
  // track_filter.h); the moving modes measure it as motion.
  double aperture_min_elongation = 2.0;
  // ... and the half-extent's frame-to-frame change counts only beyond this
  // (the MBE's own jitter: a rigid mover's ends jitter too).
  double aperture_axis_noise_m = 0.05;

  template <class V>
  void fields(V& v) {
    v.field("init_speed_std_mps", init_speed_std_mps, config::positive());
    v.field("init_accel_std_mps2", init_accel_std_mps2, config::positive());
    v.field("jerk_psd_m2ps5", jerk_psd_m2ps5, config::positive());
    v.field("axis_psd_m2ps", axis_psd_m2ps, config::positive());
    v.field("theta_psd_rad2ps", theta_psd_rad2ps, config::positive());
    v.field("r_axis_m2", r_axis_m2, config::positive());
    v.field("r_theta_rad2", r_theta_rad2, config::positive());
    v.field("orientation_min_elongation_m", orientation_min_elongation_m, config::positive());
    v.field("aperture_min_elongation", aperture_min_elongation, config::between(0.0, 1000.0));
    v.field("aperture_axis_noise_m", aperture_axis_noise_m, config::between(0.0, 10.0));
  }
};

// Manoeuvres: the low jerk noise that gives accurate velocities of steady
// targets makes one filter slow to follow a turn. Optionally the track runs
// the paper's filter (the quiet mode) beside a manoeuvring mode with the
// same H and R, mixed as an interacting multiple model (IMM); enabled =
// false is the paper's single filter. The manoeuvring mode is either a copy
// of the paper's constant-acceleration filter with more jerk noise ("ca"),
// or constant velocity driven by white acceleration ("cv", the default): an
// acceleration learnt in an abrupt turn would otherwise outlive it, and the
// velocity overshoot the new heading for over a second.
struct ManeuverParams {
  bool enabled = true;
  double jerk_psd_m2ps5 = 0.1;   // jerk PSD of the manoeuvring mode
  double mean_quiet_s = 60.0;    // expected time in the quiet mode before a manoeuvre
  double mean_maneuver_s = 1.0;  // expected duration of a manoeuvre
  // The manoeuvring mode's model: "ca" (the paper's constant acceleration
  // with jerk_psd_m2ps5) or "cv" (acceleration held at zero, white
  // acceleration of accel_psd_m2ps3 drives the velocity).
  std::string model = "cv";
  double accel_psd_m2ps3 = 1.0;

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("jerk_psd_m2ps5", jerk_psd_m2ps5, config::positive());
    v.field("mean_quiet_s", mean_quiet_s, config::positive());
    v.field("mean_maneuver_s", mean_maneuver_s, config::positive());
    v.choice("model", model, {"ca", "cv"});
    v.field("accel_psd_m2ps3", accel_psd_m2ps3, config::positive());
  }
};

// A third IMM mode for things that stand still (bins, parked cars, a
// pedestrian waiting): velocity and acceleration held at zero, the centre a
// slow random walk. As the robot drives past, the visible faces of a static
// object change and its MBE centre wanders or jumps (pieces of a car merge
// and split); the moving modes read that as motion and the quiet one holds
// it for seconds, so the object's predicted ellipse drifts and swells over
// the horizon. Here the stationary mode predicts the next frames better and
// takes the probability back. Requires the manoeuvring mode: starting to
// move is a manoeuvre, and a manoeuvre ends in steady motion or in a stop.
struct StationaryParams {
  bool enabled = true;
  double mean_stationary_s = 30.0;   // expected time standing before starting to move
  double stop_share = 0.5;           // share of ending manoeuvres that end standing (the rest in steady motion)
  double position_psd_m2ps = 0.002;  // random walk of the centre (the MBE's drift with the view)

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("mean_stationary_s", mean_stationary_s, config::positive());
    v.field("stop_share", stop_share, config::between(0.0, 1.0));
    v.field("position_psd_m2ps", position_psd_m2ps, config::positive());
  }
};

struct AdaptiveNoiseParams {
  int window_frames = 10;                      // m, frames in the shape-variation window
  std::string shape_variation_source = "own";  // own | tracker
  double kappa = 5.5;                          // Xi_p = kappa * Xi_eta^gamma
  double gamma = 1.3;
  double xi_min_m2 = 0.0016;     // Xi_min,crit
  double xi_max_m2 = 0.25;       // Xi_max,crit
  double r_pos_min_m2 = 0.0016;  // R_p,min
  double r_pos_max_m2 = 0.25;    // R_p,max

  template <class V>
  void fields(V& v) {
    v.field("window_frames", window_frames, config::between(2, 1000));
    v.choice("shape_variation_source", shape_variation_source, {"own", "tracker"});
    v.field("kappa", kappa, config::positive());
    v.field("gamma", gamma, config::positive());
    v.field("xi_min_m2", xi_min_m2, config::positive());
    v.field("xi_max_m2", xi_max_m2, config::positive());
    v.rule(xi_max_m2 > xi_min_m2, "xi_max_m2", "must be greater than xi_min_m2");
    v.field("r_pos_min_m2", r_pos_min_m2, config::positive());
    v.field("r_pos_max_m2", r_pos_max_m2, config::positive());
    v.rule(r_pos_max_m2 >= r_pos_min_m2, "r_pos_max_m2", "must be at least r_pos_min_m2");
  }
};

struct UncertaintyParams {
  double confidence = 0.95;        // probability mass covered by r_p and r_eta
  double min_axis_m = 0.05;        // axes are floored at this before inflation
  double root_tolerance_m = 1e-9;  // sigma_min bracket width at convergence
  // Upper bound of the inflation added to both axes. The paper lets the
  // ellipse grow with k; a constant-acceleration covariance grows like k^4,
  // and unbounded it makes every moving obstacle cover the road by k = 25,
  // which leaves the planner no feasible plan.
  double max_inflation_m = 0.5;
  // How r_p and r_eta make one radius: sum (the paper: both at their 95 %
  // bound at once), rss (sqrt(r_p^2 + r_eta^2): independent errors, the
  // 95 % bound of their sum) or position (r_p alone).
  std::string combine = "sum";

  template <class V>
  void fields(V& v) {
    v.field("confidence", confidence, config::between(0.5, 0.999999));
    v.field("min_axis_m", min_axis_m, config::positive());
    v.field("root_tolerance_m", root_tolerance_m, config::between(1e-15, 1e-3));
    v.field("max_inflation_m", max_inflation_m, config::between(0.0, 100.0));
    v.choice("combine", combine, {"sum", "rss", "position"});
  }
};

struct LimitParams {
  double max_speed_mps = 5.0;     // predicted speed is clipped to this
  double max_accel_mps2 = 1.5;    // predicted acceleration magnitude is clipped to this
  double max_accel_time_s = 1.5;  // the acceleration acts for at most this long into the prediction

  template <class V>
  void fields(V& v) {
    v.field("max_speed_mps", max_speed_mps, config::positive());
    v.field("max_accel_mps2", max_accel_mps2, config::positive());
    v.field("max_accel_time_s", max_accel_time_s, config::between(0.0, 1e3));
  }
};

struct PredictorParams {
  int prediction_steps = 25;     // N (planner horizon); k = 0..N are published
  double prediction_dt_s = 0.1;  // planner step
  double max_frame_gap_s = 1.0;  // a longer gap between frames restarts every track
  double coast_max_s = 1.0;      // a track missing from the list is predicted and published this long, then dropped
  int coast_min_frames = 3;      // ... if it was seen in at least this many frames (else dropped at its first miss)
  OccludedParams occluded;       // ... or longer, while it is hidden (occluded.h)
  double max_abs_coordinate_m = 1000.0;  // an obstacle centre beyond this (odometry frame) is malformed
  double max_axis_m = 50.0;              // a semi-axis beyond this is malformed
  FilterParams filter;
  ManeuverParams maneuver;
  StationaryParams stationary;
  AdaptiveNoiseParams adaptive_noise;
  UncertaintyParams uncertainty;
  LimitParams limits;

  template <class V>
  void fields(V& v) {
    v.field("prediction_steps", prediction_steps, config::between(1, 1000));
    v.field("prediction_dt_s", prediction_dt_s, config::between(1e-3, 10.0));
    v.field("max_frame_gap_s", max_frame_gap_s, config::between(1e-3, 60.0));
    v.field("coast_max_s", coast_max_s, config::between(0.0, 60.0));
    v.field("coast_min_frames", coast_min_frames, config::between(1, 1000));
    v.section("occluded", occluded);
    v.field("max_abs_coordinate_m", max_abs_coordinate_m, config::positive());
    v.field("max_axis_m", max_axis_m, config::positive());
    v.section("filter", filter);
    v.section("maneuver", maneuver);
    v.section("stationary", stationary);
    v.rule(!stationary.enabled || maneuver.enabled, "stationary.enabled",
           "the stationary mode needs maneuver.enabled (a start from rest is a manoeuvre)");
    v.section("adaptive_noise", adaptive_noise);
    v.section("uncertainty", uncertainty);
    v.section("limits", limits);
  }

  static PredictorParams from_config(const config::Node& section);
};

}  // namespace evade::prediction
