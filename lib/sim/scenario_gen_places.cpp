// Families built around static things: doorway, occlusion, static_clutter
// (scenario_gen_families.h).
#include <algorithm>
#include <cmath>
#include <functional>

#include "sim/scenario_gen_families.h"

namespace evade::sim::gen::detail {
namespace {

constexpr int kTriesPerObstacle = 30;
// A person going through a gap keeps this much room to its edges.
constexpr double kGapRoomM = 0.05;
// A person stepping out passes this far from the vehicle's front end.
constexpr double kFrontClearM = 0.25;
// The person going through is on the gap's line this far either side of the wall.
constexpr double kInGapM = 0.6;

// A wall piece at x whose edge at the gap is exactly at y_gap and which
// reaches about `reach` away from it on side `side`.
ObstacleSpec wall_piece(double x, double y_gap, int side, double reach, double thickness, double height) {
  ObstacleSpec o;
  o.shape = Shape::kBox;
  o.length = thickness;
  o.width = q(reach);
  o.height = height;
  o.x = x;
  o.y = q(y_gap + side * o.width / 2.0, 1e-4);
  return o;
}

// Someone going through the gap at (xw, yc): `dir` +1 the robot's way, -1
// towards it; passes the wall `lead` s before the robot's nominal arrival.
bool through_walker(Ctx& c, Draft& d, double xw, double yc, double gap, int dir) {
  const DoorwayParams& k = c.p.doorway;
  ObstacleSpec o = cylinder_body(c, c.p.shapes.walker);
  o.radius = std::min(o.radius, q(gap / 2.0 - kGapRoomM));
  double approach = c.rng.uniform(k.approach_m), lead = c.rng.uniform(k.lead_s);
  double offset = c.rng.uniform(-0.5, 0.5) * (approach - 1.0);
  int aside = c.rng.sign();
  double exit = c.rng.uniform(k.exit_m), exit_aside = c.rng.uniform(k.exit_aside_m);
  std::vector<Vec2> path{Vec2{xw - dir * approach, yc + offset}, Vec2{xw - dir * kInGapM, yc},
                         Vec2{xw + dir * kInGapM, yc}, Vec2{xw + dir * exit, yc + aside * exit_aside}};
  double s_meet = path_length({path[0], path[1]}) + kInGapM;
  follow_timed(o, path, c.rng.uniform(c.p.shapes.walker.speed_mps), s_meet, arrival_s(c, d, xw) - lead);
  return add_if_clear(c, d, o,
                      std::string("walker through the gap ") + (dir > 0 ? "the robot's way" : "towards the robot") +
                          " at " + num(o.speed) + " m/s, passes the gap " + timing(lead));
}

// A parked vehicle on `side` along the route, near side `kerb` off it,
// spanning x in [x_rear, x_rear + length].
ObstacleSpec parked(Ctx& c, int side, double kerb, double* x_rear, bool rear_given, double x_front = 0.0) {
  ObstacleSpec o = box_body(c, c.p.shapes.parked_vehicle, 0.0);
  if (!rear_given) *x_rear = x_front - o.length;
  o.x = q(*x_rear + o.length / 2.0);
  o.y = q(side * (kerb + o.width / 2.0));
  return o;
}

bool static_item(Ctx& c, Draft& d) {
  const ClutterParams& k = c.p.static_clutter;
  double kind = c.rng.unit();
  double x = c.rng.uniform(d.sc.start.x + 1.0, d.sc.goal.x);
  ObstacleSpec o;
  std::string what;
  if (kind < k.bin_share) {
    o = cylinder_body(c, k.bin), what = "bin";
  } else if (kind < k.bin_share + k.post_share) {
    o = cylinder_body(c, k.post), what = "post";
  } else if (kind < k.bin_share + k.post_share + k.bench_share) {
    o = box_body(c, k.bench, c.rng.uniform(-0.4, 0.4)), what = "bench";
  } else if (kind < k.bin_share + k.post_share + k.bench_share + k.planter_share) {
    o = box_body(c, k.planter, c.rng.uniform(0.0, M_PI / 2.0)), what = "planter";
  } else {
    o = box_body(c, c.p.shapes.parked_vehicle, c.rng.uniform(-0.1, 0.1)), what = "parked vehicle";
    o.x = q(x);
    o.y = q(c.rng.sign() * c.rng.uniform(k.vehicle_lateral_m));
    return add_if_clear(c, d, o, what);
  }
  o.x = q(x);
  o.y = q(c.rng.uniform(k.lateral_m));
  return add_if_clear(c, d, o, what);
}

bool place(const std::function<bool()>& draw) {
  for (int i = 0; i < kTriesPerObstacle; ++i)
    if (draw()) return true;
  return false;
}

}  // namespace

bool doorway(Ctx& c, Draft& d) {
  const DoorwayParams& k = c.p.doorway;
  const double length = d.sc.goal.x - d.sc.start.x;
  double xw = q(d.sc.start.x + c.rng.uniform(k.wall_at) * length);
  // Gaps the robot cannot pass are left out: a wider robot (a profile,
  // config/robots/) draws from the part of the range it fits through.
  const Range gaps{std::max(k.gap_m.lo, c.robot.footprint_width_m + c.p.common.passage_margin_m), k.gap_m.hi};
  double yc = q(c.rng.uniform(k.gap_offset_m)), gap = q(c.rng.uniform(gaps));
  if (gap < gaps.lo) gap = gaps.lo;  // rounding never narrows it below the floor
  double half = c.rng.uniform(k.wall_half_length_m), thick = q(c.rng.uniform(c.p.shapes.wall.thickness_m));
  double height = q(c.rng.uniform(c.p.shapes.wall.height_m));
  double before = xw - k.straight_m - d.sc.start.x;
  if (before <= 0.0 || xw + k.straight_m >= d.sc.goal.x) return false;
  d.sc.route = {Vec2{d.sc.start.x, d.sc.start.y}, Vec2{q(xw - k.straight_m), yc}, Vec2{q(xw + k.straight_m), yc},
                d.sc.goal};
  d.sc.start.yaw = q(std::atan2(yc - d.sc.start.y, before), 1e-4);
  ObstacleSpec upper = wall_piece(xw, yc + gap / 2.0, 1, half - gap / 2.0, thick, height);
  ObstacleSpec lower = wall_piece(xw, yc - gap / 2.0, -1, half - gap / 2.0, thick, height);
  if (!add_if_clear(c, d, upper, "wall, left of a " + num(gap) + " m gap at y " + num(yc)) ||
      !add_if_clear(c, d, lower, "wall, right of the gap"))
    return false;
  bool someone = c.rng.chance(k.through_share);
  int dir = c.rng.chance(k.same_way_share) ? 1 : -1;
  if (someone && !place([&] { return through_walker(c, d, xw, yc, gap, dir); })) return false;
  d.summary.push_back("doorway: a " + num(gap) + " m gap in a wall across the way at x " + num(xw) +
                      (someone ? ", someone coming through" : ", nobody coming through"));
  return true;
}

bool occlusion(Ctx& c, Draft& d) {
  const OcclusionParams& k = c.p.occlusion;
  const bool jogger = c.rng.chance(k.jogger_share);
  ObstacleSpec person = cylinder_body(c, jogger ? c.p.shapes.jogger : c.p.shapes.walker);
  double x_cross = meet_x(c, d);
  int side = c.rng.sign();
  double kerb = q(c.rng.uniform(k.kerb_offset_m));
  double rear = 0.0;
  ObstacleSpec hiding = parked(c, side, kerb, &rear, false, x_cross - person.radius - kFrontClearM);
  if (!add_if_clear(c, d, hiding, "parked vehicle hiding the person")) return false;
  // The person waits behind it, then walks round its front end and across.
  double front = rear + hiding.length, y_behind = side * (kerb + hiding.width + k.behind_m + person.radius);
  double exit = c.rng.uniform(k.exit_m), lead = c.rng.uniform(k.lead_s);
  std::vector<Vec2> path{Vec2{front - c.rng.uniform(k.hidden_from_front_m), y_behind}, Vec2{x_cross, y_behind},
                         Vec2{x_cross, -side * exit}};
  double s_meet = path_length({path[0], path[1]}) + std::fabs(y_behind);
  double speed = c.rng.uniform(jogger ? c.p.shapes.jogger.speed_mps : c.p.shapes.walker.speed_mps);
  follow_timed(person, path, speed, s_meet, arrival_s(c, d, x_cross) - lead);
  if (!add_if_clear(c, d, person,
                    std::string(jogger ? "jogger" : "walker") + " stepping out from behind it at " + num(person.speed) +
                        " m/s, crosses at x " + num(x_cross) + " " + timing(lead)))
    return false;
  // More vehicles in line, before it or past the crossing lane.
  double first_rear = rear, last_front = x_cross + person.radius + kFrontClearM;
  int n = c.rng.integer(k.vehicles);
  for (int i = 1; i < n; ++i) {
    double gap = c.rng.uniform(k.vehicle_gap_m);
    ObstacleSpec v;
    if (c.rng.chance(0.5)) {
      v = parked(c, side, kerb, &rear, false, first_rear - gap);
      first_rear = rear;
    } else {
      rear = last_front + gap;
      v = parked(c, side, kerb, &rear, true);
      last_front = rear + v.length;
    }
    if (!add_if_clear(c, d, v, "parked vehicle")) return false;
  }
  d.summary.push_back("occlusion: a person steps out from behind a parked vehicle (" + count(n, "vehicle") +
                      " parked in line)");
  return true;
}

bool static_clutter(Ctx& c, Draft& d) {
  int n = c.rng.integer(c.p.static_clutter.items);
  for (int i = 0; i < n; ++i)
    if (!place([&] { return static_item(c, d); })) return false;
  d.summary.push_back("static_clutter: " + count(n, "piece", "pieces") + " of street furniture");
  return true;
}

}  // namespace evade::sim::gen::detail
