#include "sim/scenario_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "sim/motion.h"
#include "sim/scenario_geometry.h"

namespace evade::sim {
namespace {

std::string fmt(const char* format, double a, double b = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof(buf), format, a, b);
  return buf;
}

std::string obstacle_name(const ObstacleSpec& o) { return "obstacles[" + std::to_string(o.id) + "]"; }

// Occupancy grid of the obstacles at rest for good, each grown by the
// half-width of the way the robot needs.
class PassageGrid {
 public:
  PassageGrid(const Scenario& sc, const ScenarioCheckParams& p) : res_(p.grid_m) {
    double x0 = std::min(sc.start.x, sc.goal.x), x1 = std::max(sc.start.x, sc.goal.x);
    double y0 = std::min(sc.start.y, sc.goal.y), y1 = std::max(sc.start.y, sc.goal.y);
    for (const Vec2& r : sc.route) {
      x0 = std::min(x0, r.x), x1 = std::max(x1, r.x), y0 = std::min(y0, r.y), y1 = std::max(y1, r.y);
    }
    ox_ = x0 - p.route_pad_m;
    oy_ = y0 - p.route_pad_m;
    nx_ = static_cast<int>(std::ceil((x1 - x0 + 2 * p.route_pad_m) / res_)) + 1;
    ny_ = static_cast<int>(std::ceil((y1 - y0 + 2 * p.route_pad_m) / res_)) + 1;
    blocked_.assign(static_cast<size_t>(nx_) * ny_, 0);
    // Half a cell of tolerance: a way exactly as wide as required still
    // holds a row of free cell centres.
    grow_ = (sc.footprint_width + p.passage_margin_m) / 2.0 - res_ / 2.0;
  }

  void add(const geom::Outline& o) {
    double lo_x = o.centre.x - o.radius, hi_x = o.centre.x + o.radius;
    double lo_y = o.centre.y - o.radius, hi_y = o.centre.y + o.radius;
    for (const Vec2& c : o.corners) {
      lo_x = std::min(lo_x, c.x), hi_x = std::max(hi_x, c.x), lo_y = std::min(lo_y, c.y), hi_y = std::max(hi_y, c.y);
    }
    int i0 = std::max(0, cell(lo_x - grow_, ox_)), i1 = std::min(nx_ - 1, cell(hi_x + grow_, ox_) + 1);
    int j0 = std::max(0, cell(lo_y - grow_, oy_)), j1 = std::min(ny_ - 1, cell(hi_y + grow_, oy_) + 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (geom::point_clearance(centre(i, j), o) < grow_) blocked_[index(i, j)] = 1;
  }

  bool blocked_at(const Vec2& p) const { return blocked_[index(nearest(p.x, ox_, nx_), nearest(p.y, oy_, ny_))] != 0; }

  // 8-connected flood fill from a to b over free cells.
  bool connected(const Vec2& a, const Vec2& b) const {
    int ai = nearest(a.x, ox_, nx_), aj = nearest(a.y, oy_, ny_);
    int bi = nearest(b.x, ox_, nx_), bj = nearest(b.y, oy_, ny_);
    std::vector<uint8_t> seen(blocked_.size(), 0);
    std::vector<std::pair<int, int>> todo{{ai, aj}};
    seen[index(ai, aj)] = 1;
    while (!todo.empty()) {
      auto [i, j] = todo.back();
      todo.pop_back();
      if (i == bi && j == bj) return true;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          int u = i + di, v = j + dj;
          if (u < 0 || v < 0 || u >= nx_ || v >= ny_) continue;
          size_t k = index(u, v);
          if (seen[k] || blocked_[k]) continue;
          seen[k] = 1;
          todo.emplace_back(u, v);
        }
    }
    return false;
  }

 private:
  int cell(double v, double origin) const { return static_cast<int>(std::floor((v - origin) / res_)); }
  int nearest(double v, double origin, int n) const {
    return std::clamp(static_cast<int>(std::lround((v - origin) / res_)), 0, n - 1);
  }
  Vec2 centre(int i, int j) const { return Vec2{ox_ + i * res_, oy_ + j * res_}; }
  size_t index(int i, int j) const { return static_cast<size_t>(j) * nx_ + i; }

  double res_;
  double ox_ = 0.0, oy_ = 0.0;
  int nx_ = 0, ny_ = 0;
  double grow_ = 0.0;
  std::vector<uint8_t> blocked_;
};

void check_route(const Scenario& sc, std::vector<std::string>* out) {
  constexpr double kSameM = 1e-6;
  if (geom::distance(sc.route.front(), Vec2{sc.start.x, sc.start.y}) > kSameM)
    out->push_back("route: does not start at the robot's start");
  if (geom::distance(sc.route.back(), sc.goal) > kSameM) out->push_back("route: does not end at the goal");
}

void check_rest(const Scenario& sc, const ScenarioCheckParams& p, std::vector<std::string>* out) {
  const double half_diagonal = std::hypot(sc.footprint_length, sc.footprint_width) / 2.0;
  const geom::Outline at_goal = geom::disc(sc.goal.x, sc.goal.y, half_diagonal);
  PassageGrid grid(sc, p);
  for (const ObstacleSpec& o : sc.obstacles) {
    Vec2 rest;
    if (!final_rest(o, &rest)) continue;
    geom::Outline shape = geom::obstacle_outline(o, rest.x, rest.y);
    double c = geom::clearance(at_goal, shape);
    if (c < p.goal_margin_m)
      out->push_back(obstacle_name(o) +
                     fmt(": rests %.3f m from the robot at the goal (margin %.3f m)", c, p.goal_margin_m));
    grid.add(shape);
  }
  Vec2 start{sc.start.x, sc.start.y};
  if (grid.blocked_at(start) || grid.blocked_at(sc.goal) || !grid.connected(start, sc.goal))
    out->push_back(fmt("passage: no way %.3f m wide from start to goal past the obstacles at rest",
                       sc.footprint_width + p.passage_margin_m));
}

}  // namespace

bool final_rest(const ObstacleSpec& o, Vec2* at) {
  if (o.motion == MotionKind::kStatic) {
    *at = Vec2{o.x, o.y};
    return true;
  }
  if (o.motion == MotionKind::kWaypoints && o.mode == WaypointMode::kOnce) {
    *at = o.waypoints.back();
    return true;
  }
  return false;
}

double start_gap(const ObstacleSpec& a, const ObstacleSpec& b) {
  return geom::clearance(geom::obstacle_outline(a, a.x, a.y), geom::obstacle_outline(b, b.x, b.y));
}

double start_clearance(const Scenario& sc, const ObstacleSpec& o, const ScenarioCheckParams& p) {
  const geom::Outline robot = geom::footprint(sc.start, sc.footprint_length, sc.footprint_width);
  double worst = std::numeric_limits<double>::infinity();
  const int steps = static_cast<int>(std::ceil(p.start_clear_time_s / p.time_step_s));
  for (int k = 0; k <= steps; ++k) {
    ObstacleState st = obstacle_state(o, std::min(k * p.time_step_s, p.start_clear_time_s));
    worst = std::min(worst, geom::clearance(robot, geom::obstacle_outline(o, st.x, st.y)));
  }
  return worst;
}

std::vector<std::string> check_scenario(const Scenario& sc, const ScenarioCheckParams& p) {
  std::vector<std::string> out;
  check_route(sc, &out);
  for (const ObstacleSpec& o : sc.obstacles) {
    if (o.height < p.min_height_m)
      out.push_back(obstacle_name(o) + fmt(": %.3f m high, below the visible %.3f m", o.height, p.min_height_m));
    double c = start_clearance(sc, o, p);
    if (c < p.start_margin_m)
      out.push_back(obstacle_name(o) + fmt(": comes %.3f m from the robot's start footprint in the first %.1f s", c,
                                           p.start_clear_time_s));
  }
  for (size_t i = 0; i < sc.obstacles.size(); ++i)
    for (size_t j = i + 1; j < sc.obstacles.size(); ++j) {
      double c = start_gap(sc.obstacles[i], sc.obstacles[j]);
      if (c < p.apart_m)
        out.push_back(obstacle_name(sc.obstacles[i]) + " and " + obstacle_name(sc.obstacles[j]) +
                      fmt(": start %.3f m apart (at least %.3f m)", c, p.apart_m));
    }
  check_rest(sc, p, &out);
  return out;
}

}  // namespace evade::sim
