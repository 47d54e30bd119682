#include "planning/passive_safety.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "planning/fallback.h"

namespace evade::planning {

double passive_safe_speed(double gap_m, double mover_speed_mps, double reaction_s, double decel_mps2) {
  const double s = std::max(0.0, mover_speed_mps);
  const double g = gap_m - s * reaction_s;
  if (!(g > 0.0) || !(decel_mps2 > 0.0)) return 0.0;
  const double p = reaction_s + s / decel_mps2;
  return decel_mps2 * (std::sqrt(p * p + 2.0 * g / decel_mps2) - p);
}

double passive_safe_turn_rate(double gap_m, double mover_speed_mps, double lever_m, double reaction_s,
                              double alpha_radps2) {
  const double s = std::max(0.0, mover_speed_mps), q = std::max(0.0, lever_m);
  const double c = s * reaction_s - gap_m;  // the condition at w = 0, as c <= 0
  if (!(c < 0.0) || !(alpha_radps2 > 0.0)) return 0.0;
  // q / (2 alpha) w^2 + (s / alpha + q reaction_s) w + c <= 0: the positive root
  const double qa = q / (2.0 * alpha_radps2), qb = s / alpha_radps2 + q * reaction_s;
  const double den = qb + std::sqrt(qb * qb - 4.0 * qa * c);
  return den > 0.0 ? -2.0 * c / den : std::numeric_limits<double>::infinity();
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

// A mover of pb as the bounds take it (header): its body now without its
// inflation, where its tracker last measured it (measured_position) and
// its speed.
struct Mover {
  ObstacleTrack body;
  std::optional<ObstacleTrack::Body> measured;
  double speed_mps = 0.0;
};

std::vector<Mover> movers(const PassiveSafetyParams& p, const Problem& pb) {
  std::vector<Mover> out;
  for (const ObstacleTrack& track : pb.obstacles) {
    if (track.field || track.x.empty()) continue;
    double speed = std::max(fastest_predicted_speed(track, pb.dt), track.recent_speed_mps);
    if (track.age_s < p.min_track_age_s)
      speed = std::max(speed, p.unknown_speed_mps);
    else if (speed < p.min_mover_speed_mps)
      continue;
    Mover m{track, std::nullopt, speed};
    remove_inflation(&m.body);
    if (p.measured_position && track.measured) m.measured = *track.measured;
    out.push_back(std::move(m));
  }
  return out;
}

// The footprint rectangle's point nearest the ellipse (x, y, a, b, theta)'s
// centre from pose `start`: its lever arm (rx, ry) from the base centre
// (world frame), its gap to the ellipse (the barrier at that point, d_safe
// 0) and the unit vector from it towards the ellipse (-grad h).
struct EdgeGap {
  double rx = 0.0, ry = 0.0, gap = 0.0, dx = 0.0, dy = 0.0;
};
EdgeGap edge_gap(const Footprint& fp, const double* start, double x, double y, double a, double b, double theta) {
  const double c = std::cos(start[2]), s = std::sin(start[2]);
  const double bx = c * (x - start[0]) + s * (y - start[1]), by = -s * (x - start[0]) + c * (y - start[1]);
  const double px = std::clamp(bx, -0.5 * fp.length, 0.5 * fp.length);
  const double py = std::clamp(by, -0.5 * fp.width, 0.5 * fp.width);
  EdgeGap out;
  out.rx = c * px - s * py;
  out.ry = s * px + c * py;
  const BarrierValue h = barrier(start[0] + out.rx, start[1] + out.ry, x, y, a, b, theta, 0.0);
  const double norm = std::hypot(h.gx, h.gy);
  out.gap = h.h;
  if (norm > 0.0) out.dx = -h.gx / norm, out.dy = -h.gy / norm;
  return out;
}

// The nearer of the mover's body at step 0 and its measured body.
EdgeGap nearest_edge_gap(const Footprint& fp, const double* start, const Mover& m) {
  const ObstacleTrack& o = m.body;
  EdgeGap g = edge_gap(fp, start, o.x[0], o.y[0], o.a[0], o.b[0], o.theta[0]);
  if (m.measured) {
    const ObstacleTrack::Body& b = *m.measured;
    const EdgeGap mg = edge_gap(fp, start, b.x, b.y, b.a, b.b, b.theta);
    if (mg.gap < g.gap) g = mg;
  }
  return g;
}

// The barrier (footprint discs, d_safe 0) between the robot standing at
// pb's start, its heading's cosine c and sine s, and the mover's body of
// step k (orientation's cosine ct and sine st) centred at (x, y).
double h_standing(const Problem& pb, const ObstacleTrack& body, size_t k, double x, double y, double c, double s,
                  double ct, double st) {
  return footprint_stage(pb.x0, pb.y0, c, s, x, y, body.a[k], body.b[k], ct, st, pb.footprint, 0.0).h;
}

// The least h_standing over the horizon, the robot turned by yaw_by,
// against the mover's predicted body (inflation removed), its centre
// followed between the steps at kWaySamples points a step (so that a turn
// that slides a disc along the mover's way gains nothing from where the
// steps fall).
constexpr int kWaySamples = 8;
double least_h_at_rest(const Problem& pb, const ObstacleTrack& body, double yaw_by) {
  const double c = std::cos(pb.yaw0 + yaw_by), s = std::sin(pb.yaw0 + yaw_by);
  double least = std::numeric_limits<double>::infinity();
  const size_t n = body.x.size();
  for (size_t k = 0; k < n; ++k) {
    const double ct = std::cos(body.theta[k]), st = std::sin(body.theta[k]);
    for (int j = 0; j < (k + 1 < n ? kWaySamples : 1); ++j) {
      const double f = static_cast<double>(j) / kWaySamples;
      const double x = k + 1 < n ? body.x[k] + f * (body.x[k + 1] - body.x[k]) : body.x[k];
      const double y = k + 1 < n ? body.y[k] + f * (body.y[k + 1] - body.y[k]) : body.y[k];
      least = std::min(least, h_standing(pb, body, k, x, y, c, s, ct, st));
    }
  }
  return least;
}

// Whether the robot turning on the spot from pb's start the way `side`
// (+1 counter-clockwise), from its measured turn rate at the limits
// (omega_max, alpha) until it has turned by `by` (rad), keeps clear of the
// mover's predicted body (inflation removed) at every step.
bool turn_keeps_clear(const Problem& pb, const ObstacleTrack& body, int side, double by) {
  double yaw = 0.0, omega = std::clamp(pb.omega_prev, -pb.lim.omega_max, pb.lim.omega_max);
  const double dw = pb.lim.alpha * pb.dt;
  const size_t n = std::min(body.x.size(), static_cast<size_t>(pb.N) + 1);
  for (size_t k = 0; k < n; ++k) {
    const double c = std::cos(pb.yaw0 + side * yaw), s = std::sin(pb.yaw0 + side * yaw);
    const double ct = std::cos(body.theta[k]), st = std::sin(body.theta[k]);
    if (!(h_standing(pb, body, k, body.x[k], body.y[k], c, s, ct, st) > 0.0)) return false;
    const double want = side * yaw < by ? side * pb.lim.omega_max : 0.0;
    omega = std::clamp(want, omega - dw, omega + dw);
    yaw += side * omega * pb.dt;
    if (side * yaw > by) yaw = side * by;
  }
  return true;
}

// Whether turning the way `side` (+1 counter-clockwise) is what gets the
// body out of the mover's way in time: its predicted body meets the robot
// standing, the robot standing turned by some angle up to a quarter turn
// that way would not meet it, and the turn there, at the limits, keeps
// clear of it all the way.
bool turn_gets_out_of_its_way(const Problem& pb, const ObstacleTrack& body, int side) {
  if (least_h_at_rest(pb, body, 0.0) > 0.0) return false;
  const double step = pb.lim.omega_max * pb.dt;
  for (double by = step; by <= 0.5 * M_PI; by += step)
    if (least_h_at_rest(pb, body, side * by) > 0.0) return turn_keeps_clear(pb, body, side, by);
  return false;
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
  for (Mover& mover : movers(p, pb)) {
    MoverBound m{std::move(mover.body), pb.lim.v_max, mover.speed_mps};
    double gap = barrier_h_at(front, m.body, 0, start);
    if (mover.measured) nearer_measured(front, *mover.measured, start, &m.body, &gap);
    if (!std::isfinite(gap)) continue;
    m.speed_mps = std::min(pb.lim.v_max, passive_safe_speed(gap, m.mover_speed_mps, p.reaction_s, pb.lim.decel));
    out.push_back(std::move(m));
  }
  return out;
}

TurnBounds passive_turn_bounds(const PassiveSafetyParams& p, const Problem& pb) {
  TurnBounds out{-pb.lim.omega_max, pb.lim.omega_max};
  if (!(pb.footprint.length > 0.0) && !(pb.footprint.width > 0.0)) return out;  // a point swings nothing
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  for (const Mover& m : movers(p, pb)) {
    const EdgeGap g = nearest_edge_gap(pb.footprint, start, m);
    const double q = -g.ry * g.dx + g.rx * g.dy;  // the nearest point's swing towards the body per rad/s
    if (!std::isfinite(g.gap) || !std::isfinite(q) || q == 0.0) continue;
    const double w = passive_safe_turn_rate(g.gap, m.speed_mps, std::fabs(q), p.reaction_s, pb.lim.alpha);
    const int side = q > 0.0 ? 1 : -1;
    if (!(w < pb.lim.omega_max) || turn_gets_out_of_its_way(pb, m.body, side)) continue;
    if (side > 0)
      out.hi = std::min(out.hi, w);
    else
      out.lo = std::max(out.lo, -w);
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

bool bound_turn_passively(const PassiveSafetyParams& p, Problem* pb) {
  const TurnBounds t = passive_turn_bounds(p, *pb);
  if (!(t.lo > -pb->lim.omega_max) && !(t.hi < pb->lim.omega_max)) return false;
  const size_t n = static_cast<size_t>(std::max(pb->N, 1));
  pb->omega_lo.resize(std::max(pb->omega_lo.size(), n), -pb->lim.omega_max);
  pb->omega_hi.resize(std::max(pb->omega_hi.size(), n), pb->lim.omega_max);
  pb->omega_lo[0] = std::max(pb->omega_lo[0], t.lo);
  pb->omega_hi[0] = std::min(pb->omega_hi[0], t.hi);
  return true;
}

}  // namespace evade::planning
