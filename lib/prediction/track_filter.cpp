#include "prediction/track_filter.h"

#include <Eigen/Cholesky>
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

Covariance process_noise(const FilterParams& p, double dt) {
  Covariance Q = Covariance::Zero();
  const double t2 = dt * dt, t3 = t2 * dt, t4 = t3 * dt, t5 = t4 * dt;
  // Continuous white jerk of PSD q integrated over dt (the standard
  // discretisation of the constant-acceleration model).
  const double q = p.jerk_psd_m2ps5;
  const double blk[3][3] = {{t5 / 20, t4 / 8, t3 / 6}, {t4 / 8, t3 / 3, t2 / 2}, {t3 / 6, t2 / 2, dt}};
  for (const auto& ax : kAxes)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q(ax[i], ax[j]) = q * blk[i][j];
  Q(kA, kA) = p.axis_psd_m2ps * dt;
  Q(kB, kB) = p.axis_psd_m2ps * dt;
  Q(kTheta, kTheta) = p.theta_psd_rad2ps * dt;
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
  P_(kX, kX) = P_(kY, kY) = params.adaptive.r_pos_min_m2;
  P_(kA, kA) = P_(kB, kB) = f.r_axis_m2;
  P_(kTheta, kTheta) = f.r_theta_rad2 + f.r_axis_m2 / std::pow(std::max(std::fabs(z.a - z.b), f.orientation_min_elongation_m), 2);
  P_(kVx, kVx) = P_(kVy, kVy) = f.init_speed_std_mps * f.init_speed_std_mps;
  P_(kAx, kAx) = P_(kAy, kAy) = f.init_accel_std_mps2 * f.init_accel_std_mps2;
  window_.reserve(static_cast<size_t>(params.adaptive.window_frames));
  window_.push_back({z.a, z.b, x_(kTheta)});
  last_theta_ = x_(kTheta);
  use_tracker_variation_ = params.adaptive.shape_variation_source == "tracker";
  window_next_ = window_.size() % static_cast<size_t>(params.adaptive.window_frames);
  updates_ = 0;
}

void TrackFilter::predict(double dt) { propagate(&x_, &P_, process_noise(params_->filter, dt), dt); }

double TrackFilter::own_shape_variation() const {
  const size_t m = window_.size();
  if (m < 2) return 0.0;
  double ma = 0, mb = 0, mt = 0;
  for (const auto& s : window_) { ma += s.a; mb += s.b; mt += s.theta; }
  ma /= m; mb /= m; mt /= m;
  const double elongation = std::fabs(ma - mb);
  double sum = 0;
  for (const auto& s : window_) {
    const double dt = elongation * (s.theta - mt);
    sum += (s.a - ma) * (s.a - ma) + (s.b - mb) * (s.b - mb) + dt * dt;
  }
  return sum / static_cast<double>(m - 1);
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
    ma = z.b; mb = z.a; mt = z.theta + 0.5 * kPi;
    info.swapped_axes = true;
  }
  const double theta_innovation = wrap_half_pi(mt - pt);

  // Shape window, theta unwrapped against the previous entry so that its mean is meaningful.
  const Shape aligned{ma, mb, last_theta_ + wrap_half_pi(mt - last_theta_)};
  last_theta_ = aligned.theta;
  const size_t m = static_cast<size_t>(params_->adaptive.window_frames);
  if (window_.size() < m) window_.push_back(aligned); else window_[window_next_] = aligned;
  window_next_ = (window_next_ + 1) % m;

  info.xi_eta = use_tracker_variation_ ? std::max(0.0, z.tracker_shape_variation) : own_shape_variation();
  info.r_position = adaptive_position_variance(info.xi_eta, params_->adaptive, &info.k);

  Eigen::Matrix<double, kMeasSize, 1> innovation;
  innovation << z.x - x_(kX), z.y - x_(kY), ma - pa, mb - pb, theta_innovation;
  Eigen::Matrix<double, kMeasSize, 1> r_diag;
  const double elongation = std::max(std::fabs(ma - mb), f.orientation_min_elongation_m);
  r_diag << info.r_position, info.r_position, f.r_axis_m2, f.r_axis_m2,
      f.r_theta_rad2 + f.r_axis_m2 / (elongation * elongation);

  // H = [I_5 0]: H P H^T is the top-left 5x5 block and P H^T the first 5 columns.
  Eigen::Matrix<double, kMeasSize, kMeasSize> S = P_.topLeftCorner<kMeasSize, kMeasSize>();
  S.diagonal() += r_diag;
  const Eigen::Matrix<double, kStateSize, kMeasSize> PHt = P_.leftCols<kMeasSize>();
  const Eigen::Matrix<double, kStateSize, kMeasSize> K = S.ldlt().solve(PHt.transpose()).transpose();
  x_ += K * innovation;
  x_(kTheta) = wrap_half_pi(x_(kTheta));
  // Joseph form: P = (I - KH) P (I - KH)^T + K R K^T, symmetric and positive by construction.
  Covariance IKH = Covariance::Identity();
  IKH.leftCols<kMeasSize>() -= K;
  P_ = IKH * P_ * IKH.transpose() + K * r_diag.asDiagonal() * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
  ++updates_;
  return info;
}

}  // namespace evade::prediction
