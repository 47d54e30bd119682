// Families of movers on a straight route: crossing, headon, overtaking,
// fast_small, crowd (scenario_gen_families.h).
#include <cmath>
#include <functional>

#include "sim/scenario_gen_families.h"
#include "sim/scenario_geometry.h"

namespace evade::sim::gen::detail {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
// Draws of one obstacle before the whole scene is redrawn.
constexpr int kTriesPerObstacle = 30;

bool try_place(const std::function<bool()>& draw) {
  for (int i = 0; i < kTriesPerObstacle; ++i)
    if (draw()) return true;
  return false;
}

const char* side_name(int side) { return side > 0 ? "the left" : "the right"; }

// A mover crossing the route at (x_meet, 0) from `side` (+1: y > 0) at
// `angle_deg` to the route, straight from `approach` before to `exit` past.
std::vector<Vec2> straight_across(double x_meet, int side, double angle_deg, double approach, double exit, Vec2* dir) {
  Vec2 h = heading(angle_deg * kDegToRad);
  *dir = Vec2{h.x, -side * h.y};
  Vec2 meet{x_meet, 0.0};
  return {along(meet, *dir, -approach), along(meet, *dir, exit)};
}

// A straight course across the route, drawn in this order: where it meets
// the route, from which side, at what angle, how far before and past, how
// early the mover gets there.
struct Crossing {
  double x = 0.0, angle = 0.0, approach = 0.0, exit = 0.0, lead = 0.0;
  int side = 1;
  Vec2 dir;
  std::vector<Vec2> path;
};

Crossing draw_crossing(Ctx& c, Draft& d, const Range& angle_deg, const Range& approach_m, const Range& exit_m,
                       const Range& lead_s) {
  Crossing k;
  k.x = meet_x(c, d);
  k.side = c.rng.sign();
  k.angle = c.rng.uniform(angle_deg);
  k.approach = c.rng.uniform(approach_m);
  k.exit = c.rng.uniform(exit_m);
  k.lead = c.rng.uniform(lead_s);
  k.path = straight_across(k.x, k.side, k.angle, k.approach, k.exit, &k.dir);
  return k;
}

bool crosser(Ctx& c, Draft& d) {
  const CrossingParams& k = c.p.crossing;
  bool bike = c.rng.chance(k.bike_share);
  const Crossing x = draw_crossing(c, d, k.crossing_angle_deg, k.approach_m, k.exit_m, k.lead_s);
  ObstacleSpec o =
      bike ? box_body(c, c.p.shapes.bike, std::atan2(x.dir.y, x.dir.x)) : cylinder_body(c, c.p.shapes.walker);
  double speed = c.rng.uniform(bike ? c.p.shapes.bike.speed_mps : c.p.shapes.walker.speed_mps);
  follow_timed(o, x.path, speed, x.approach, arrival_s(c, d, x.x) - x.lead);
  return add_if_clear(c, d, o,
                      std::string(bike ? "bike" : "walker") + " crossing from " + side_name(x.side) + " at " +
                          num(o.speed) + " m/s, " + num(x.angle) + " deg, meets the route at x " + num(x.x) + " " +
                          timing(x.lead));
}

bool headon_mover(Ctx& c, Draft& d) {
  const HeadonParams& k = c.p.headon;
  bool bike = c.rng.chance(k.bike_share);
  bool group = !bike && c.rng.chance(k.group_share);
  int size = group ? c.rng.integer(k.group_size) : 1;
  double spacing = group ? c.rng.uniform(k.group_spacing_m) : 0.0;
  double x = d.sc.goal.x + c.rng.uniform(k.start_past_goal_m), y = c.rng.uniform(k.lateral_offset_m);
  double speed = c.rng.uniform(bike ? c.p.shapes.bike.speed_mps : c.p.shapes.walker.speed_mps);
  double delay = q(c.rng.uniform(k.start_delay_s), 0.01);
  std::vector<ObstacleSpec> movers;
  std::vector<std::string> notes;
  for (int i = 0; i < size; ++i) {
    ObstacleSpec o = bike ? box_body(c, c.p.shapes.bike, M_PI) : cylinder_body(c, c.p.shapes.walker);
    o.x = q(x);
    o.y = q(y + (i - (size - 1) / 2.0) * spacing);  // abreast, centred on the drawn line
    o.motion = MotionKind::kConstantVelocity;
    o.vx = -q(speed);
    o.start_delay_s = delay;
    movers.push_back(o);
    notes.push_back(std::string(bike ? "bike" : "walker") + " head-on at " + num(-o.vx) + " m/s, " + num(o.y) +
                    " m off the route, after " + num(delay) + " s" +
                    (group ? ", one of " + std::to_string(size) + " abreast" : ""));
  }
  return add_all_if_clear(c, d, movers, notes);
}

bool overtaker(Ctx& c, Draft& d) {
  const OvertakingParams& k = c.p.overtaking;
  double kind = c.rng.unit();
  bool jogger = kind < k.jogger_share, bike = !jogger && kind < k.jogger_share + k.bike_share;
  ObstacleSpec o = bike     ? box_body(c, c.p.shapes.bike, 0.0)
                   : jogger ? cylinder_body(c, c.p.shapes.jogger)
                            : cylinder_body(c, c.p.shapes.walker);
  const Range& speed = bike ? c.p.shapes.bike.speed_mps : jogger ? c.p.shapes.jogger.speed_mps : k.walker_speed_mps;
  o.y = q(c.rng.sign() * c.rng.uniform(k.lateral_offset_m));
  o.x = q(d.sc.start.x - c.rng.uniform(k.start_behind_m));
  o.motion = MotionKind::kConstantVelocity;
  o.vx = q(c.rng.uniform(speed));
  o.start_delay_s = q(c.rng.uniform(k.start_delay_s), 0.01);
  const char* what = bike ? "bike" : jogger ? "jogger" : "walker";
  return add_if_clear(c, d, o,
                      std::string(what) + " overtaking at " + num(o.vx) + " m/s, " + num(o.y) + " m off the route, " +
                          num(d.sc.start.x - o.x) + " m behind, after " + num(o.start_delay_s) + " s");
}

// A zig-zag from `from` along `dir`, legs alternating left and right of it,
// until it has made `progress` along dir.
std::vector<Vec2> zigzag(Ctx& c, const Vec2& from, const Vec2& dir, double progress) {
  const FastSmallParams& k = c.p.fast_small;
  std::vector<Vec2> path{from};
  int turn_side = c.rng.sign();
  double made = 0.0;
  while (made < progress) {
    double leg = c.rng.uniform(k.zigzag_leg_m), turn = turn_side * c.rng.uniform(k.zigzag_turn_deg) * kDegToRad;
    turn_side = -turn_side;
    Vec2 leg_dir{dir.x * std::cos(turn) - dir.y * std::sin(turn), dir.x * std::sin(turn) + dir.y * std::cos(turn)};
    path.push_back(along(path.back(), leg_dir, leg));
    made += leg * std::cos(turn);
  }
  return path;
}

// Where `path` first reaches y = 0: the point and the arc length to it.
bool first_crossing(const std::vector<Vec2>& path, Vec2* at, double* arc) {
  double s = 0.0;
  for (size_t i = 1; i < path.size(); ++i) {
    const Vec2 &a = path[i - 1], &b = path[i];
    if ((a.y > 0.0) != (b.y > 0.0) || b.y == 0.0) {
      double f = a.y / (a.y - b.y);
      *at = Vec2{a.x + f * (b.x - a.x), 0.0};
      *arc = s + f * geom::distance(a, b);
      return true;
    }
    s += geom::distance(a, b);
  }
  return false;
}

bool small_mover(Ctx& c, Draft& d) {
  const FastSmallParams& k = c.p.fast_small;
  bool ball = c.rng.chance(k.ball_share);
  const Crossing course = draw_crossing(c, d, k.crossing_angle_deg, k.approach_m, k.exit_m, k.lead_s);
  const double x = course.x, lead = course.lead;
  const int side = course.side;
  std::vector<Vec2> path = course.path;
  if (!ball) path = zigzag(c, path.front(), course.dir, course.approach + course.exit);
  Vec2 cross;
  double s_meet = 0.0;
  if (std::fabs(path.front().y) < 1.0 || !first_crossing(path, &cross, &s_meet)) return false;
  for (Vec2& p : path) p.x += x - cross.x;  // meet the route at x
  ObstacleSpec o = cylinder_body(c, ball ? c.p.shapes.ball : c.p.shapes.dog);
  if (ball) o.height = q(2.0 * o.radius);
  double speed = c.rng.uniform(ball ? c.p.shapes.ball.speed_mps : c.p.shapes.dog.speed_mps);
  follow_timed(o, path, speed, s_meet, arrival_s(c, d, x) - lead);
  return add_if_clear(c, d, o,
                      std::string(ball ? "ball rolling" : "dog zig-zagging") + " from " + side_name(side) + " at " +
                          num(o.speed) + " m/s, meets the route at x " + num(x) + " " + timing(lead));
}

// A walker going back and forth between a and b (loop a -> b -> a), first
// seen at a random point between them, heading either way.
void back_and_forth(Ctx& c, ObstacleSpec& o, const Vec2& a, const Vec2& b, double speed) {
  double u = c.rng.unit();
  bool to_b = c.rng.chance(0.5);
  Vec2 p{q(a.x + u * (b.x - a.x)), q(a.y + u * (b.y - a.y))};
  Vec2 qa{q(a.x), q(a.y)}, qb{q(b.x), q(b.y)};
  o.x = p.x;
  o.y = p.y;
  o.motion = MotionKind::kWaypoints;
  o.mode = WaypointMode::kLoop;
  o.waypoints = to_b ? std::vector<Vec2>{qb, qa} : std::vector<Vec2>{qa, qb};
  o.speed = q(speed);
}

bool crowd_walker(Ctx& c, Draft& d, double street_width, double crossing_share) {
  const CrowdParams& k = c.p.crowd;
  ObstacleSpec o = cylinder_body(c, c.p.shapes.walker);
  double speed = c.rng.uniform(c.p.shapes.walker.speed_mps);
  double half = street_width / 2.0;
  std::string note;
  if (c.rng.chance(crossing_share)) {
    double x = c.rng.uniform(d.sc.start.x, d.sc.goal.x), angle = c.rng.uniform(k.crossing_angle_deg) * kDegToRad;
    Vec2 dir{std::cos(angle), -std::sin(angle)}, mid{x, 0.0};
    double reach = half / std::sin(angle);
    back_and_forth(c, o, along(mid, dir, -reach), along(mid, dir, reach), speed);
    note = "walker crossing back and forth at x " + num(x) + ", " + num(o.speed) + " m/s";
  } else {
    double y = c.rng.sign() * std::min(c.rng.uniform(k.along_lateral_m), half - o.radius);
    double xc = c.rng.uniform(d.sc.start.x, d.sc.goal.x), len = c.rng.uniform(k.along_length_m);
    back_and_forth(c, o, Vec2{xc - len / 2.0, y}, Vec2{xc + len / 2.0, y}, speed);
    note = "walker back and forth along the street, " + num(y) + " m off the route, " + num(o.speed) + " m/s";
  }
  for (const ObstacleSpec& other : d.sc.obstacles)
    if (geom::distance(Vec2{o.x, o.y}, Vec2{other.x, other.y}) - o.radius - other.radius < k.min_separation_m)
      return false;
  return add_if_clear(c, d, o, note);
}

}  // namespace

bool crossing(Ctx& c, Draft& d) {
  int n = c.rng.integer(c.p.crossing.movers);
  for (int i = 0; i < n; ++i)
    if (!try_place([&] { return crosser(c, d); })) return false;
  d.summary.push_back("crossing: " + count(n, "mover") + " crossing the route");
  return true;
}

bool headon(Ctx& c, Draft& d) {
  int n = c.rng.integer(c.p.headon.movers);
  const size_t before = d.sc.obstacles.size();
  for (int i = 0; i < n; ++i)
    if (!try_place([&] { return headon_mover(c, d); })) return false;
  int added = static_cast<int>(d.sc.obstacles.size() - before);
  // Each draw is one mover or one group abreast.
  d.summary.push_back("headon: " + count(added, "mover") + (added > n ? " in " + count(n, "rank") : "") +
                      " coming down the route");
  return true;
}

bool overtaking(Ctx& c, Draft& d) {
  int n = c.rng.integer(c.p.overtaking.movers);
  for (int i = 0; i < n; ++i)
    if (!try_place([&] { return overtaker(c, d); })) return false;
  d.summary.push_back("overtaking: " + count(n, "faster mover") + " from behind");
  return true;
}

bool fast_small(Ctx& c, Draft& d) {
  int n = c.rng.integer(c.p.fast_small.movers);
  for (int i = 0; i < n; ++i)
    if (!try_place([&] { return small_mover(c, d); })) return false;
  d.summary.push_back("fast_small: " + count(n, "ball or dog", "balls and dogs"));
  return true;
}

bool crowd(Ctx& c, Draft& d) {
  const CrowdParams& k = c.p.crowd;
  int n = c.rng.integer(k.walkers);
  double width = q(c.rng.uniform(k.street_width_m), 0.01), share = c.rng.uniform(k.crossing_share);
  for (int i = 0; i < n; ++i)
    if (!try_place([&] { return crowd_walker(c, d, width, share); })) return false;
  d.summary.push_back("crowd: " + std::to_string(n) + " walkers in a " + num(width) + " m street, " +
                      num(100.0 * share) + " % of them crossing");
  return true;
}

}  // namespace evade::sim::gen::detail
