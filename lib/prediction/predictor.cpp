#include "prediction/predictor.h"

#include <algorithm>
#include <cmath>

#include "prediction/inflation.h"

namespace evade::prediction {
namespace {

bool valid(const evade::obstacle_t& o, const PredictorParams& p) {
  const double v[] = {o.x, o.y, o.a, o.b, o.theta, o.shape_variation};
  for (double d : v)
    if (!std::isfinite(d)) return false;
  return std::fabs(o.x) <= p.max_abs_coordinate_m && std::fabs(o.y) <= p.max_abs_coordinate_m && o.a > 0.0 &&
         o.b >= 0.0 && o.a <= p.max_axis_m && o.b <= p.max_axis_m;
}

bool finite(const TrackFilter& f) { return f.state().allFinite() && f.covariance().allFinite(); }

// Scales a 2-vector down to a maximum norm.
void clip_norm(double* x, double* y, double max_norm) {
  const double n = std::hypot(*x, *y);
  if (n > max_norm) {
    *x *= max_norm / n;
    *y *= max_norm / n;
  }
}

}  // namespace

Predictor::Predictor(const PredictorParams& params)
    : params_(std::make_shared<const PredictorParams>(params)),
      chi2_position_(chi_square_2dof_quantile(params.uncertainty.confidence)),
      z_shape_(normal_two_sided_quantile(params.uncertainty.confidence)) {}

const TrackFilter* Predictor::track(int64_t id) const {
  auto it = tracks_.find(id);
  return it == tracks_.end() ? nullptr : &it->second;
}

bool Predictor::process(const evade::obstacle_list_t& in, evade::prediction_list_t* out, FrameStats* stats) {
  FrameStats st;
  if (last_utime_ >= 0 && in.utime <= last_utime_) return false;
  // dt from the message stamps: frames arrive at 10-20 Hz with jitter.
  const double dt = last_utime_ < 0 ? 0.0 : 1e-6 * static_cast<double>(in.utime - last_utime_);
  if (last_utime_ >= 0 && dt > params_->max_frame_gap_s) {
    st.gap_reset = !tracks_.empty();
    st.dropped += static_cast<int>(tracks_.size());
    tracks_.clear();
    last_seen_utime_.clear();
    last_z_.clear();
  }
  last_utime_ = in.utime;
  update_seen(in, dt, &st);
  coast_missing(in.utime, dt, &st);

  out->utime = in.utime;
  out->dt = params_->prediction_dt_s;
  out->horizon = params_->prediction_steps + 1;
  out->tracks.clear();
  out->tracks.reserve(order_.size() + coasting_.size());
  for (const auto* ids : {&order_, &coasting_})
    for (int64_t id : *ids) {
      out->tracks.emplace_back();
      const auto h = hidden_.find(id);
      if (h == hidden_.end()) {
        predict_track(id, tracks_.at(id), &out->tracks.back());
        continue;
      }
      const Measurement& z = last_z_.at(id);
      hidden_prediction(params_->occluded, id, z.x, z.y, std::max(z.a, z.b), std::min(z.a, z.b),
                        z.a >= z.b ? z.theta : std::remainder(z.theta + 0.5 * M_PI, M_PI), h->second,
                        params_->prediction_steps + 1, params_->prediction_dt_s, &out->tracks.back());
    }
  st.coasting = static_cast<int>(coasting_.size());
  st.hidden = static_cast<int>(hidden_.size());
  out->num_tracks = static_cast<int32_t>(out->tracks.size());
  if (stats) *stats = st;
  return true;
}

void Predictor::update_seen(const evade::obstacle_list_t& in, double dt, FrameStats* st) {
  seen_.clear();
  order_.clear();
  created_.clear();
  for (const auto& o : in.obstacles) {
    if (!valid(o, *params_) || !seen_.emplace(o.id, 0).second) {
      ++st->malformed;
      continue;
    }
    Measurement z;
    z.x = o.x;
    z.y = o.y;
    z.a = o.a;
    z.b = o.b;
    z.theta = o.theta;
    z.tracker_shape_variation = o.shape_variation;
    last_seen_utime_[o.id] = in.utime;
    last_z_[o.id] = z;
    auto it = tracks_.find(o.id);
    if (it == tracks_.end()) {
      it = tracks_.emplace(o.id, TrackFilter(*params_, z)).first;
      created_.push_back(o.id);
      ++st->created;
    } else {
      it->second.predict(dt);
      it->second.update(z);
      ++st->updated;
      if (!finite(it->second)) {  // never publish NaN: restart the track from this MBE
        it->second = TrackFilter(*params_, z);
        ++st->diverged;
      }
    }
    order_.push_back(o.id);
  }
}

void Predictor::coast_missing(int64_t utime, double dt, FrameStats* st) {
  // A track missing from this list coasts: the tracker keeps an unmatched
  // id alive for a few frames (occlusion, a merge with a neighbour) and
  // matches it again under the same id, so the filter is time-updated and
  // still published, its ellipse growing with the covariance, until it has
  // been unseen for coast_max_s. Dropping it at the first miss would make a
  // mover that reappears restart at rest, and the planner would take it for
  // a static obstacle. Ids are never reused by the tracker. A track seen in
  // fewer than coast_min_frames frames is not coasted: a cluster split off
  // a mover for a frame or two has no velocity yet, so its prediction is a
  // static ellipse inflated to the cap, a ghost the planner would have to
  // get around for coast_max_s.
  const int64_t coast_us = std::llround(params_->coast_max_s * 1e6);
  coasting_.clear();
  hidden_.clear();
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    const int64_t id = it->first;
    if (seen_.count(id) != 0) {
      ++it;
      continue;
    }
    const bool hidden = hidden_at(id, utime);
    if ((hidden || utime - last_seen_utime_[id] <= coast_us) && it->second.updates() + 1 >= params_->coast_min_frames) {
      it->second.predict(dt);
      if (finite(it->second)) {
        coasting_.push_back(id);
        if (hidden) hidden_[id] = 1e-6 * double(utime - last_seen_utime_[id]);
        ++it;
        continue;
      }
      ++st->diverged;
    }
    last_seen_utime_.erase(id);
    last_z_.erase(id);
    it = tracks_.erase(it);
    ++st->dropped;
  }
  std::sort(coasting_.begin(), coasting_.end());  // a fixed order, whatever the hash map's
}

bool Predictor::hidden_at(int64_t id, int64_t utime) const {
  const OccludedParams& p = params_->occluded;
  if (!p.enabled || !hidden_regions_ || std::llabs(hidden_regions_->utime - utime) > std::llround(p.max_age_s * 1e6))
    return false;
  const auto z = last_z_.find(id);
  if (z == last_z_.end()) return false;
  const double unseen_s = 1e-6 * double(utime - last_seen_utime_.at(id));
  const double horizon_s = params_->prediction_steps * params_->prediction_dt_s;
  const State& st = tracks_.at(id).state();
  return keep_hidden(p, *hidden_regions_, z->second.x, z->second.y, std::max(z->second.a, z->second.b),
                     std::hypot(st(kVx), st(kVy)), unseen_s, horizon_s);
}

void Predictor::predict_track(int64_t id, const TrackFilter& filter, evade::track_prediction_t* out) const {
  const int n = params_->prediction_steps + 1;
  const double T = params_->prediction_dt_s;
  const LimitParams& lim = params_->limits;
  const UncertaintyParams& unc = params_->uncertainty;

  State x = filter.state();
  Covariance P = filter.covariance();
  // Q of one prediction step: with the IMM, each mode's own model weighted
  // by its probability, so that a manoeuvring target's ellipse grows faster.
  const Covariance Q = filter.prediction_noise(T);
  // Caps: a noisy acceleration estimate must not fling the prediction across
  // the map, so the acceleration and speed used for extrapolation are clipped.
  clip_norm(&x(kVx), &x(kVy), lim.max_speed_mps);
  clip_norm(&x(kAx), &x(kAy), lim.max_accel_mps2);

  // Reported shape with a >= b (the filter may hold the swapped representation).
  double a = std::max(x(kA), unc.min_axis_m), b = std::max(x(kB), unc.min_axis_m), theta = x(kTheta);
  const bool swap = b > a;
  if (swap) {
    std::swap(a, b);
    theta = wrap_half_pi(theta + 0.5 * 3.14159265358979323846);
  }

  out->id = id;
  out->vx = x(kVx);
  out->vy = x(kVy);
  out->ax = x(kAx);
  out->ay = x(kAy);
  out->horizon = n;
  out->x.resize(n);
  out->y.resize(n);
  out->a.resize(n);
  out->b.resize(n);
  out->theta.resize(n);
  out->sigma.resize(n);
  for (int k = 0; k < n; ++k) {
    if (k > 0) {
      // Paper: x_k = A x_(k-1), P_k = A P_(k-1) A^T + Q; the mean with the speed cap
      // (once at the cap the acceleration stops acting), the covariance linear.
      // Past max_accel_time_s the velocity is held (a constant acceleration
      // is rarely sustained by people or bikes).
      if (k * T > lim.max_accel_time_s + 1e-9) x(kAx) = x(kAy) = 0.0;
      const double vx0 = x(kVx), vy0 = x(kVy);
      double vx1 = vx0 + T * x(kAx), vy1 = vy0 + T * x(kAy);
      if (std::hypot(vx1, vy1) > lim.max_speed_mps) {
        clip_norm(&vx1, &vy1, lim.max_speed_mps);
        x(kAx) = x(kAy) = 0.0;
      }
      x(kX) += 0.5 * (vx0 + vx1) * T;  // = vx T + ax T^2 / 2 when not capped
      x(kY) += 0.5 * (vy0 + vy1) * T;
      x(kVx) = vx1;
      x(kVy) = vy1;
      State unused = State::Zero();
      propagate(&unused, &P, Q, T);
    }
    const double r_p = position_radius(P(kX, kX), P(kX, kY), P(kY, kY), chi2_position_);
    const double r_eta = shape_radius(P(kA, kA), P(kB, kB), P(kTheta, kTheta), a - b, z_shape_);
    const Inflation inf = solve_inflation(a, b, combined_radius(r_p, r_eta, unc.combine), unc.root_tolerance_m);
    const double sigma = std::min(inf.total, unc.max_inflation_m);
    out->x[k] = x(kX);
    out->y[k] = x(kY);
    out->a[k] = a + sigma;
    out->b[k] = b + sigma;
    out->theta[k] = theta;
    out->sigma[k] = sigma;
  }
}

}  // namespace evade::prediction
