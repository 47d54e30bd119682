#include "planning/passive_safety.h"

#include <algorithm>
#include <cmath>

#include "planning/fallback.h"

namespace evade::planning {

double passive_safe_speed(double gap_m, double mover_speed_mps, double reaction_s, double decel_mps2) {
  const double s = std::max(0.0, mover_speed_mps);
  const double g = gap_m - s * reaction_s;
  if (!(g > 0.0) || !(decel_mps2 > 0.0)) return 0.0;
  const double p = reaction_s + s / decel_mps2;
  return decel_mps2 * (std::sqrt(p * p + 2.0 * g / decel_mps2) - p);
}

namespace {

// The offset (m) of the footprint's front disc; fp has at least one disc.
double front_offset_m(const Footprint& fp) { return *std::max_element(fp.offsets.begin(), fp.offsets.end()); }

// Where the measured body is nearer the front disc than body's step 0
// (gap), step 0 becomes the measured body and *gap its distance.
void nearer_measured(const Problem& front, const ObstacleTrack::Body& measured, const double* start,
                     ObstacleTrack* body, double* gap) {
  ObstacleTrack m;
  m.x = {measured.x}, m.y = {measured.y}, m.a = {measured.a}, m.b = {measured.b}, m.theta = {measured.theta};
  const double g = barrier_h_at(front, m, 0, start);
  if (!(g < *gap)) return;
  body->x[0] = measured.x, body->y[0] = measured.y, body->a[0] = measured.a, body->b[0] = measured.b;
  body->theta[0] = measured.theta;
  *gap = g;
}

}  // namespace

std::vector<MoverBound> mover_bounds(const PassiveSafetyParams& p, const Problem& pb) {
  std::vector<MoverBound> out;
  if (pb.footprint.offsets.empty()) return out;
  // the front disc alone, without d_safe (barrier_h_at reads only these)
  Problem front;
  front.footprint.offsets = {front_offset_m(pb.footprint)};
  front.footprint.radius = pb.footprint.radius;
  front.d_safe = 0.0;
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  for (const ObstacleTrack& track : pb.obstacles) {
    if (track.field || track.x.empty()) continue;
    double speed = std::max(fastest_predicted_speed(track, pb.dt), track.recent_speed_mps);
    if (track.age_s < p.min_track_age_s)
      speed = std::max(speed, p.unknown_speed_mps);
    else if (speed < p.min_mover_speed_mps)
      continue;
    MoverBound m{track, pb.lim.v_max, speed};
    remove_inflation(&m.body);
    double gap = barrier_h_at(front, m.body, 0, start);
    if (p.measured_position && track.measured) nearer_measured(front, *track.measured, start, &m.body, &gap);
    if (!std::isfinite(gap)) continue;
    m.speed_mps = std::min(pb.lim.v_max, passive_safe_speed(gap, speed, p.reaction_s, pb.lim.decel));
    out.push_back(std::move(m));
  }
  return out;
}

double passive_speed_bound(const PassiveSafetyParams& p, const Problem& pb) {
  double bound = pb.lim.v_max;
  for (const MoverBound& m : mover_bounds(p, pb)) bound = std::min(bound, m.speed_mps);
  return bound;
}

std::vector<ReachBound> passive_reach_bounds(const PassiveSafetyParams& p, const Problem& pb) {
  std::vector<ReachBound> out;
  std::vector<double> brake(static_cast<size_t>(pb.num_controls()), 0.0), states;
  double offset = 0.0;
  for (const MoverBound& m : mover_bounds(p, pb)) {
    if (!(m.speed_mps < pb.lim.v_max)) continue;
    if (states.empty()) {  // once, for the first binding mover
      project_controls(pb, &brake);
      states.resize(3 * static_cast<size_t>(pb.N + 1));
      rollout(pb, brake.data(), states.data());
      offset = front_offset_m(pb.footprint);  // a mover means a footprint (mover_bounds)
    }
    ReachBound r;
    r.id = m.body.id;
    r.x = m.body.x[0], r.y = m.body.y[0], r.a = m.body.a[0], r.b = m.body.b[0], r.theta = m.body.theta[0];
    r.speed_mps = m.mover_speed_mps;
    r.reaction_s = p.reaction_s;
    r.decel_mps2 = pb.lim.decel;
    r.offset_m = offset;
    r.radius_m = pb.footprint.radius;
    r.allowance_m.assign(static_cast<size_t>(pb.N), 0.0);
    for (int k = 0; k < pb.N; ++k) {
      const double* x = &states[3 * static_cast<size_t>(k)];
      const double braking = reach_value(r, k, x[0], x[1], x[2], brake[2 * static_cast<size_t>(k)], false).g;
      r.allowance_m[static_cast<size_t>(k)] = std::max(0.0, -braking);
    }
    out.push_back(std::move(r));
  }
  return out;
}

namespace {

// Whether every reach bound of pb holds at step k from state x going v.
bool reach_holds(const Problem& pb, int k, const double* x, double v) {
  for (const ReachBound& r : pb.reach)
    if (reach_value(r, k, x[0], x[1], x[2], v, false).g < 0.0) return false;
  return true;
}

// The fastest speed in [lo, hi] at which reach_holds, given that lo holds
// and hi does not (bisection to 1 mm/s).
double fastest_holding(const Problem& pb, int k, const double* x, double lo, double hi) {
  while (hi - lo > 1e-3) {
    const double mid = 0.5 * (lo + hi);
    (reach_holds(pb, k, x, mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

bool project_onto_reach(const Problem& pb, std::vector<double>* u) {
  if (pb.reach.empty() || u->size() < static_cast<size_t>(pb.num_controls())) return false;
  double x[3] = {pb.x0, pb.y0, pb.yaw0};
  double v_prev = std::clamp(pb.v_prev, pb.lim.v_min, pb.lim.v_max);
  bool lowered = false;
  for (int k = 0; k < pb.N; ++k) {
    double& v = (*u)[2 * static_cast<size_t>(k)];
    const double w = (*u)[2 * static_cast<size_t>(k) + 1];
    const double v_lo = std::max(pb.lim.v_min, v_prev - pb.lim.decel * pb.dt);
    v = std::max(v_lo, std::min(v, v_prev + pb.lim.accel * pb.dt));  // a lower speed before
    if (v > v_lo && !reach_holds(pb, k, x, v)) {
      v = reach_holds(pb, k, x, v_lo) ? fastest_holding(pb, k, x, v_lo, v) : v_lo;
      lowered = true;
    }
    unicycle_step(v, w, pb.dt, &x[0], &x[1], &x[2]);
    v_prev = v;
  }
  return lowered;
}

bool bound_passively(const PassiveSafetyParams& p, Problem* pb) {
  if (p.braking_point) {
    std::vector<ReachBound> bounds = passive_reach_bounds(p, *pb);
    if (bounds.empty()) return false;
    for (ReachBound& r : bounds) pb->reach.push_back(std::move(r));
    return true;
  }
  const double bound = passive_speed_bound(p, *pb);
  if (!(bound < pb->lim.v_max)) return false;
  pb->v_cap.resize(static_cast<size_t>(std::max(pb->N, 0)), pb->lim.v_max);
  for (double& cap : pb->v_cap) cap = std::min(cap, bound);
  return true;
}

}  // namespace evade::planning
