#include "metrics/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::metrics {
namespace {

Vec2 to_local(const OrientedRect& r, Vec2 p) {
  double c = std::cos(r.yaw), s = std::sin(r.yaw);
  double dx = p.x - r.centre.x, dy = p.y - r.centre.y;
  return {c * dx + s * dy, -s * dx + c * dy};
}

Vec2 to_world(const OrientedRect& r, Vec2 p) {
  double c = std::cos(r.yaw), s = std::sin(r.yaw);
  return {r.centre.x + c * p.x - s * p.y, r.centre.y + s * p.x + c * p.y};
}

// Closest point of the (closed) rectangle to p, in world coordinates.
Vec2 closest_on_rect(const OrientedRect& r, Vec2 p) {
  Vec2 l = to_local(r, p);
  double hx = 0.5 * r.length, hy = 0.5 * r.width;
  Vec2 q{std::clamp(l.x, -hx, hx), std::clamp(l.y, -hy, hy)};
  if (std::fabs(l.x) <= hx && std::fabs(l.y) <= hy) {
    // inside: the nearest edge
    double ex = hx - std::fabs(l.x), ey = hy - std::fabs(l.y);
    if (ex < ey)
      q.x = std::copysign(hx, l.x);
    else
      q.y = std::copysign(hy, l.y);
  }
  return to_world(r, q);
}

Vec2 closest_on_segment(Vec2 a, Vec2 b, Vec2 p) {
  double dx = b.x - a.x, dy = b.y - a.y;
  double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, 0.0, 1.0) : 0.0;
  return {a.x + t * dx, a.y + t * dy};
}

double dist(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

// Separating-axis test for two rectangles: the overlap depth along the
// axis of least overlap (> 0 when they intersect), or <= 0 when separated.
double overlap_depth(const OrientedRect& a, const OrientedRect& b) {
  auto ca = a.corners(), cb = b.corners();
  double best = std::numeric_limits<double>::infinity();
  for (const OrientedRect* r : {&a, &b}) {
    for (double ang : {r->yaw, r->yaw + M_PI / 2}) {
      Vec2 axis{std::cos(ang), std::sin(ang)};
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (auto p : ca) {
        double d = p.x * axis.x + p.y * axis.y;
        amin = std::min(amin, d);
        amax = std::max(amax, d);
      }
      for (auto p : cb) {
        double d = p.x * axis.x + p.y * axis.y;
        bmin = std::min(bmin, d);
        bmax = std::max(bmax, d);
      }
      best = std::min(best, std::min(amax, bmax) - std::max(amin, bmin));
    }
  }
  return best;
}

}  // namespace

std::array<Vec2, 4> OrientedRect::corners() const {
  double hx = 0.5 * length, hy = 0.5 * width;
  return {to_world(*this, {hx, hy}), to_world(*this, {-hx, hy}), to_world(*this, {-hx, -hy}),
          to_world(*this, {hx, -hy})};
}

double signed_distance(const OrientedRect& r, Vec2 p) {
  Vec2 l = to_local(r, p);
  double dx = std::fabs(l.x) - 0.5 * r.length, dy = std::fabs(l.y) - 0.5 * r.width;
  if (dx <= 0 && dy <= 0) return std::max(dx, dy);
  return std::hypot(std::max(dx, 0.0), std::max(dy, 0.0));
}

double clearance(const OrientedRect& r, Vec2 centre, double radius) { return signed_distance(r, centre) - radius; }

void closest_points(const OrientedRect& r, Vec2 centre, double radius, Vec2* on_r, Vec2* on_circle) {
  Vec2 q = closest_on_rect(r, centre);
  *on_r = q;
  double d = dist(q, centre);
  if (d < 1e-12) {
    *on_circle = centre;
    return;
  }
  double s = signed_distance(r, centre) < 0 ? -1.0 : 1.0;  // inside: the circle edge lies beyond q
  *on_circle = {centre.x + s * (q.x - centre.x) / d * radius, centre.y + s * (q.y - centre.y) / d * radius};
}

double clearance(const OrientedRect& a, const OrientedRect& b) {
  double depth = overlap_depth(a, b);
  if (depth > 0) return -depth;
  Vec2 pa, pb;
  closest_points(a, b, &pa, &pb);
  return dist(pa, pb);
}

void closest_points(const OrientedRect& a, const OrientedRect& b, Vec2* on_a, Vec2* on_b) {
  auto ca = a.corners(), cb = b.corners();
  double best = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < 2; ++pass) {
    const auto& verts = pass == 0 ? ca : cb;
    const auto& edges = pass == 0 ? cb : ca;
    for (auto v : verts) {
      for (int e = 0; e < 4; ++e) {
        Vec2 q = closest_on_segment(edges[e], edges[(e + 1) % 4], v);
        double d = dist(v, q);
        if (d < best) {
          best = d;
          *on_a = pass == 0 ? v : q;
          *on_b = pass == 0 ? q : v;
        }
      }
    }
  }
}

}  // namespace evade::metrics
