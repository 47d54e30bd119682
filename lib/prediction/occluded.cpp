#include "prediction/occluded.h"

#include <cmath>

namespace evade::prediction {
namespace {

double cross(double ax, double ay, double bx, double by, double px, double py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

}  // namespace

bool inside(const evade::hidden_region_t& r, double x, double y) {
  // The quadrilateral is convex (two rays from one point, cut beyond the
  // occluder): inside = on the same side of its four edges.
  const double vx[4] = {r.near_x[0], r.near_x[1], r.far_x[1], r.far_x[0]};
  const double vy[4] = {r.near_y[0], r.near_y[1], r.far_y[1], r.far_y[0]};
  int pos = 0, neg = 0;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const double c = cross(vx[i], vy[i], vx[j], vy[j], x, y);
    pos += c > 0;
    neg += c < 0;
  }
  return pos == 0 || neg == 0;
}

bool keep_hidden(const OccludedParams& p, const evade::hidden_region_list_t& regions, double x, double y, double a,
                 double speed_mps, double unseen_s, double horizon_s) {
  if (!p.enabled || unseen_s > p.max_s || speed_mps < p.min_speed_mps) return false;
  const double to_sensor = std::hypot(x - regions.sensor_x, y - regions.sensor_y) - a;
  if (to_sensor > p.max_speed_mps * (unseen_s + horizon_s)) return false;
  for (const auto& r : regions.regions)
    if (inside(r, x, y)) return true;
  return false;
}

void hidden_prediction(const OccludedParams& p, int64_t id, double x, double y, double a, double b, double theta,
                       double unseen_s, int steps, double dt, evade::track_prediction_t* out) {
  out->id = id;
  out->vx = out->vy = out->ax = out->ay = 0.0;
  out->horizon = steps;
  out->x.assign(steps, x);
  out->y.assign(steps, y);
  out->theta.assign(steps, theta);
  out->a.resize(steps);
  out->b.resize(steps);
  out->sigma.resize(steps);
  for (int k = 0; k < steps; ++k) {
    const double grow = p.max_speed_mps * (unseen_s + k * dt);
    out->a[k] = a + grow;
    out->b[k] = b + grow;
    out->sigma[k] = grow;
  }
}

}  // namespace evade::prediction
