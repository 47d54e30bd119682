// PlannerCore's static structure (static_structure.h), kept apart from the
// planning itself: the elevation maps' arrival and the field of each cycle.
#include <algorithm>
#include <cmath>
#include <vector>

#include "evade/grid_map_t.hpp"
#include "planning/escape.h"
#include "planning/input_checks.h"
#include "planning/planner_core.h"

namespace evade::planning {
namespace {

bool uses_field(const ModeSpec& m, const PlannerParams& p) { return m.evade_layers && p.static_field.enabled; }

// A barrier constraint's slack (h_k+1 - decay h_k, m) at most this is active.
constexpr double kHeldSlack = 1e-3;
// How far (m) a turn out of BLOCKED may take the footprint into the
// structure's margin (static_field.d_safe_m, 0.03 m by default).
constexpr double kEscapeIntoMarginM = 0.01;

// A plan that creeps (still within escape.min_progress_m of the start
// halfway through the horizon) where the way straight ahead is closed (the
// footprint moved straight on by min_progress_m would enter the
// structure's margin deeper than a turn out of it may): a robot that
// cannot reverse stands, whatever the plan promises at the horizon's end.
bool creeps_into_closed_way(const Problem& pb, const ObstacleTrack& field, const std::vector<double>& states,
                            double min_progress_m) {
  const int half = pb.N / 2;
  if (std::hypot(states[3 * half] - pb.x0, states[3 * half + 1] - pb.y0) >= min_progress_m) return false;
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  const double ahead[3] = {pb.x0 + min_progress_m * std::cos(pb.yaw0), pb.y0 + min_progress_m * std::sin(pb.yaw0),
                           pb.yaw0};
  const double floor = std::min(0.0, barrier_at(pb, field, 0, start).h) - kEscapeIntoMarginM;
  return barrier_at(pb, field, 0, ahead).h < floor;
}

}  // namespace

double static_field_reach_m(const PlannerParams& p) {
  double off = 0.0;
  for (double o : p.footprint.offsets) off = std::max(off, std::fabs(o));
  const double speed = std::max(std::fabs(p.limits.v_min), std::fabs(p.limits.v_max));
  return p.horizon_steps * p.dt_s * speed + off + 0.05;
}

namespace {

// Where this cycle reads the static field: every point the footprint's
// discs can reach over the horizon, and the route points the detour grid
// checks ahead of the progress (detour.h: lookahead_m, and the first point
// past it). A detour beyond that reads the whole map's field
// (StaticField::map_distance).
FieldWindow field_window(const PlannerParams& p, const RouteFollower& route, const evade::odometry_t& odom) {
  FieldWindow w = FieldWindow::around(odom.x, odom.y, static_field_reach_m(p));
  if (!p.detour.enabled || !route.has_route()) return w;
  const double s0 = route.progress(), step = p.detour.cell_m;
  const int samples = static_cast<int>(std::ceil(p.detour.lookahead_m / step)) + 2;
  for (int i = 0; i < samples; ++i) {
    double x, y;
    route.position_at(std::min(route.length(), s0 + i * step), &x, &y);
    w.include(x, y);
  }
  return w;
}

}  // namespace

void PlannerCore::subscribe_static_map() {
  if (!uses_field(mode_, p_)) return;
  subscribe<evade::grid_map_t>("ELEVATION_MAP", [this](const evade::grid_map_t& m) {
    switch (arrival(now(), m.utime, std::llround(p_.static_field.map_max_age_s * 1e6))) {
      case Arrival::kLate:
        count("static_map_late");
        return;
      case Arrival::kFuture:
        count("static_map_future");
        return;
      case Arrival::kOnTime:
        break;
    }
    if (epoch_start_utime_ >= 0 && m.utime < epoch_start_utime_) {
      count("static_map_before_epoch");  // built in the old odometry frame
      return;
    }
    static_.keep_map(m);
  });
}

void PlannerCore::update_static_field(const evade::odometry_t& odom) {
  detour_.set_field(nullptr, 0.0);
  if (!uses_field(mode_, p_)) return;
  StaticStructure::Inputs in;
  in.odometry_utime = odom.utime;
  in.window = field_window(p_, route_, odom);
  in.predictions = predictions_ ? &*predictions_ : nullptr;
  in.observed = observed_ ? &*observed_ : nullptr;
  in.track_age_s = [&](int64_t id) { return track_age_s(id, odom.utime); };
  switch (static_.update(in)) {
    case StaticStructure::Update::kStale:
      count("static_map_stale");  // every track by its ellipse, as without the field
      return;
    case StaticStructure::Update::kInvalid:
      count("static_map_invalid");
      return;
    case StaticStructure::Update::kBuilt:
      break;
  }
  count("static_field");
  detour_.set_field(static_.field(), p_.footprint.radius);
}

bool PlannerCore::escape_from_structure(const Problem& pb, const evade::odometry_t& odom, bool is_blocked,
                                        std::vector<double>* u) {
  const int side_before = escape_side_;
  escape_side_ = 0;
  if (!is_blocked || !uses_field(mode_, p_) || !p_.escape.enabled || pb.ref_x.empty()) return false;
  const auto field =
      std::find_if(pb.obstacles.begin(), pb.obstacles.end(), [](const ObstacleTrack& o) { return o.field; });
  if (field == pb.obstacles.end()) return false;
  const int N = pb.N;
  std::vector<double> states(3 * (N + 1));
  rollout(pb, u->data(), states.data());
  // headway: the rollout's end at least escape.min_progress_m from the start
  const auto headway = [&] {
    return std::hypot(states[3 * N] - pb.x0, states[3 * N + 1] - pb.y0) >= p_.escape.min_progress_m;
  };
  if (headway() && !creeps_into_closed_way(pb, *field, states, p_.escape.min_progress_m)) return false;
  // held by the wall (once the turn has begun, it goes on while the solver would turn back)
  if (!side_before && !(barrier_slack(pb, *field, states) <= kHeldSlack)) return false;
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  const BarrierValue h = barrier_at(pb, *field, 0, start);
  const double out = std::atan2(h.gy, h.gx);
  const double to_ref = std::atan2(pb.ref_y[N] - pb.y0, pb.ref_x[N] - pb.x0);
  const double cone = p_.escape.cone_half_angle_rad;
  const double err = wrap_angle(out + std::clamp(wrap_angle(to_ref - out), -cone, cone) - pb.yaw0);
  if (std::fabs(err) < 0.5 * p_.limits.omega_max * p_.dt_s) return false;  // facing the way out
  const int first = side_before ? side_before : (err > 0 ? 1 : -1);
  // the movers' constraints (and the rate limits) met; the structure's
  // margin entered by at most kEscapeIntoMarginM (at h near 0 its D-CBF
  // leaves no room for the footprint's corners to swing); some headway
  Problem movers = pb;
  movers.obstacles.erase(movers.obstacles.begin() + (field - pb.obstacles.begin()));
  const std::vector<double> brake = braking_controls(odom.v, odom.omega);
  const double w0 = std::clamp(odom.omega, -p_.limits.omega_max, p_.limits.omega_max);
  for (int side : {first, -first}) {
    const double left = side * err > 0 ? std::fabs(err) : 2 * M_PI - std::fabs(err);
    std::vector<double> turn = turn_on_the_spot(pb, side * left, brake, w0, &*field, kEscapeIntoMarginM);
    rollout(pb, turn.data(), states.data());
    if (!(max_violation(movers, turn.data()) <= p_.solver.constraint_tolerance) ||
        !(structure_intrusion(pb, states) <= kEscapeIntoMarginM) ||
        !(side * (states[3 * N + 2] - pb.yaw0) >= p_.limits.omega_max * p_.dt_s || headway()))
      continue;
    *u = turn;
    escape_side_ = side;
    return true;
  }
  return false;
}

}  // namespace evade::planning
