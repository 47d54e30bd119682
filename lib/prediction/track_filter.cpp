#include "prediction/track_filter.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace evade::prediction {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMeasSize = 5;

// The (p, v, a) indices of each Cartesian axis.
constexpr int kAxes[2][3] = {{kX, kVx, kAx}, {kY, kVy, kAy}};

}  // namespace

double wrap_half_pi(double angle) {
  double w = std::fmod(angle + 0.5 * kPi, kPi);
  if (w < 0) w += kPi;
  return w - 0.5 * kPi;
}

Covariance transition_matrix(double dt) {
  Covariance A = Covariance::Identity();
  for (const auto& ax : kAxes) {
    A(ax[0], ax[1]) = dt;
    A(ax[0], ax[2]) = 0.5 * dt * dt;
    A(ax[1], ax[2]) = dt;
  }
  return A;
}

Covariance process_noise(const FilterParams& p, double dt, double jerk_psd) {
  Covariance Q = Covariance::Zero();
  const double t2 = dt * dt, t3 = t2 * dt, t4 = t3 * dt, t5 = t4 * dt;
  // Continuous white jerk of PSD q integrated over dt (the standard
  // discretisation of the constant-acceleration model).
  const double q = jerk_psd;
  const double blk[3][3] = {{t5 / 20, t4 / 8, t3 / 6}, {t4 / 8, t3 / 3, t2 / 2}, {t3 / 6, t2 / 2, dt}};
  for (const auto& ax : kAxes)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q(ax[i], ax[j]) = q * blk[i][j];
  Q(kA, kA) = p.axis_psd_m2ps * dt;
  Q(kB, kB) = p.axis_psd_m2ps * dt;
  Q(kTheta, kTheta) = p.theta_psd_rad2ps * dt;
  return Q;
}

Covariance process_noise_cv(const FilterParams& p, double dt, double accel_psd) {
  Covariance Q = process_noise(p, dt, 0.0);
  const double q = accel_psd, t2 = dt * dt, t3 = t2 * dt;
  for (const auto& ax : kAxes) {
    Q(ax[0], ax[0]) += q * t3 / 3;
    Q(ax[0], ax[1]) += q * t2 / 2;
    Q(ax[1], ax[0]) += q * t2 / 2;
    Q(ax[1], ax[1]) += q * dt;
  }
  return Q;
}

void propagate(State* x, Covariance* P, const Covariance& Q, double dt) {
  const double h = 0.5 * dt * dt;
  State& s = *x;
  Covariance& M = *P;
  for (const auto& ax : kAxes) {
    s(ax[0]) += dt * s(ax[1]) + h * s(ax[2]);
    s(ax[1]) += dt * s(ax[2]);
  }
  // Rows: M <- A M (row p += dt row v + h row a; row v += dt row a; p first,
  // since it reads the old v row).
  for (const auto& ax : kAxes) {
    M.row(ax[0]) += dt * M.row(ax[1]) + h * M.row(ax[2]);
    M.row(ax[1]) += dt * M.row(ax[2]);
  }
  // Columns: M <- M A^T.
  for (const auto& ax : kAxes) {
    M.col(ax[0]) += dt * M.col(ax[1]) + h * M.col(ax[2]);
    M.col(ax[1]) += dt * M.col(ax[2]);
  }
  M += Q;
}

double adaptive_position_variance(double xi_eta, const AdaptiveNoiseParams& p, double* k_out) {
  double k = 0.0;
  if (xi_eta > 0.0) {
    const double xi_p = p.kappa * std::pow(xi_eta, p.gamma);
    k = std::log10(xi_p / p.xi_min_m2) / std::log10(p.xi_max_m2 / p.xi_min_m2);
    k = std::clamp(k, 0.0, 1.0);
  }
  if (k_out) *k_out = k;
  return std::pow(p.r_pos_max_m2, k) * std::pow(p.r_pos_min_m2, 1.0 - k);
}

Measurement as_measurement(const State& x) {
  Measurement m;
  m.x = x(kX);
  m.y = x(kY);
  m.a = x(kA);
  m.b = x(kB);
  m.theta = x(kTheta);
  return m;
}

Eigen::Vector2d aperture_shift(const Measurement& before, const Measurement& after, double min_elongation,
                               double axis_noise) {
  const double a = std::max(after.a, after.b), b = std::min(after.a, after.b);
  if (!(min_elongation > 0.0) || !(a >= min_elongation * b)) return Eigen::Vector2d::Zero();
  const double theta = after.a >= after.b ? after.theta : after.theta + 0.5 * kPi;
  const Eigen::Vector2d u(std::cos(theta), std::sin(theta));
  // before's half-extent along u (its support function)
  const double phi = theta - before.theta;
  const double extent = std::hypot(before.a * std::cos(phi), before.b * std::sin(phi));
  const double ds = u.dot(Eigen::Vector2d(after.x - before.x, after.y - before.y));
  const double da = std::max(0.0, std::fabs(a - extent) - axis_noise);
  const double shared = std::copysign(std::max(0.0, std::fabs(ds) - da), ds);
  return (ds - shared) * u;
}

TrackFilter::TrackFilter(const PredictorParams& params, const Measurement& z) : params_(&params) {
  const FilterParams& f = params.filter;
  x_.setZero();
  x_(kX) = z.x;
  x_(kY) = z.y;
  x_(kA) = z.a;
  x_(kB) = z.b;
  x_(kTheta) = wrap_half_pi(z.theta);
  P_.setZero();
  // Position: the noise of one steady MBE (R_p,min); the shape window fills from here.
  P_(kX, kX) = P_(kY, kY) = params.adaptive_noise.r_pos_min_m2;
  P_(kA, kA) = P_(kB, kB) = f.r_axis_m2;
  P_(kTheta, kTheta) =
      f.r_theta_rad2 + f.r_axis_m2 / std::pow(std::max(std::fabs(z.a - z.b), f.orientation_min_elongation_m), 2);
  P_(kVx, kVx) = P_(kVy, kVy) = f.init_speed_std_mps * f.init_speed_std_mps;
  P_(kAx, kAx) = P_(kAy, kAy) = f.init_accel_std_mps2 * f.init_accel_std_mps2;
  num_modes_ = !params.maneuver.enabled ? 1 : params.stationary.enabled ? 3 : 2;
  cv_maneuver_ = params.maneuver.model == "cv";
  modes_[kQuiet] = {x_, P_, f.jerk_psd_m2ps5};
  modes_[kManeuver] = {x_, P_, params.maneuver.jerk_psd_m2ps5};
  modes_[kStationary] = {x_, P_, 0.0};
  hold_still(&modes_[kStationary]);
  // Start at the stationary distribution of the mode chain (see transitions):
  // each mode's share is proportional to the time spent in it per manoeuvre.
  const double stop = num_modes_ == 3 ? params.stationary.stop_share : 0.0;
  const double share[kMaxModes] = {(1.0 - stop) * params.maneuver.mean_quiet_s, params.maneuver.mean_maneuver_s,
                                   stop * params.stationary.mean_stationary_s};
  double total = 0;
  for (int j = 0; j < num_modes_; ++j) total += share[j];
  for (int j = 0; j < kMaxModes; ++j) mu_[j] = j < num_modes_ ? share[j] / total : 0.0;
  combine();
  window_.reserve(static_cast<size_t>(params.adaptive_noise.window_frames));
  window_.push_back({z.a, z.b, x_(kTheta)});
  last_theta_ = x_(kTheta);
  use_tracker_variation_ = params.adaptive_noise.shape_variation_source == "tracker";
  window_next_ = window_.size() % static_cast<size_t>(params.adaptive_noise.window_frames);
  updates_ = 0;
}

namespace {

// a - b with the orientation difference taken pi-periodically.
State state_difference(const State& a, const State& b) {
  State d = a - b;
  d(kTheta) = wrap_half_pi(d(kTheta));
  return d;
}

}  // namespace

void TrackFilter::hold_still(Mode* m) {
  m->x.segment<4>(kVx).setZero();
  m->P.block<4, kStateSize>(kVx, 0).setZero();
  m->P.block<kStateSize, 4>(0, kVx).setZero();
}

void TrackFilter::transitions(double dt, double pi[kMaxModes][kMaxModes]) const {
  // Leaving a mode within dt: 1 - exp(-dt / mean time in it). Steady motion
  // and standing end in a manoeuvre; a manoeuvre ends in either.
  const ManeuverParams& mv = params_->maneuver;
  const double leave_quiet = -std::expm1(-dt / mv.mean_quiet_s);
  const double leave_maneuver = -std::expm1(-dt / mv.mean_maneuver_s);
  for (int i = 0; i < kMaxModes; ++i)
    for (int j = 0; j < kMaxModes; ++j) pi[i][j] = 0.0;
  pi[kQuiet][kQuiet] = 1.0 - leave_quiet;
  pi[kQuiet][kManeuver] = leave_quiet;
  pi[kManeuver][kManeuver] = 1.0 - leave_maneuver;
  if (num_modes_ < 3) {
    pi[kManeuver][kQuiet] = leave_maneuver;
    return;
  }
  const StationaryParams& st = params_->stationary;
  const double leave_stationary = -std::expm1(-dt / st.mean_stationary_s);
  pi[kManeuver][kQuiet] = leave_maneuver * (1.0 - st.stop_share);
  pi[kManeuver][kStationary] = leave_maneuver * st.stop_share;
  pi[kStationary][kManeuver] = leave_stationary;
  pi[kStationary][kStationary] = 1.0 - leave_stationary;
}

Covariance TrackFilter::mode_noise(int j, double dt) const {
  if (j == kStationary) {
    Covariance Q = process_noise(params_->filter, dt, 0.0);
    Q(kX, kX) += params_->stationary.position_psd_m2ps * dt;
    Q(kY, kY) += params_->stationary.position_psd_m2ps * dt;
    return Q;
  }
  if (j == kManeuver && cv_maneuver_) return process_noise_cv(params_->filter, dt, params_->maneuver.accel_psd_m2ps3);
  return process_noise(params_->filter, dt, modes_[j].jerk_psd);
}

Covariance TrackFilter::prediction_noise(double dt) const {
  Covariance Q = Covariance::Zero();
  for (int j = 0; j < num_modes_; ++j) Q += mu_[j] * mode_noise(j, dt);
  return Q;
}

void TrackFilter::combine() {
  if (num_modes_ == 1) {
    x_ = modes_[0].x;
    P_ = modes_[0].P;
    return;
  }
  const State ref = modes_[0].x;
  State mean = State::Zero();
  for (int j = 0; j < num_modes_; ++j) mean += mu_[j] * state_difference(modes_[j].x, ref);
  x_ = ref + mean;
  x_(kTheta) = wrap_half_pi(x_(kTheta));
  P_.setZero();
  for (int j = 0; j < num_modes_; ++j) {
    const State d = state_difference(modes_[j].x, x_);
    P_ += mu_[j] * (modes_[j].P + d * d.transpose());
  }
}

void TrackFilter::predict(double dt) {
  const int n = num_modes_;
  if (n > 1) {
    // IMM mixing: each mode starts from the mix of all modes weighted by
    // the probability that the target was in mode i given it is now in j.
    double pi[kMaxModes][kMaxModes];
    transitions(dt, pi);
    double c[kMaxModes];
    Mode mixed[kMaxModes];
    for (int j = 0; j < n; ++j) {
      c[j] = 0.0;
      for (int i = 0; i < n; ++i) c[j] += pi[i][j] * mu_[i];
      mixed[j] = modes_[j];
      if (c[j] <= 0.0) continue;  // unreachable mode (stop_share 0): unchanged
      State x0 = modes_[j].x;
      for (int i = 0; i < n; ++i) x0 += pi[i][j] * mu_[i] / c[j] * state_difference(modes_[i].x, modes_[j].x);
      x0(kTheta) = wrap_half_pi(x0(kTheta));
      Covariance P0 = Covariance::Zero();
      for (int i = 0; i < n; ++i) {
        const State d = state_difference(modes_[i].x, x0);
        P0 += pi[i][j] * mu_[i] / c[j] * (modes_[i].P + d * d.transpose());
      }
      mixed[j].x = x0;
      mixed[j].P = P0;
    }
    double total = 0.0;
    for (int j = 0; j < n; ++j) total += c[j];
    for (int j = 0; j < n; ++j) {
      modes_[j] = mixed[j];
      mu_[j] = c[j] / total;
    }
  }
  for (int j = 0; j < n; ++j) {
    Mode& m = modes_[j];
    if (j == kStationary) {
      hold_still(&m);
    } else if (j == kManeuver && cv_maneuver_) {
      // constant velocity: no acceleration; white acceleration drives v
      m.x(kAx) = m.x(kAy) = 0.0;
      for (int a : {static_cast<int>(kAx), static_cast<int>(kAy)}) {
        m.P.row(a).setZero();
        m.P.col(a).setZero();
      }
    }
    propagate(&m.x, &m.P, mode_noise(j, dt), dt);
  }
  combine();
}

double TrackFilter::own_shape_variation() const {
  const size_t m = window_.size();
  if (m < 2) return 0.0;
  double ma = 0, mb = 0, mt = 0;
  for (const auto& s : window_) {
    ma += s.a;
    mb += s.b;
    mt += s.theta;
  }
  ma /= m;
  mb /= m;
  mt /= m;
  const double elongation = std::fabs(ma - mb);
  double sum = 0;
  for (const auto& s : window_) {
    const double dt = elongation * (s.theta - mt);
    sum += (s.a - ma) * (s.a - ma) + (s.b - mb) * (s.b - mb) + dt * dt;
  }
  return sum / static_cast<double>(m - 1);
}

void TrackFilter::record_shape(double a, double b, double theta) {
  // theta unwrapped against the previous entry so that its mean is meaningful
  const Shape aligned{a, b, last_theta_ + wrap_half_pi(theta - last_theta_)};
  last_theta_ = aligned.theta;
  const size_t m = static_cast<size_t>(params_->adaptive_noise.window_frames);
  if (window_.size() < m)
    window_.push_back(aligned);
  else
    window_[window_next_] = aligned;
  window_next_ = (window_next_ + 1) % m;
}

UpdateInfo TrackFilter::update(const Measurement& z) {
  const FilterParams& f = params_->filter;
  UpdateInfo info;

  // An MBE (a, b, theta) and (b, a, theta + pi/2) are the same ellipse; the
  // tracker's a >= b convention flips between them when a ~ b. Match the
  // representation closest to the predicted shape (boundary displacement metric).
  const double pa = x_(kA), pb = x_(kB), pt = x_(kTheta);
  const double scale = 0.5 * (std::fabs(pa) + std::fabs(pb));
  auto distance = [&](double a, double b, double t) {
    const double dtheta = scale * wrap_half_pi(t - pt);
    return (a - pa) * (a - pa) + (b - pb) * (b - pb) + dtheta * dtheta;
  };
  double ma = z.a, mb = z.b, mt = z.theta;
  if (distance(z.b, z.a, z.theta + 0.5 * kPi) < distance(z.a, z.b, z.theta)) {
    ma = z.b;
    mb = z.a;
    mt = z.theta + 0.5 * kPi;
    info.swapped_axes = true;
  }

  record_shape(ma, mb, mt);

  info.xi_eta = use_tracker_variation_ ? std::max(0.0, z.tracker_shape_variation) : own_shape_variation();
  info.r_position = adaptive_position_variance(info.xi_eta, params_->adaptive_noise, &info.k);

  Eigen::Matrix<double, kMeasSize, 1> r_diag;
  const double elongation = std::max(std::fabs(ma - mb), f.orientation_min_elongation_m);
  r_diag << info.r_position, info.r_position, f.r_axis_m2, f.r_axis_m2,
      f.r_theta_rad2 + f.r_axis_m2 / (elongation * elongation);

  double log_likelihood[kMaxModes] = {0.0, 0.0, 0.0};
  for (int j = 0; j < num_modes_; ++j) {
    // Standing still, a change of the seen extent explains what the ends do
    // not share: it moves the centre as a known offset (never past the
    // measurement). The moving modes measure it as motion.
    if (j == kStationary)
      modes_[j].x.head<2>() +=
          aperture_shift(as_measurement(modes_[j].x), z, f.aperture_min_elongation, f.aperture_axis_noise_m);
    State& x = modes_[j].x;
    Covariance& P = modes_[j].P;
    Eigen::Matrix<double, kMeasSize, 1> innovation;
    innovation << z.x - x(kX), z.y - x(kY), ma - x(kA), mb - x(kB), wrap_half_pi(mt - x(kTheta));
    // H = [I_5 0]: H P H^T is the top-left 5x5 block and P H^T the first 5 columns.
    Eigen::Matrix<double, kMeasSize, kMeasSize> S = P.topLeftCorner<kMeasSize, kMeasSize>();
    S.diagonal() += r_diag;
    const Eigen::Matrix<double, kStateSize, kMeasSize> PHt = P.leftCols<kMeasSize>();
    const Eigen::Matrix<double, kStateSize, kMeasSize> K = S.ldlt().solve(PHt.transpose()).transpose();
    if (num_modes_ > 1) {
      // Mode likelihood from the centre innovation only: the modes differ in kinematics alone.
      const Eigen::Matrix2d Sp = S.topLeftCorner<2, 2>();
      const Eigen::Vector2d nu = innovation.head<2>();
      log_likelihood[j] = -0.5 * nu.dot(Sp.ldlt().solve(nu)) - 0.5 * std::log(Sp.determinant());
    }
    x += K * innovation;
    x(kTheta) = wrap_half_pi(x(kTheta));
    // P = (I - KH) P = P - K S K^T for the optimal gain (cheaper than the Joseph
    // form; symmetrised against round-off).
    P.noalias() -= K * S * K.transpose();
    P = 0.5 * (P + P.transpose()).eval();
  }
  if (num_modes_ > 1) {
    double top = log_likelihood[0];
    for (int j = 1; j < num_modes_; ++j) top = std::max(top, log_likelihood[j]);
    double w[kMaxModes], total = 0.0;
    for (int j = 0; j < num_modes_; ++j) total += (w[j] = mu_[j] * std::exp(log_likelihood[j] - top));
    // keep every mode alive (a probability of exactly 0 could never recover)
    constexpr double kMinProbability = 1e-6;
    double clamped = 0.0;
    for (int j = 0; j < num_modes_; ++j) clamped += (w[j] = std::max(w[j] / total, kMinProbability));
    for (int j = 0; j < num_modes_; ++j) mu_[j] = w[j] / clamped;
  }
  combine();
  info.maneuver_probability = maneuver_probability();
  info.stationary_probability = stationary_probability();
  ++updates_;
  return info;
}

}  // namespace evade::prediction
