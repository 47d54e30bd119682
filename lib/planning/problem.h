// The MPC problem of the paper (Sec. III-A, Eq. "optimization-formulation"),
// written once and shared by the Ceres solver and the IPOPT peer so that both
// solve the same NLP.
//
//   min_u  sum_{k=0}^{N-1} ||x_k - x_k^d||_Q + ||u_k||_R + ||u_{k+1} - u_k||_S
//          + ||x_N - x_N^d||_P                    (quadratic forms, yaw error wrapped)
//   s.t.   x_{k+1} = x_k + [cos th, 0; sin th, 0; 0, 1] u_k dt   (unicycle model)
//          v_min <= v_k <= v_max, |omega_k| <= omega_max        (parameter bounds)
//          -decel dt <= v_k - v_{k-1} <= accel dt, |omega_k - omega_{k-1}| <= alpha dt
//                 (k = 0 uses the measured v, omega)
//          h_i(X_{k+1}) >= decay_i h_i(X_k), k = 0..N-1, every obstacle i
//
// with h = ||p - x_ob|| - l(delta) - d_safe, l the paper's line-ellipse
// distance. decay = 1 - gamma gives the discrete (D-)CBF condition
// Delta h >= -gamma h; decay = 0 gives the plain distance constraint h >= 0.
// The robot is its footprint's covering discs (Footprint): h is the
// smallest over the discs of that distance from the disc's centre, less the
// disc's radius, so d_safe is the margin beyond the body; it depends on the
// heading as well as the position.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <type_traits>
#include <vector>

#include "config/fields.h"

namespace evade::planning {

// `planner.weights`: the diagonal Q, P, R, S of the cost; the defaults are
// config/robot.yaml's.
struct Weights {
  double q_xy = 10.0, q_yaw = 1.0;  // stage state weights (Q diagonal)
  double p_xy = 20.0, p_yaw = 2.0;  // terminal state weights (P diagonal)
  double r_v = 0.1, r_omega = 0.1;  // control weights (R diagonal)
  double s_v = 1.0, s_omega = 1.0;  // control-rate weights (S diagonal)

  template <class V>
  void fields(V& v) {
    const config::Range r = config::between(0, 1e6);
    v.field("q_xy", q_xy, r);
    v.field("q_yaw", q_yaw, r);
    v.field("p_xy", p_xy, r);
    v.field("p_yaw", p_yaw, r);
    v.field("r_v", r_v, r);
    v.field("r_omega", r_omega, r);
    v.field("s_v", s_v, r);
    v.field("s_omega", s_omega, r);
  }
};

struct Limits {
  double v_min = 0, v_max = 0;  // m/s
  double omega_max = 0;         // rad/s, symmetric
  double accel = 0, decel = 0;  // m/s^2, both positive
  double alpha = 0;             // rad/s^2
};

class StaticField;  // static_field.h

// One obstacle over the plan's steps k = 0..N (already aligned to the plan's
// time, already inflated), and the kind of constraint it carries. With
// `field` set it is the static structure's distance field instead of an
// ellipse (static_field.h; the ellipse arrays hold the robot's start).
struct ObstacleTrack {
  int64_t id = 0;
  std::vector<double> x, y, a, b, theta;  // N + 1 each
  std::vector<double> sigma;              // N + 1: the inflation in a and b (predictions), else empty
  double decay = 0.0;                     // 1 - gamma (CBF) or 0 (distance)
  double age_s = 0.0;                     // since the planner first saw the track (solve_elastic)
  double still_s = 0.0;                   // since its centre (step 0) last moved still_radius_m (hold_settled)
  double recent_speed_mps = 0.0;          // the fastest its tracker reported lately (passive_safety.speed_memory_s)
  struct Body {
    double x = 0.0, y = 0.0, a = 0.0, b = 0.0, theta = 0.0;
  };
  std::optional<Body> measured;  // its tracker's last measurement (passive_safety.measured_position), no inflation
  std::shared_ptr<const StaticField> field;  // static structure (static_field.h), else null
};

// How fast an obstacle's predicted centre goes, from its x, y over steps of
// dt. The fastest step (m/s; non-finite steps skipped; 0 without two steps or
// without dt > 0).
double fastest_predicted_speed(const ObstacleTrack& o, double dt);
// The mean over steps 0..N: the length of the centres' path over N dt (m/s;
// 0 without N steps or with a non-finite centre).
double mean_predicted_speed(const ObstacleTrack& o, int N, double dt);

// The robot's body as discs along its heading: centres `offsets` (m,
// forward of the base centre), each of `radius`. The default, one disc of
// radius 0 at the centre, is the paper's point robot.
struct Footprint {
  std::vector<double> offsets{0.0};
  double radius = 0.0;
  double length = 0.0, width = 0.0;  // the rectangle the discs cover (covering; 0 x 0: a point)
  // n discs covering a length x width rectangle centred on the base: the
  // length cut in n equal slices, each disc the circle round its slice.
  static Footprint covering(double length, double width, int n) {
    Footprint f;
    f.offsets.clear();
    const double slice = length / n;
    for (int i = 0; i < n; ++i) f.offsets.push_back(-0.5 * length + slice * (i + 0.5));
    f.radius = std::hypot(0.5 * slice, 0.5 * width);
    f.length = length;
    f.width = width;
    return f;
  }
};

// Passive safety against one mover (passive_safety.h): for k = 0..N-1
//   h(B_k) - radius_m - speed_mps (reaction_s + v_k / decel_mps2) + allowance_m[k] >= 0,
// B_k = p_k + (offset_m + v_k reaction_s + v_k^2 / (2 decel_mps2)) (cos th_k, sin th_k)
// the centre of the footprint's front disc where the robot, at X_k going
// v_k, stands when it goes on for reaction_s and then brakes; h that
// point's barrier against the mover's body now (d_safe 0). So the robot
// would stand before the mover, going at speed_mps in any direction from
// where it is now, could reach the front disc. allowance_m[k] is what
// braking from the measured controls misses of it (0 where braking meets
// it), so braking always meets it. v_k >= 0 (the planner never reverses).
struct ReachBound {
  int64_t id = 0;                                // the obstacle it was made from
  double x = 0, y = 0, a = 0, b = 0, theta = 0;  // the mover's body now
  double speed_mps = 0, reaction_s = 0, decel_mps2 = 1;
  double offset_m = 0, radius_m = 0;  // the front disc
  std::vector<double> allowance_m;    // N
};

struct Problem {
  int N = 0;
  double dt = 0;
  double x0 = 0, y0 = 0, yaw0 = 0;            // start state (fixed)
  double v_prev = 0, omega_prev = 0;          // measured controls, for the rate limits at k = 0
  std::vector<double> ref_x, ref_y, ref_yaw;  // N + 1, yaw unwrapped near yaw0
  Weights w;
  Limits lim;
  double d_safe = 0;  // margin beyond the footprint
  Footprint footprint;
  std::vector<ObstacleTrack> obstacles;
  // Optional per-constraint relaxation added to g_j (empty = none): used
  // only for an infeasible problem, see CeresMpcSolver::solve_elastic and
  // fallback.h.
  std::vector<double> relax;
  // The fallback's problem (fallback.h): each barrier link charges the
  // robot only for its own motion, h(X_k+1, O_k+1) >= decay' h(X_k, O_k+1)
  // with decay' = the obstacle's decay where that h is positive, 1 where it
  // is not (the robot may close on an obstacle by (1 - decay) h a step, and
  // not at all once within d_safe; the obstacle's own approach is not the
  // plan's doing)...
  bool own_motion = false;
  // ...and the depth within d_safe costs penetration_weight (1/m^2) squared,
  // summed over obstacles and steps 1..N (0: no such term).
  double penetration_weight = 0.0;
  // Optional per-step upper bounds on v_k below lim.v_max (empty = none):
  // mode evade near hidden regions (occlusion_speed.h).
  std::vector<double> v_cap;
  // Optional per-step bounds on omega_k within [-omega_max, omega_max]
  // (empty = none; a step past a vector's end is unbounded): mode evade's
  // passive turn bound (passive_safety.h), omega_lo <= 0 <= omega_hi.
  std::vector<double> omega_lo, omega_hi;
  // Optional passive-safety bounds, one per mover (ReachBound, above).
  std::vector<ReachBound> reach;

  int num_controls() const { return 2 * N; }
  // 4 rate constraints per step (v up, v down, omega up, omega down), then N
  // barrier constraints per obstacle, then N per reach bound.
  int num_rate_constraints() const { return 4 * N; }
  int num_barrier_constraints() const { return static_cast<int>(obstacles.size()) * N; }
  int num_constraints() const { return 4 * N + num_barrier_constraints() + static_cast<int>(reach.size()) * N; }
};

// [*lo, *hi], the turn rates step k may take otherwise, narrowed by
// pb.omega_lo/omega_hi where they bound step k; never crossed (the upper
// bound first, as v_cap, so a step that cannot slow to it slows as fast
// as [*lo, *hi] allows).
inline void narrow_to_turn_bounds(const Problem& pb, int k, double* lo, double* hi) {
  const size_t i = static_cast<size_t>(k);
  if (i < pb.omega_hi.size()) *hi = std::max(*lo, std::min(*hi, pb.omega_hi[i]));
  if (i < pb.omega_lo.size()) *lo = std::min(*hi, std::max(*lo, pb.omega_lo[i]));
}

// A bound on v_k (pb.v_cap) raised to what braking from the measured speed
// at the deceleration limit can reach by step k (never above v_max): a step
// cannot slow to a bound below that yet.
inline double cap_braking_can_meet(const Problem& pb, int k, double cap) {
  return std::max(cap, std::min(pb.lim.v_max, pb.v_prev - pb.lim.decel * pb.dt * (k + 1)));
}

inline double wrap_angle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// ---- the line-ellipse distance and the barrier ----
//
// d = p - c, e1 = (cos theta, sin theta) (major axis), e2 = (-sin, cos).
// With cos(delta) = d.e1/|d|, sin(delta) = d.e2/|d| the paper's
//   l = sqrt(a^2 b^2 (1 + tan^2 delta) / (b^2 + a^2 tan^2 delta))
// equals a b / sqrt(b^2 cos^2 delta + a^2 sin^2 delta) = a b |d| / s with
// s = sqrt(b^2 (d.e1)^2 + a^2 (d.e2)^2); this form has no tan singularity at
// delta = 90 deg. h = |d| - l - d_safe.
struct BarrierValue {
  double h = 0;
  double gx = 0, gy = 0;             // dh/dp
  double hxx = 0, hxy = 0, hyy = 0;  // d2h/dp2 (used by the IPOPT peer)
  // of the footprint's h (footprint_barrier): dh/dyaw, and the second
  // derivatives with yaw (0 for a point)
  double gth = 0;
  double hxt = 0, hyt = 0, htt = 0;
};

// Below this centre distance (m) the direction to the robot is undefined;
// the value is clamped so that derivatives stay finite.
inline constexpr double kMinCentreDistance = 1e-6;

// The first stage of the barrier: the offset d from the centre (clamped
// away from it), |d|, d.e1, d.e2, s, and h. The derivatives follow from it
// (barrier_derivatives); a caller that needs only h stops here.
struct BarrierStage {
  double dx = 0, dy = 0, r = 0, p = 0, q = 0, s = 0, h = 0;
};

// The ellipse's orientation as its cosine c and sine s_ (a caller that
// evaluates the same ellipse many times computes them once).
inline BarrierStage barrier_stage(double px, double py, double cx, double cy, double a, double b, double c, double s_,
                                  double d_safe) {
  BarrierStage t;
  t.dx = px - cx;
  t.dy = py - cy;
  t.r = std::sqrt(t.dx * t.dx + t.dy * t.dy);  // planner coordinates are bounded: no overflow to guard against
  if (t.r < kMinCentreDistance) {
    // At the centre: any direction; use the major axis so the gradient points out.
    t.dx = kMinCentreDistance * c;
    t.dy = kMinCentreDistance * s_;
    t.r = kMinCentreDistance;
  }
  t.p = t.dx * c + t.dy * s_;   // d.e1
  t.q = -t.dx * s_ + t.dy * c;  // d.e2
  const double a2 = a * a, b2 = b * b;
  t.s = std::sqrt(b2 * t.p * t.p + a2 * t.q * t.q);
  const double l = a * b * t.r / t.s;
  t.h = t.r - l - d_safe;
  return t;
}

// h and its derivatives in the position from the first stage.
inline BarrierValue barrier_derivatives(const BarrierStage& t, double a, double b, double c, double s_,
                                        bool want_hessian) {
  BarrierValue out;
  const double dx = t.dx, dy = t.dy, r = t.r, p = t.p, q = t.q, s = t.s;
  const double a2 = a * a, b2 = b * b;
  const double ab = a * b;
  out.h = t.h;
  // gradients in the world frame
  const double rx = dx / r, ry = dy / r;             // grad r
  const double sx = (b2 * p * c - a2 * q * s_) / s;  // grad s
  const double sy = (b2 * p * s_ + a2 * q * c) / s;
  const double lx = ab * (rx * s - r * sx) / (s * s);  // grad l
  const double ly = ab * (ry * s - r * sy) / (s * s);
  out.gx = rx - lx;
  out.gy = ry - ly;
  if (want_hessian) {
    // grad^2 r = (I - d d^T / r^2) / r
    const double rxx = (1 - rx * rx) / r, rxy = -rx * ry / r, ryy = (1 - ry * ry) / r;
    // grad^2 s = (b^2 e1 e1^T + a^2 e2 e2^T)/s - grad s grad s^T / s
    const double sxx = (b2 * c * c + a2 * s_ * s_) / s - sx * sx / s;
    const double sxy = (b2 * c * s_ - a2 * s_ * c) / s - sx * sy / s;
    const double syy = (b2 * s_ * s_ + a2 * c * c) / s - sy * sy / s;
    // l = ab r / s: grad^2 l = ab [H_r / s - (g_r g_s^T + g_s g_r^T)/s^2 - r H_s / s^2 + 2 r g_s g_s^T / s^3]
    const double s2 = s * s, s3 = s2 * s;
    const double lxx = ab * (rxx / s - 2 * rx * sx / s2 - r * sxx / s2 + 2 * r * sx * sx / s3);
    const double lxy = ab * (rxy / s - (rx * sy + sx * ry) / s2 - r * sxy / s2 + 2 * r * sx * sy / s3);
    const double lyy = ab * (ryy / s - 2 * ry * sy / s2 - r * syy / s2 + 2 * r * sy * sy / s3);
    out.hxx = rxx - lxx;
    out.hxy = rxy - lxy;
    out.hyy = ryy - lyy;
  }
  return out;
}

inline BarrierValue barrier_cs(double px, double py, double cx, double cy, double a, double b, double c, double s_,
                               double d_safe, bool want_hessian = false) {
  return barrier_derivatives(barrier_stage(px, py, cx, cy, a, b, c, s_, d_safe), a, b, c, s_, want_hessian);
}

inline BarrierValue barrier(double px, double py, double cx, double cy, double a, double b, double theta, double d_safe,
                            bool want_hessian = false) {
  return barrier_cs(px, py, cx, cy, a, b, std::cos(theta), std::sin(theta), d_safe, want_hessian);
}

inline BarrierValue barrier_at(const ObstacleTrack& o, int k, double px, double py, double d_safe,
                               bool want_hessian = false) {
  return barrier(px, py, o.x[k], o.y[k], o.a[k], o.b[k], o.theta[k], d_safe, want_hessian);
}

// Whether the footprint is the paper's point robot (its h does not depend
// on the heading).
inline bool is_point(const Footprint& fp) { return fp.offsets.size() == 1 && fp.offsets[0] == 0.0; }

// The footprint's nearest disc at pose (px, py) with heading cosine cyaw
// and sine syaw against an ellipse (orientation as cosine c and sine s_):
// the smallest over the discs of the barrier of the disc's centre less its
// radius (h), that disc's first stage and its offset.
struct FootprintStage {
  BarrierStage disc;
  double h = 0.0, off = 0.0;
};

inline FootprintStage footprint_stage(double px, double py, double cyaw, double syaw, double cx, double cy, double a,
                                      double b, double c, double s_, const Footprint& fp, double d_safe) {
  FootprintStage best;
  bool first = true;
  for (double off : fp.offsets) {
    const BarrierStage t = barrier_stage(px + off * cyaw, py + off * syaw, cx, cy, a, b, c, s_, d_safe);
    const double h = t.h - fp.radius;
    if (first || h < best.h) best.disc = t, best.h = h, best.off = off, first = false;
  }
  return best;
}

// The footprint's h and its derivatives in (x, y, yaw): those of the
// nearest disc (h is a minimum of smooth functions: where two discs tie,
// one side's derivatives).
inline BarrierValue footprint_derivatives(const FootprintStage& t, double cyaw, double syaw, double a, double b,
                                          double c, double s_, bool want_hessian = false) {
  BarrierValue out = barrier_derivatives(t.disc, a, b, c, s_, want_hessian);
  out.h = t.h;
  if (t.off != 0.0) {
    // the disc's centre moves with yaw by t = off (-sin, cos), t' = -off (cos, sin)
    const double tx = -t.off * syaw, ty = t.off * cyaw;
    out.gth = out.gx * tx + out.gy * ty;
    if (want_hessian) {
      out.hxt = out.hxx * tx + out.hxy * ty;
      out.hyt = out.hxy * tx + out.hyy * ty;
      out.htt = tx * out.hxt + ty * out.hyt + out.gx * (-t.off * cyaw) + out.gy * (-t.off * syaw);
    }
  }
  return out;
}

// Both: h alone unless want_derivatives.
inline BarrierValue footprint_barrier_trig(double px, double py, double cyaw, double syaw, double cx, double cy,
                                           double a, double b, double c, double s_, const Footprint& fp, double d_safe,
                                           bool want_derivatives, bool want_hessian = false) {
  const FootprintStage t = footprint_stage(px, py, cyaw, syaw, cx, cy, a, b, c, s_, fp, d_safe);
  if (want_derivatives) return footprint_derivatives(t, cyaw, syaw, a, b, c, s_, want_hessian);
  BarrierValue out;
  out.h = t.h;
  return out;
}

// The same at heading yaw.
inline BarrierValue footprint_barrier_cs(double px, double py, double yaw, double cx, double cy, double a, double b,
                                         double c, double s_, const Footprint& fp, double d_safe,
                                         bool want_hessian = false) {
  const bool point = is_point(fp);
  const double cyaw = point ? 1.0 : std::cos(yaw), syaw = point ? 0.0 : std::sin(yaw);
  return footprint_barrier_trig(px, py, cyaw, syaw, cx, cy, a, b, c, s_, fp, d_safe, true, want_hessian);
}

// The footprint's h against a static distance field (static_field.cpp;
// second derivatives 0).
BarrierValue static_field_barrier(const StaticField& f, double px, double py, double yaw, const Footprint& fp);

// The footprint's h of obstacle o at its step k for a state (x, y, yaw).
inline BarrierValue barrier_at(const Problem& pb, const ObstacleTrack& o, int k, const double* state,
                               bool want_hessian = false) {
  if (o.field) return static_field_barrier(*o.field, state[0], state[1], state[2], pb.footprint);
  return footprint_barrier_cs(state[0], state[1], state[2], o.x[k], o.y[k], o.a[k], o.b[k], std::cos(o.theta[k]),
                              std::sin(o.theta[k]), pb.footprint, pb.d_safe, want_hessian);
}

// ---- the model, generic in the scalar type (double or ceres::Jet) ----

// One step of rollout's model in double, for controllers that choose each
// step's controls from the pose they have reached: the pose after driving
// (v, w) for dt from (x, y, yaw).
inline void unicycle_step(double v, double w, double dt, double* x, double* y, double* yaw) {
  *x += v * std::cos(*yaw) * dt;
  *y += v * std::sin(*yaw) * dt;
  *yaw += w * dt;
}

// states: 3 (N + 1) values x, y, yaw per step; u: 2 N values v, omega per step.
// cos_th, sin_th (N each, optional): the cosine and sine of the heading at
// each step k < N, as used (the solver's sensitivities need them too).
template <class T>
void rollout(const Problem& pb, const T* u, T* states, T* cos_th = nullptr, T* sin_th = nullptr) {
  using std::cos;
  using std::sin;
  states[0] = T(pb.x0);
  states[1] = T(pb.y0);
  states[2] = T(pb.yaw0);
  for (int k = 0; k < pb.N; ++k) {
    const T* xk = states + 3 * k;
    T* xn = states + 3 * (k + 1);
    const T& v = u[2 * k];
    const T& w = u[2 * k + 1];
    const T c = cos(xk[2]), s = sin(xk[2]);
    if (cos_th) cos_th[k] = c;
    if (sin_th) sin_th[k] = s;
    xn[0] = xk[0] + v * c * pb.dt;
    xn[1] = xk[1] + v * s * pb.dt;
    xn[2] = xk[2] + w * pb.dt;
  }
}

// Lifts a barrier value computed in double back into the scalar type T by
// the chain rule (h depends on the position only): for double this is h,
// for a Jet the derivative part is gx * px.v + gy * py.v.
inline double lift_barrier(const BarrierValue& b, double, double, double) { return b.h; }
template <class J>
J lift_barrier(const BarrierValue& b, const J& px, const J& py, const J& yaw) {
  J out;
  out.a = b.h;
  out.v = b.gx * px.v + b.gy * py.v + b.gth * yaw.v;
  return out;
}
inline double value_of(double x) { return x; }
template <class J>
double value_of(const J& x) {
  return x.a;
}

// h alone of obstacle o at its step k for a state (x, y, yaw) whose
// heading's cosine and sine are cyaw and syaw (1 and 0 for a point robot;
// unused for the static field).
inline double barrier_h_trig(const Problem& pb, const ObstacleTrack& o, int k, const double* state, double cyaw,
                             double syaw) {
  if (o.field) return static_field_barrier(*o.field, state[0], state[1], state[2], pb.footprint).h;
  return footprint_stage(state[0], state[1], cyaw, syaw, o.x[k], o.y[k], o.a[k], o.b[k], std::cos(o.theta[k]),
                         std::sin(o.theta[k]), pb.footprint, pb.d_safe)
      .h;
}

// The same with the heading's trig computed here: barrier_at's h without
// its derivatives.
inline double barrier_h_at(const Problem& pb, const ObstacleTrack& o, int k, const double* state) {
  const bool trig = !o.field && !is_point(pb.footprint);
  return barrier_h_trig(pb, o, k, state, trig ? std::cos(state[2]) : 1.0, trig ? std::sin(state[2]) : 0.0);
}

// The barrier of constraint(): for double its value alone (lift_barrier
// uses no more), for a Jet with its derivatives.
template <class T>
BarrierValue constraint_barrier(const Problem& pb, const ObstacleTrack& o, int k, const double* state) {
  if constexpr (std::is_same_v<T, double>) {
    BarrierValue b;
    b.h = barrier_h_at(pb, o, k, state);
    return b;
  } else {
    return barrier_at(pb, o, k, state);
  }
}

// Reach bound r's constraint at step k for the state (x, y, th) and speed v:
// its value g and, with want_derivatives, dg/dx, dg/dy, dg/dth, dg/dv.
struct ReachValue {
  double g = 0, gx = 0, gy = 0, gth = 0, gv = 0;
};
// The same with the heading's cosine c and sine s known.
inline ReachValue reach_value_cs(const ReachBound& r, int k, double x, double y, double c, double s, double v,
                                 bool want_derivatives) {
  const double len = r.offset_m + v * r.reaction_s + v * v / (2.0 * r.decel_mps2);
  const double ct = std::cos(r.theta), st = std::sin(r.theta);
  const BarrierStage t = barrier_stage(x + len * c, y + len * s, r.x, r.y, r.a, r.b, ct, st, 0.0);
  ReachValue out;
  out.g = t.h - r.radius_m - r.speed_mps * (r.reaction_s + v / r.decel_mps2) + r.allowance_m[static_cast<size_t>(k)];
  if (!want_derivatives) return out;
  const BarrierValue b = barrier_derivatives(t, r.a, r.b, ct, st, false);
  const double along = b.gx * c + b.gy * s;  // dh/dlen
  out.gx = b.gx;
  out.gy = b.gy;
  out.gth = len * (-b.gx * s + b.gy * c);
  out.gv = along * (r.reaction_s + v / r.decel_mps2) - r.speed_mps / r.decel_mps2;
  return out;
}
inline ReachValue reach_value(const ReachBound& r, int k, double x, double y, double th, double v,
                              bool want_derivatives) {
  return reach_value_cs(r, k, x, y, std::cos(th), std::sin(th), v, want_derivatives);
}
inline double lift_reach(const ReachValue& r, double, double, double, double) { return r.g; }
template <class J>
J lift_reach(const ReachValue& r, const J& x, const J& y, const J& th, const J& v) {
  J out;
  out.a = r.g;
  out.v = r.gx * x.v + r.gy * y.v + r.gth * th.v + r.gv * v.v;
  return out;
}

// Constraint j (>= 0 when satisfied), see Problem::num_constraints for the layout.
template <class T>
T constraint(const Problem& pb, const T* states, const T* u, int j) {
  if (j < pb.num_rate_constraints()) {
    const int k = j / 4, which = j % 4;
    const bool is_v = which < 2;
    const T& now = u[2 * k + (is_v ? 0 : 1)];
    const T prev = k == 0 ? T(is_v ? pb.v_prev : pb.omega_prev) : u[2 * (k - 1) + (is_v ? 0 : 1)];
    const double up = (is_v ? pb.lim.accel : pb.lim.alpha) * pb.dt;
    const double down = (is_v ? pb.lim.decel : pb.lim.alpha) * pb.dt;
    if (which % 2 == 0) return T(up) - (now - prev);  // rate <= up
    return (now - prev) + T(down);                    // rate >= -down
  }
  const int jj = j - pb.num_rate_constraints();
  if (jj >= pb.num_barrier_constraints()) {
    const int c = jj - pb.num_barrier_constraints(), k = c % pb.N;
    const T* x = states + 3 * k;
    const ReachValue r = reach_value(pb.reach[c / pb.N], k, value_of(x[0]), value_of(x[1]), value_of(x[2]),
                                     value_of(u[2 * k]), !std::is_same_v<T, double>);
    T g = lift_reach(r, x[0], x[1], x[2], u[2 * k]);
    if (!pb.relax.empty()) g = g + pb.relax[j];
    return g;
  }
  const ObstacleTrack& o = pb.obstacles[jj / pb.N];
  const int k = jj % pb.N;
  const T* p0 = states + 3 * k;
  const T* p1 = states + 3 * (k + 1);
  const double s1[3] = {value_of(p1[0]), value_of(p1[1]), value_of(p1[2])};
  T g = lift_barrier(constraint_barrier<T>(pb, o, k + 1, s1), p1[0], p1[1], p1[2]);
  if (o.decay != 0.0 || pb.own_motion) {
    const double s0[3] = {value_of(p0[0]), value_of(p0[1]), value_of(p0[2])};
    const BarrierValue b0 = constraint_barrier<T>(pb, o, pb.own_motion ? k + 1 : k, s0);
    const double decay = pb.own_motion && b0.h <= 0.0 ? 1.0 : o.decay;
    g = g - decay * lift_barrier(b0, p0[0], p0[1], p0[2]);
  }
  if (!pb.relax.empty()) g = g + pb.relax[j];
  return g;
}

// Wrapped angle difference, smooth for |e| < pi (atan2 of sin, cos).
template <class T>
T wrapped(const T& e) {
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(e), cos(e));
}

// Cost residuals r with J = sum r^2 (stage k = 1..N-1, terminal, controls,
// control rates). The stage term at k = 0 does not depend on u; it is added
// by objective() so that the reported cost is the paper's J.
inline int num_cost_residuals(const Problem& pb) { return 3 * pb.N + 2 * pb.N + 2 * (pb.N - 1); }

template <class T>
void cost_residuals(const Problem& pb, const T* states, const T* u, T* r) {
  using std::sqrt;
  int n = 0;
  const double sq_xy = std::sqrt(pb.w.q_xy), sq_yaw = std::sqrt(pb.w.q_yaw);
  for (int k = 1; k <= pb.N; ++k) {
    const bool terminal = k == pb.N;
    const double wxy = terminal ? std::sqrt(pb.w.p_xy) : sq_xy;
    const double wyaw = terminal ? std::sqrt(pb.w.p_yaw) : sq_yaw;
    const T* xk = states + 3 * k;
    r[n++] = wxy * (xk[0] - pb.ref_x[k]);
    r[n++] = wxy * (xk[1] - pb.ref_y[k]);
    r[n++] = wyaw * wrapped(T(xk[2] - pb.ref_yaw[k]));
  }
  const double sr_v = std::sqrt(pb.w.r_v), sr_w = std::sqrt(pb.w.r_omega);
  for (int k = 0; k < pb.N; ++k) {
    r[n++] = sr_v * u[2 * k];
    r[n++] = sr_w * u[2 * k + 1];
  }
  const double ss_v = std::sqrt(pb.w.s_v), ss_w = std::sqrt(pb.w.s_omega);
  for (int k = 0; k + 1 < pb.N; ++k) {
    r[n++] = ss_v * (u[2 * (k + 1)] - u[2 * k]);
    r[n++] = ss_w * (u[2 * (k + 1) + 1] - u[2 * k + 1]);
  }
}

// The objective J of the paper for controls u (double), plus the
// penetration term when pb.penetration_weight > 0.
double objective(const Problem& pb, const double* u);
// The same, of u whose rollout (rollout(pb, u, ...)) is `states`.
double objective(const Problem& pb, const double* u, const std::vector<double>& states);
// sum over obstacles and steps 1..N of min(0, h)^2 of a rollout's states.
double squared_penetration(const Problem& pb, const std::vector<double>& states);
// All constraints g_j(u) (>= 0 when satisfied) and the states of the rollout.
void evaluate_constraints(const Problem& pb, const double* u, std::vector<double>* states, std::vector<double>* g);
// Largest violation max_j max(0, -g_j) (m for barriers, m/s or rad/s per step for rates).
double max_violation(const Problem& pb, const double* u);
// Smallest h over every obstacle and step k = first_step..N of a rollout's
// states; kNoObstacleBarrier when there is none.
inline constexpr double kNoObstacleBarrier = 1e6;
double min_barrier(const Problem& pb, const std::vector<double>& states, int first_step = 0);
// The smallest slack h(X_k+1) - decay h(X_k) of obstacle o's barrier links
// over a rollout's states, k = 0..N-1 (NaN links skipped; +inf when there
// is none): negative where the plan misses the D-CBF constraint.
double barrier_slack(const Problem& pb, const ObstacleTrack& o, const std::vector<double>& states);

}  // namespace evade::planning
