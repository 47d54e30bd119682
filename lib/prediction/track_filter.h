// The paper's 9-state Kalman filter for one tracked MBE (section III-B,
// "Trajectory prediction"), with the adaptive position noise of
// "Uncertainty analysis".
//
// State order (the and the paper's text): s = (x, y, a, b, theta, vx, vy, ax, ay).
// The paper PRINTS its A matrix for the order (x, y, vx, vy, ax, ay, a, b, theta):
// a 6x6 constant-acceleration block and I_3 for the shape. Mapped to our order
// it reads, with T the frame interval:
//   x'  = x + T vx + T^2/2 ax      y'  = y + T vy + T^2/2 ay
//   vx' = vx + T ax                vy' = vy + T ay
//   ax' = ax, ay' = ay,  a' = a, b' = b, theta' = theta.
// The paper's printed H = [I_2 O_2x7; O_3x6 I_3] likewise picks (x, y, a, b, theta);
// in our order that is H = [I_5 O_5x4].
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "prediction/params.h"

namespace evade::prediction {

enum StateIndex { kX = 0, kY, kA, kB, kTheta, kVx, kVy, kAx, kAy, kStateSize };

using State = Eigen::Matrix<double, kStateSize, 1>;
using Covariance = Eigen::Matrix<double, kStateSize, kStateSize>;

// Wraps an ellipse orientation (pi-periodic) into [-pi/2, pi/2).
double wrap_half_pi(double angle);

// A and Q for a step of dt seconds (Q: white jerk of PSD jerk_psd per axis,
// random walk per shape parameter).
Covariance transition_matrix(double dt);
Covariance process_noise(const FilterParams& p, double dt, double jerk_psd);
// Q of the constant-velocity manoeuvring mode: white acceleration of PSD
// accel_psd on each (p, v) pair, the same shape random walk, nothing on a.
Covariance process_noise_cv(const FilterParams& p, double dt, double accel_psd);

// x <- A x and P <- A P A^T + Q using the sparsity of A (same result as the dense products).
void propagate(State* x, Covariance* P, const Covariance& Q, double dt);

// The paper's adaptive position variance: Xi_p = kappa Xi_eta^gamma,
// k = lg(Xi_p / Xi_min) / lg(Xi_max / Xi_min) clipped to [0, 1],
// R_p = R_max^k R_min^(1-k). Returns R_p; *k_out gets k.
double adaptive_position_variance(double xi_eta, const AdaptiveNoiseParams& p, double* k_out);

// One MBE observation.
struct Measurement {
  double x = 0, y = 0, a = 0, b = 0, theta = 0;
  double tracker_shape_variation = 0;  // the tracker's Xi_eta, used when configured
};

// Aperture (FilterParams::aperture_*): an elongated MBE seen only in part
// (an end in a shadow, at the map's edge, at a tile's cut) moves its centre
// along its major axis whenever the seen part changes. From `before` to
// `after` its two ends along after's major axis move by ds + da and ds - da
// (ds: the centre's shift along it; da: the change of the half-extent along
// it, less `axis_noise` towards zero: the MBE's own jitter); the object
// moves by what both ends share (the smaller, when they moved the same way;
// nothing otherwise). Returns the rest of the centre's shift, the part that
// a change of what is seen explains; zero when `after` is not at least
// min_elongation times as long as wide, or min_elongation is 0.
Eigen::Vector2d aperture_shift(const Measurement& before, const Measurement& after, double min_elongation,
                               double axis_noise);
// The ellipse a state predicts, as a measurement would give it.
Measurement as_measurement(const State& x);

// What the last update did (for tests and diagnostics).
struct UpdateInfo {
  double xi_eta = 0;                  // shape variation used
  double k = 0;                       // adaptive exponent
  double r_position = 0;              // R_p, m^2
  bool swapped_axes = false;          // the measurement was matched as (b, a, theta + pi/2)
  double maneuver_probability = 0;    // IMM probability of the manoeuvring mode after the update
  double stationary_probability = 0;  // IMM probability of the stationary mode after the update
};

class TrackFilter {
 public:
  // A new track: position and shape from the first MBE, velocity and
  // acceleration zero with a wide covariance (no spike from one noisy difference).
  TrackFilter(const PredictorParams& params, const Measurement& z);

  // Time update by dt seconds (with the IMM: mixing, then each mode's A and Q).
  void predict(double dt);
  // Measurement update with the MBE (with the IMM: each mode, then the mode probabilities).
  UpdateInfo update(const Measurement& z);

  // The (combined) estimate and its covariance.
  const State& state() const { return x_; }
  const Covariance& covariance() const { return P_; }
  int updates() const { return updates_; }
  // Probability of the manoeuvring mode (0 without the IMM).
  double maneuver_probability() const { return num_modes_ > kManeuver ? mu_[kManeuver] : 0.0; }
  // Probability of the stationary mode (0 without it).
  double stationary_probability() const { return num_modes_ > kStationary ? mu_[kStationary] : 0.0; }
  // Q of one step of dt to roll the estimate forward with: each mode's own
  // model, the one predict() runs (quiet: white jerk; manoeuvre: white
  // acceleration (cv) or strong jerk (ca); stationary: a centre random
  // walk), weighted by the mode probabilities.
  Covariance prediction_noise(double dt) const;

  // Xi_eta of the paper over the last m aligned shapes: sum ||eta_i - mean||^2 / (m - 1),
  // with the orientation term weighted by the mean (a - b) so that it is in metres
  // (the boundary displacement a rotation causes) and a circle's arbitrary
  // orientation does not count. 0 with fewer than two frames.
  double own_shape_variation() const;

 private:
  struct Shape {
    double a, b, theta;
  };
  // The IMM's modes, in this order; num_modes_ says how many run.
  enum ModeIndex { kQuiet = 0, kManeuver = 1, kStationary = 2, kMaxModes = 3 };
  struct Mode {
    State x;
    Covariance P;
    double jerk_psd;
  };
  void combine();
  // Appends one matched shape to the shape-variation window.
  void record_shape(double a, double b, double theta);
  Covariance mode_noise(int mode, double dt) const;
  // pi[i][j]: probability of going from mode i to mode j within dt.
  void transitions(double dt, double pi[kMaxModes][kMaxModes]) const;
  // The stationary mode's model: velocity and acceleration zero, and certain.
  static void hold_still(Mode* m);

  const PredictorParams* params_;
  Mode modes_[kMaxModes];
  int num_modes_ = 1;
  bool cv_maneuver_ = false;                // the manoeuvring mode is constant velocity (ManeuverParams::model "cv")
  double mu_[kMaxModes] = {1.0, 0.0, 0.0};  // mode probabilities
  State x_;
  Covariance P_;
  std::vector<Shape> window_;  // ring buffer of the last m aligned shapes
  size_t window_next_ = 0;
  double last_theta_ = 0;  // orientation of the newest window entry (unwrapped)
  bool use_tracker_variation_ = false;
  int updates_ = 0;
};

}  // namespace evade::prediction
