#include "sim/motion.h"

#include <cmath>
#include <vector>

namespace evade::sim {
namespace {

// Points closer than this are the same waypoint (a path that repeats its
// start would otherwise get a zero-length segment).
constexpr double kSamePointM = 1e-9;

bool same(const Vec2& a, const Vec2& b) { return std::hypot(a.x - b.x, a.y - b.y) < kSamePointM; }

std::vector<Vec2> path_of(const ObstacleSpec& s) {
  std::vector<Vec2> path{Vec2{s.x, s.y}};
  for (const Vec2& w : s.waypoints)
    if (!same(w, path.back())) path.push_back(w);
  if (s.mode == WaypointMode::kLoop && path.size() > 1 && !same(path.back(), path.front()))
    path.push_back(path.front());
  return path;
}

double length_of(const std::vector<Vec2>& path) {
  double l = 0.0;
  for (size_t i = 1; i < path.size(); ++i) l += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y);
  return l;
}

// Point at arc length d along the path (0 <= d <= L), moving forward at `speed`.
ObstacleState along(const std::vector<Vec2>& path, double d, double speed) {
  for (size_t i = 1; i < path.size(); ++i) {
    double dx = path[i].x - path[i - 1].x, dy = path[i].y - path[i - 1].y;
    double seg = std::hypot(dx, dy);
    if (d <= seg || i + 1 == path.size()) {
      double f = std::min(d, seg) / seg;
      return ObstacleState{path[i - 1].x + f * dx, path[i - 1].y + f * dy, speed * dx / seg, speed * dy / seg};
    }
    d -= seg;
  }
  return ObstacleState{path.front().x, path.front().y, 0.0, 0.0};
}

}  // namespace

ObstacleState obstacle_state(const ObstacleSpec& s, double since_start_s) {
  const double t_s = since_start_s - s.start_delay_s;
  if (t_s <= 0.0 || s.motion == MotionKind::kStatic) return ObstacleState{s.x, s.y, 0.0, 0.0};
  if (s.motion == MotionKind::kConstantVelocity) return ObstacleState{s.x + s.vx * t_s, s.y + s.vy * t_s, s.vx, s.vy};

  std::vector<Vec2> path = path_of(s);
  double total = length_of(path);
  if (path.size() < 2 || total <= 0.0) return ObstacleState{s.x, s.y, 0.0, 0.0};
  double travelled = s.speed * t_s;
  switch (s.mode) {
    case WaypointMode::kOnce:
      if (travelled >= total) return ObstacleState{path.back().x, path.back().y, 0.0, 0.0};
      return along(path, travelled, s.speed);
    case WaypointMode::kLoop:
      return along(path, std::fmod(travelled, total), s.speed);
    case WaypointMode::kPingpong: {
      double d = std::fmod(travelled, 2.0 * total);
      if (d <= total) return along(path, d, s.speed);
      // On the way back: same place as forward at 2L - d, velocity reversed.
      ObstacleState st = along(path, 2.0 * total - d, s.speed);
      st.vx = -st.vx;
      st.vy = -st.vy;
      return st;
    }
  }
  return ObstacleState{s.x, s.y, 0.0, 0.0};
}

}  // namespace evade::sim
