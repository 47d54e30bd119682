// Reference trajectory from the ROUTE polyline: the closest point ahead of
// the current progress (monotone along the route, no jumping back to an
// earlier part that passes close by), then arc-length steps at the
// reference speed, slowing to a stop at the route's end; heading from the
// path tangent (level with the end or past it: towards the end), unwrapped
// relative to the robot's yaw.
#pragma once

#include <vector>

namespace evade::planning {

class RouteFollower {
 public:
  // Replaces the route (consecutive duplicate points dropped). Returns false
  // (and keeps the old route) for fewer than 2 distinct or non-finite points.
  // Progress restarts only when the route actually changed.
  bool set_route(const std::vector<double>& x, const std::vector<double>& y);
  bool has_route() const { return s_.size() >= 2; }

  // Advances the progress to the closest point at or ahead of it within
  // `search_window` metres of arc length.
  void update_progress(double px, double py, double search_window);

  // Reference states k = 0..N for a robot at (px, py) with heading `yaw`
  // (ref_yaw unwrapped so that ref_yaw[0] is within pi of `yaw`). With the
  // progress at the route's end, the heading is the bearing from the robot
  // to the end, not the path's tangent.
  void reference(double px, double py, double yaw, int N, double dt, double speed, double end_decel,
                 std::vector<double>* rx, std::vector<double>* ry, std::vector<double>* ryaw) const;

  // The route point at arc length s (clamped to the route).
  void position_at(double s, double* px, double* py) const {
    double heading;
    point_at(s, px, py, &heading);
  }
  // Appends the route's vertices after arc length s, in order.
  void vertices_after(double s, std::vector<double>* x, std::vector<double>* y) const;

  double progress() const { return progress_; }
  double length() const { return s_.empty() ? 0.0 : s_.back(); }
  double end_x() const { return x_.back(); }
  double end_y() const { return y_.back(); }

 private:
  void point_at(double s, double* px, double* py, double* heading) const;
  std::vector<double> x_, y_, s_;
  double progress_ = 0;
  bool progress_valid_ = false;
};

}  // namespace evade::planning
