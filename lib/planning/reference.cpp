#include "planning/reference.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planning/problem.h"

namespace evade::planning {

bool RouteFollower::set_route(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) return false;
  std::vector<double> nx, ny;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) return false;
    if (!nx.empty() && nx.back() == x[i] && ny.back() == y[i]) continue;
    nx.push_back(x[i]);
    ny.push_back(y[i]);
  }
  if (nx.size() < 2) return false;
  if (nx == x_ && ny == y_) return true;  // same route re-published: keep progress
  x_ = std::move(nx);
  y_ = std::move(ny);
  s_.assign(x_.size(), 0.0);
  for (size_t i = 1; i < x_.size(); ++i) s_[i] = s_[i - 1] + std::hypot(x_[i] - x_[i - 1], y_[i] - y_[i - 1]);
  progress_ = 0;
  progress_valid_ = false;
  return true;
}

void RouteFollower::update_progress(double px, double py, double search_window) {
  if (!has_route()) return;
  // First fix on a new route: the closest point anywhere; afterwards only
  // at or ahead of the progress, within the window.
  const double lo = progress_valid_ ? progress_ : 0.0;
  const double hi = progress_valid_ ? progress_ + search_window : s_.back();
  double best_d = std::numeric_limits<double>::infinity(), best_s = lo;
  for (size_t i = 0; i + 1 < x_.size(); ++i) {
    if (s_[i + 1] < lo || s_[i] > hi) continue;
    const double seg = s_[i + 1] - s_[i];
    const double dx = x_[i + 1] - x_[i], dy = y_[i + 1] - y_[i];
    double t = ((px - x_[i]) * dx + (py - y_[i]) * dy) / (seg * seg);
    const double tmin = std::max(0.0, (lo - s_[i]) / seg), tmax = std::min(1.0, (hi - s_[i]) / seg);
    t = std::clamp(t, tmin, tmax);
    const double d = std::hypot(x_[i] + t * dx - px, y_[i] + t * dy - py);
    if (d < best_d) {
      best_d = d;
      best_s = s_[i] + t * seg;
    }
  }
  progress_ = std::max(lo, best_s);
  progress_valid_ = true;
}

void RouteFollower::point_at(double s, double* px, double* py, double* heading) const {
  s = std::clamp(s, 0.0, s_.back());
  size_t i = static_cast<size_t>(std::upper_bound(s_.begin(), s_.end(), s) - s_.begin());
  i = std::clamp<size_t>(i, 1, s_.size() - 1) - 1;  // segment i .. i+1
  const double seg = s_[i + 1] - s_[i];
  const double t = (s - s_[i]) / seg;
  *px = x_[i] + t * (x_[i + 1] - x_[i]);
  *py = y_[i] + t * (y_[i + 1] - y_[i]);
  *heading = std::atan2(y_[i + 1] - y_[i], x_[i + 1] - x_[i]);
}

void RouteFollower::vertices_after(double s, std::vector<double>* x, std::vector<double>* y) const {
  for (size_t i = 0; i < s_.size(); ++i)
    if (s_[i] > s) {
      x->push_back(x_[i]);
      y->push_back(y_[i]);
    }
}

void RouteFollower::reference(double px, double py, double yaw, int N, double dt, double speed, double end_decel,
                              std::vector<double>* rx, std::vector<double>* ry, std::vector<double>* ryaw) const {
  rx->assign(N + 1, 0.0);
  ry->assign(N + 1, 0.0);
  ryaw->assign(N + 1, 0.0);
  double s = progress_;
  // Level with the end or past it (an avoidance carried the robot beside or
  // beyond it): every reference point is the end, and its heading, the
  // path's last tangent, points away from the robot's way to it or across
  // it. A robot that cannot reverse then stands still outside the goal
  // tolerance: turning round raises the heading cost before any motion
  // lowers the position cost. So head for the end.
  const bool at_end = progress_ >= s_.back();
  const double to_end_x = x_.back() - px, to_end_y = y_.back() - py;
  const bool head_for_end = at_end && std::hypot(to_end_x, to_end_y) > 0.0;
  const double bearing_to_end = head_for_end ? std::atan2(to_end_y, to_end_x) : 0.0;
  double prev_heading = 0;
  for (int k = 0; k <= N; ++k) {
    double heading;
    point_at(s, &(*rx)[k], &(*ry)[k], &heading);
    if (head_for_end) heading = bearing_to_end;
    // unwrap: the first relative to the robot's yaw, then step by step
    (*ryaw)[k] = k == 0 ? yaw + wrap_angle(heading - yaw) : (*ryaw)[k - 1] + wrap_angle(heading - prev_heading);
    prev_heading = heading;
    // speed profile: v_ref, limited so that it can stop at the end at end_decel
    const double remaining = std::max(0.0, s_.back() - s);
    const double v = std::min(speed, std::sqrt(2.0 * end_decel * remaining));
    s = std::min(s_.back(), s + v * dt);
  }
}

}  // namespace evade::planning
