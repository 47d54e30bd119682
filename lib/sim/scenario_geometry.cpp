#include "sim/scenario_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::sim::geom {
namespace {

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

bool inside_polygon(const Vec2& p, const std::vector<Vec2>& c) {
  for (size_t i = 0; i < c.size(); ++i)
    if (cross(c[i], c[(i + 1) % c.size()], p) < 0.0) return false;
  return true;
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

bool segments_intersect(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  double d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && on_segment(c, d, a)) || (d2 == 0 && on_segment(c, d, b)) || (d3 == 0 && on_segment(a, b, c)) ||
         (d4 == 0 && on_segment(a, b, d));
}

double segment_segment_distance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  if (segments_intersect(a, b, c, d)) return 0.0;
  return std::min({point_segment_distance(a, c, d), point_segment_distance(b, c, d), point_segment_distance(c, a, b),
                   point_segment_distance(d, a, b)});
}

// Distance from p to the boundary of polygon c.
double boundary_distance(const Vec2& p, const std::vector<Vec2>& c) {
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < c.size(); ++i) best = std::min(best, point_segment_distance(p, c[i], c[(i + 1) % c.size()]));
  return best;
}

double polygon_polygon(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (inside_polygon(a[0], b) || inside_polygon(b[0], a)) return -1.0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j) {
      double d = segment_segment_distance(a[i], a[(i + 1) % a.size()], b[j], b[(j + 1) % b.size()]);
      if (d == 0.0) return -1.0;
      best = std::min(best, d);
    }
  return best;
}

}  // namespace

// sqrt of the sum of squares (IEEE: correctly rounded everywhere, and far
// cheaper than std::hypot; no coordinate here is near overflow).
double norm(double dx, double dy) { return std::sqrt(dx * dx + dy * dy); }

double distance(const Vec2& a, const Vec2& b) { return norm(a.x - b.x, a.y - b.y); }

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  double dx = b.x - a.x, dy = b.y - a.y;
  double len2 = dx * dx + dy * dy;
  double t = len2 > 0.0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return norm(p.x - (a.x + t * dx), p.y - (a.y + t * dy));
}

Outline rectangle(double cx, double cy, double yaw, double length, double width) {
  Outline o;
  o.centre = Vec2{cx, cy};
  double c = std::cos(yaw), s = std::sin(yaw);
  const double hl = length / 2.0, hw = width / 2.0;
  const double corners[4][2] = {{-hl, -hw}, {hl, -hw}, {hl, hw}, {-hl, hw}};  // counter-clockwise
  for (const auto& k : corners) o.corners.push_back(Vec2{cx + c * k[0] - s * k[1], cy + s * k[0] + c * k[1]});
  return o;
}

Outline disc(double cx, double cy, double radius) {
  Outline o;
  o.centre = Vec2{cx, cy};
  o.radius = radius;
  return o;
}

Outline footprint(const Pose2& pose, double length, double width) {
  return rectangle(pose.x, pose.y, pose.yaw, length, width);
}

Outline obstacle_outline(const ObstacleSpec& o, double x, double y) {
  if (o.shape == Shape::kCylinder) return disc(x, y, o.radius);
  return rectangle(x, y, o.yaw, o.length, o.width);
}

double point_clearance(const Vec2& p, const Outline& o) {
  if (o.corners.empty()) return distance(p, o.centre) - o.radius;
  if (inside_polygon(p, o.corners)) return 0.0;
  return boundary_distance(p, o.corners);
}

double clearance(const Outline& a, const Outline& b) {
  if (a.corners.empty() && b.corners.empty()) return distance(a.centre, b.centre) - a.radius - b.radius;
  if (a.corners.empty()) return point_clearance(a.centre, b) - a.radius;
  if (b.corners.empty()) return point_clearance(b.centre, a) - b.radius;
  return polygon_polygon(a.corners, b.corners);
}

bool segment_hits(const Vec2& a, const Vec2& b, const Outline& o) {
  if (o.corners.empty()) return point_segment_distance(o.centre, a, b) <= o.radius;
  if (inside_polygon(a, o.corners)) return true;
  for (size_t i = 0; i < o.corners.size(); ++i)
    if (segments_intersect(a, b, o.corners[i], o.corners[(i + 1) % o.corners.size()])) return true;
  return false;
}

}  // namespace evade::sim::geom
