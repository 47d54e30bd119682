#include "planning/passive_safety.h"

#include <algorithm>
#include <array>
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
                              double alpha_radps2, double residual_mps) {
  const double s = std::max(0.0, mover_speed_mps), q = std::max(0.0, lever_m);
  if (!(q > 0.0)) return std::numeric_limits<double>::infinity();  // the point does not swing
  const double slow = std::max(0.0, residual_mps) / q;             // the point comes at most at residual_mps
  if (!(alpha_radps2 > 0.0)) return slow;
  // above slow: on for reaction_s, then down to slow at alpha, as the
  // condition q / (2 alpha) w^2 + (s / alpha + q reaction_s) w + c <= 0
  const double c = s * reaction_s - gap_m - s * slow / alpha_radps2 - q * slow * slow / (2.0 * alpha_radps2);
  if (!(c < 0.0)) return slow;
  const double qa = q / (2.0 * alpha_radps2), qb = s / alpha_radps2 + q * reaction_s;
  return std::max(slow, -2.0 * c / (qb + std::sqrt(qb * qb - 4.0 * qa * c)));
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

// The directions (robot frame, unit) a contact at the rectangle's point
// (px, py) can have, as the metrics take it (between the closest points):
// an edge's outward normal; at a corner, kCornerDirections between its
// two edges' normals; none inside the rectangle (half-length hl,
// half-width hw).
constexpr int kCornerDirections = 7;
std::vector<std::array<double, 2>> contact_directions(double px, double py, double hl, double hw) {
  const double nx = px >= hl ? 1.0 : (px <= -hl ? -1.0 : 0.0);
  const double ny = py >= hw ? 1.0 : (py <= -hw ? -1.0 : 0.0);
  if (nx == 0.0 || ny == 0.0) {
    if (nx == 0.0 && ny == 0.0) return {};
    return {{nx, ny}};
  }
  // cosine and sine of the kCornerDirections angles over a quarter turn,
  // computed once
  static const std::array<std::array<double, 2>, kCornerDirections> quarter = [] {
    std::array<std::array<double, 2>, kCornerDirections> q{};
    for (int j = 0; j < kCornerDirections; ++j) {
      const double f = 0.5 * M_PI * j / (kCornerDirections - 1);
      q[static_cast<size_t>(j)] = {std::cos(f), std::sin(f)};
    }
    return q;
  }();
  std::vector<std::array<double, 2>> out;
  out.reserve(kCornerDirections);
  for (const auto& cs : quarter) out.push_back({nx * cs[0], ny * cs[1]});
  return out;
}

// The footprint rectangle of a robot at (x0, y0) whose heading has cosine
// c and sine s, and the change between the world and the robot's frame
// (x along the heading).
struct RectangleFrame {
  double x0, y0, c, s, hl, hw;
  RectangleFrame(const Footprint& fp, double x0_, double y0_, double c_, double s_)
      : x0(x0_), y0(y0_), c(c_), s(s_), hl(0.5 * fp.length), hw(0.5 * fp.width) {}
  // The world point (x, y) in the robot's frame.
  std::array<double, 2> to_robot(double x, double y) const {
    return {c * (x - x0) + s * (y - y0), -s * (x - x0) + c * (y - y0)};
  }
  // The robot-frame point pt in the world.
  std::array<double, 2> to_world(const std::array<double, 2>& pt) const {
    return {x0 + c * pt[0] - s * pt[1], y0 + s * pt[0] + c * pt[1]};
  }
  // The rectangle's point nearest the world point (x, y).
  std::array<double, 2> nearest_to(double x, double y) const {
    const std::array<double, 2> b = to_robot(x, y);
    return {std::clamp(b[0], -hl, hl), std::clamp(b[1], -hw, hw)};
  }
  // Corner i mod 4, counter-clockwise from front left.
  std::array<double, 2> corner(int i) const {
    const int j = i % 4;
    return {j == 0 || j == 3 ? hl : -hl, j < 2 ? hw : -hw};
  }
};

// The mover's body (centre (ox, oy), robot frame, from the point) as seen
// from a point of the rectangle: its gap there (m) and its extent towards
// the point (the distance to its centre less the gap).
struct SeenFrom {
  double gap = 0.0, ox = 0.0, oy = 0.0, extent = 0.0;
};

// The rectangle r's point pt (robot frame) and the ellipse (x, y, a, b,
// theta).
SeenFrom seen_from(const RectangleFrame& r, const std::array<double, 2>& pt, double x, double y, double a, double b,
                   double theta) {
  const std::array<double, 2> at = r.to_world(pt), centre = r.to_robot(x, y);
  SeenFrom out;
  out.gap = barrier(at[0], at[1], x, y, a, b, theta, 0.0).h;
  out.ox = centre[0] - pt[0];
  out.oy = centre[1] - pt[1];
  out.extent = std::max(0.0, std::hypot(out.ox, out.oy) - out.gap);
  return out;
}

// The footprint rectangle's points the turn bound checks against an
// ellipse centred at the world point (x, y): the point nearest that
// centre, the corners, and kEdgeSteps - 1 points evenly
// between the corners on each edge. A mover passing along a side reaches
// the far corner before the turn stops, so the nearest point alone is not
// enough.
constexpr int kEdgeSteps = 4;
std::vector<std::array<double, 2>> checked_points(const RectangleFrame& r, double x, double y) {
  std::vector<std::array<double, 2>> out{r.nearest_to(x, y)};
  for (int e = 0; e < 4; ++e) {
    const std::array<double, 2> from = r.corner(e), to = r.corner(e + 1);
    for (int j = 0; j < kEdgeSteps; ++j) {
      const double f = static_cast<double>(j) / kEdgeSteps;
      out.push_back({from[0] + f * (to[0] - from[0]), from[1] + f * (to[1] - from[1])});
    }
  }
  return out;
}

// The least turn rate of turn_bound each way ([0] clockwise, [1]
// counter-clockwise; infinity where nothing binds) over the checked points
// of pb's footprint and their contact directions against the ellipse
// (x, y, a, b, theta) of a mover going at speed_mps. To touch point c from
// direction n, the body's centre has to get to c + extent n: from where
// it is, the gap when n points at it, farther round the corner.
void bound_each_way(const PassiveSafetyParams& p, const Problem& pb, double speed_mps, double x, double y, double a,
                    double b, double theta, double* w_each) {
  const RectangleFrame r(pb.footprint, pb.x0, pb.y0, std::cos(pb.yaw0), std::sin(pb.yaw0));
  const auto bound = [&](int i, double q, double way) {
    if (q > 0.0)
      w_each[i] = std::min(w_each[i],
                           passive_safe_turn_rate(way, speed_mps, q, p.reaction_s, pb.lim.alpha, p.turn_residual_mps));
  };
  for (const auto& pt : checked_points(r, x, y)) {
    const SeenFrom o = seen_from(r, pt, x, y, a, b, theta);
    if (!std::isfinite(o.gap)) continue;
    const auto dirs = contact_directions(pt[0], pt[1], r.hl, r.hw);
    for (int i = 0; i < 2; ++i) {
      const double side = i == 0 ? -1.0 : 1.0, vx = -side * pt[1], vy = side * pt[0];  // the swing per rad/s
      if (dirs.empty()) bound(i, std::hypot(vx, vy), o.gap);                           // inside: any direction
      for (const auto& n : dirs) {
        const double way = o.gap > 0.0 ? std::hypot(o.ox - o.extent * n[0], o.oy - o.extent * n[1]) : o.gap;
        bound(i, vx * n[0] + vy * n[1], way);
      }
    }
  }
}

// The gap between the footprint rectangle of the robot standing at pb's
// start, its heading's cosine c and sine s, and the mover's body of step
// k (orientation's cosine ct and sine st) centred at (x, y): the least
// barrier (d_safe 0) at the rectangle's point nearest the body's centre
// and at its corners (exact for a round body; the rectangle, not the
// covering discs, which stick out at its sides, so a robot a few
// centimetres clear of a lane is clear here too).
double h_standing(const Problem& pb, const ObstacleTrack& body, size_t k, double x, double y, double c, double s,
                  double ct, double st) {
  const RectangleFrame r(pb.footprint, pb.x0, pb.y0, c, s);
  const std::array<double, 2> pts[5] = {r.nearest_to(x, y), r.corner(0), r.corner(1), r.corner(2), r.corner(3)};
  double least = std::numeric_limits<double>::infinity();
  for (const auto& pt : pts) {
    const std::array<double, 2> at = r.to_world(pt);
    least = std::min(least, barrier_cs(at[0], at[1], x, y, body.a[k], body.b[k], ct, st, 0.0).h);
  }
  return least;
}

// The mover's body centre a fraction f of the way from step k to k + 1
// (step k's own at the last step).
void way_point(const ObstacleTrack& body, size_t k, double f, double* x, double* y) {
  const bool last = k + 1 >= body.x.size();
  *x = last ? body.x[k] : body.x[k] + f * (body.x[k + 1] - body.x[k]);
  *y = last ? body.y[k] : body.y[k] + f * (body.y[k + 1] - body.y[k]);
}

// The least h_standing over the horizon, the robot turned by yaw_by,
// against the mover's predicted body (inflation removed), its centre
// followed between the steps at kWaySamples points a step (so that a turn
// that slides the body along the mover's way, or a mover that passes a
// corner between two steps, gains nothing from where the steps fall).
constexpr int kWaySamples = 8;
double least_h_at_rest(const Problem& pb, const ObstacleTrack& body, double yaw_by) {
  const double c = std::cos(pb.yaw0 + yaw_by), s = std::sin(pb.yaw0 + yaw_by);
  double least = std::numeric_limits<double>::infinity();
  const size_t n = body.x.size();
  for (size_t k = 0; k < n; ++k) {
    const double ct = std::cos(body.theta[k]), st = std::sin(body.theta[k]);
    for (int j = 0; j < (k + 1 < n ? kWaySamples : 1); ++j) {
      double x = 0.0, y = 0.0;
      way_point(body, k, static_cast<double>(j) / kWaySamples, &x, &y);
      least = std::min(least, h_standing(pb, body, k, x, y, c, s, ct, st));
    }
  }
  return least;
}

// Whether the robot turning on the spot from pb's start the way `side`
// (+1 counter-clockwise), from its measured turn rate at the limits
// (omega_max, alpha) until it has turned by `by` (rad), keeps clear of the
// mover's predicted body (inflation removed) all the way (kWaySamples
// points a step, the turn between them too).
bool turn_keeps_clear(const Problem& pb, const ObstacleTrack& body, int side, double by) {
  // yaw and omega: turned and turning that way (negative: the other way)
  double yaw = 0.0, omega = side * std::clamp(pb.omega_prev, -pb.lim.omega_max, pb.lim.omega_max);
  const double dw = pb.lim.alpha * pb.dt;
  const size_t n = std::min(body.x.size(), static_cast<size_t>(pb.N) + 1);
  for (size_t k = 0; k < n; ++k) {
    omega = std::clamp(yaw < by ? pb.lim.omega_max : 0.0, omega - dw, omega + dw);
    const double next = std::min(by, yaw + omega * pb.dt);
    const double ct = std::cos(body.theta[k]), st = std::sin(body.theta[k]);
    for (int j = 0; j < (k + 1 < n ? kWaySamples : 1); ++j) {
      const double f = static_cast<double>(j) / kWaySamples, turned = pb.yaw0 + side * (yaw + f * (next - yaw));
      double x = 0.0, y = 0.0;
      way_point(body, k, f, &x, &y);
      if (!(h_standing(pb, body, k, x, y, std::cos(turned), std::sin(turned), ct, st) > 0.0)) return false;
    }
    yaw = next;
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
  for (const Mover& m : movers(p, pb)) {
    const double inf = std::numeric_limits<double>::infinity();
    double w[2] = {inf, inf};
    const ObstacleTrack& o = m.body;
    bound_each_way(p, pb, m.speed_mps, o.x[0], o.y[0], o.a[0], o.b[0], o.theta[0], w);
    if (m.measured) {
      const ObstacleTrack::Body& mb = *m.measured;
      bound_each_way(p, pb, m.speed_mps, mb.x, mb.y, mb.a, mb.b, mb.theta, w);
    }
    if (w[0] < pb.lim.omega_max && !turn_gets_out_of_its_way(pb, o, -1)) out.lo = std::max(out.lo, -w[0]);
    if (w[1] < pb.lim.omega_max && !turn_gets_out_of_its_way(pb, o, 1)) out.hi = std::min(out.hi, w[1]);
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
