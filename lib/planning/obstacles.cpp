#include "planning/obstacles.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::planning {

bool valid_track(const evade::track_prediction_t& t) {
  const size_t n = static_cast<size_t>(std::max(0, t.horizon));
  if (n == 0 || t.x.size() != n || t.y.size() != n || t.a.size() != n || t.b.size() != n || t.theta.size() != n)
    return false;
  if (!std::isfinite(t.vx) || !std::isfinite(t.vy)) return false;
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(t.x[i]) || !std::isfinite(t.y[i]) || !std::isfinite(t.theta[i])) return false;
    if (!(t.a[i] > 0) || !(t.b[i] > 0) || !std::isfinite(t.a[i]) || !std::isfinite(t.b[i])) return false;
  }
  return true;
}

ObstacleTrack align_track(const evade::track_prediction_t& t, double pred_dt, double offset_s, int N, double plan_dt) {
  ObstacleTrack o;
  o.id = t.id;
  const int last = t.horizon - 1;
  for (int k = 0; k <= N; ++k) {
    const double f = (offset_s + k * plan_dt) / pred_dt;  // fractional prediction index
    double x, y;
    int shape;
    if (f <= 0 || last == 0) {  // before the first step, or a single-step track
      const double tau = f * pred_dt;
      x = t.x[0] + t.vx * tau;
      y = t.y[0] + t.vy * tau;
      shape = 0;
    } else if (f >= last) {
      const double tau = (f - last) * pred_dt;
      x = t.x[last] + t.vx * tau;
      y = t.y[last] + t.vy * tau;
      shape = last;
    } else {
      const int i = static_cast<int>(std::floor(f));
      const double w = f - i;
      x = (1 - w) * t.x[i] + w * t.x[i + 1];
      y = (1 - w) * t.y[i] + w * t.y[i + 1];
      shape = w < 0.5 ? i : i + 1;
    }
    o.x.push_back(x);
    o.y.push_back(y);
    o.a.push_back(t.a[shape]);
    o.b.push_back(t.b[shape]);
    o.theta.push_back(t.theta[shape]);
    const double sigma = t.sigma.size() == t.a.size() ? t.sigma[shape] : 0.0;
    o.sigma.push_back(std::isfinite(sigma) && sigma > 0 ? sigma : 0.0);
  }
  return o;
}

bool valid_observed(const evade::obstacle_t& o) {
  return std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.theta) && o.a > 0 && o.b > 0 &&
         std::isfinite(o.a) && std::isfinite(o.b);
}

ObstacleTrack hold_observed(const evade::obstacle_t& o, int N) {
  ObstacleTrack t;
  t.id = o.id;
  t.x.assign(N + 1, o.x);
  t.y.assign(N + 1, o.y);
  t.a.assign(N + 1, o.a);
  t.b.assign(N + 1, o.b);
  t.theta.assign(N + 1, o.theta);
  return t;
}

void CurveFitHistory::add(const evade::obstacle_list_t& msg) {
  for (const auto& o : msg.obstacles) {
    if (!valid_observed(o)) continue;
    auto& h = history_[o.id];
    if (!h.empty() && h.back().utime >= msg.utime) continue;  // replayed or out of order
    h.push_back({msg.utime, o.x, o.y});
  }
  // forget samples (and tracks) older than the window
  for (auto it = history_.begin(); it != history_.end();) {
    auto& h = it->second;
    while (!h.empty() && msg.utime - h.front().utime > window_us_) h.pop_front();
    it = h.empty() ? history_.erase(it) : std::next(it);
  }
}

size_t CurveFitHistory::samples(int64_t id) const {
  auto it = history_.find(id);
  return it == history_.end() ? 0 : it->second.size();
}

ObstacleTrack CurveFitHistory::extrapolate(const evade::obstacle_t& ob, int64_t t_plan_us, int N,
                                           double plan_dt) const {
  ObstacleTrack o = hold_observed(ob, N);
  auto it = history_.find(ob.id);
  if (it == history_.end() || it->second.size() < 2) return o;
  const auto& h = it->second;
  // least squares in time relative to the newest sample (s), degree limited
  // by the number of samples
  const int deg = std::min<int>(degree_, static_cast<int>(h.size()) - 1);
  const int64_t t0 = h.back().utime;
  Eigen::MatrixXd A(h.size(), deg + 1);
  Eigen::VectorXd bx(h.size()), by(h.size());
  for (size_t r = 0; r < h.size(); ++r) {
    const double tau = (h[r].utime - t0) * 1e-6;
    double p = 1;
    for (int c = 0; c <= deg; ++c, p *= tau) A(r, c) = p;
    bx(r) = h[r].x;
    by(r) = h[r].y;
  }
  const auto qr = A.colPivHouseholderQr();
  const Eigen::VectorXd cx = qr.solve(bx), cy = qr.solve(by);
  if (!cx.allFinite() || !cy.allFinite()) return o;
  for (int k = 0; k <= N; ++k) {
    const double tau = (t_plan_us - t0) * 1e-6 + k * plan_dt;
    double p = 1, x = 0, y = 0;
    for (int c = 0; c <= deg; ++c, p *= tau) {
      x += cx(c) * p;
      y += cy(c) * p;
    }
    o.x[k] = x;
    o.y[k] = y;
  }
  return o;
}

namespace {

// The mode's input, moved over the horizon as the mode says (no decay, no
// selection yet).
std::vector<ObstacleTrack> moved_obstacles(const PlannerParams& p, const ObstacleInputs& in, int64_t t_plan_us,
                                           int* invalid) {
  const ModeSpec& mode = mode_spec(p.mode);
  const int N = p.horizon_steps;
  std::vector<ObstacleTrack> out;
  if (mode.source == ObstacleSource::kPredicted && in.predictions) {
    const evade::prediction_list_t& msg = *in.predictions;
    const double offset_s = (t_plan_us - msg.utime) * 1e-6;
    for (const auto& t : msg.tracks) {
      if (!valid_track(t)) {
        if (invalid) ++*invalid;
        continue;
      }
      out.push_back(align_track(t, msg.dt, offset_s, N, p.dt_s));
    }
  } else if (mode.source == ObstacleSource::kObserved && in.observed) {
    for (const auto& o : in.observed->obstacles) {
      if (!valid_observed(o)) {
        if (invalid) ++*invalid;
        continue;
      }
      const bool fit = mode.motion == ObstacleMotion::kCurveFit && in.history;
      out.push_back(fit ? in.history->extrapolate(o, t_plan_us, N, p.dt_s) : hold_observed(o, N));
    }
  }
  return out;
}

}  // namespace

std::vector<ObstacleTrack> constraint_obstacles(const PlannerParams& p, const ObstacleInputs& in, int64_t t_plan_us,
                                                double px, double py, int* invalid) {
  const int N = p.horizon_steps;
  const double decay = p.constraint_decay();
  std::vector<std::pair<double, ObstacleTrack>> scored;
  for (ObstacleTrack& o : moved_obstacles(p, in, t_plan_us, invalid)) {
    o.decay = decay;
    double closest = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= N; ++k) closest = std::min(closest, std::hypot(o.x[k] - px, o.y[k] - py) - o.a[k]);
    if (!std::isfinite(closest) || closest > p.obstacle_consider_radius_m) continue;
    scored.emplace_back(closest, std::move(o));
  }
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<ObstacleTrack> out;
  for (auto& s : scored) {
    if (static_cast<int>(out.size()) >= p.max_obstacles) break;
    out.push_back(std::move(s.second));
  }
  return out;
}

void attach_measurements(const evade::obstacle_list_t& observed, std::vector<ObstacleTrack>* obstacles) {
  std::map<int64_t, const evade::obstacle_t*> by_id;
  for (const evade::obstacle_t& o : observed.obstacles) by_id[o.id] = &o;
  for (ObstacleTrack& t : *obstacles) {
    const auto it = by_id.find(t.id);
    if (t.field || it == by_id.end()) continue;
    const evade::obstacle_t& o = *it->second;
    if (valid_observed(o)) t.measured = ObstacleTrack::Body{o.x, o.y, o.a, o.b, o.theta};
  }
}

}  // namespace evade::planning
