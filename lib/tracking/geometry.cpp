#include "tracking/geometry.h"

#include <algorithm>
#include <cmath>

namespace evade::tracking {

double wrap_half_pi(double a) {
  a = std::fmod(a + M_PI / 2, M_PI);
  if (a < 0.0) a += M_PI;
  return a - M_PI / 2;
}

namespace {
double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}
}  // namespace

std::vector<Vec2> convex_hull(std::vector<Vec2> pts) {
  std::sort(pts.begin(), pts.end(),
            [](const Vec2& p, const Vec2& q) { return p.x < q.x || (p.x == q.x && p.y < q.y); });
  pts.erase(std::unique(pts.begin(), pts.end(), [](const Vec2& p, const Vec2& q) { return p.x == q.x && p.y == q.y; }),
            pts.end());
  if (pts.size() < 3) return pts;
  std::vector<Vec2> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i - 1]) <= 0) --k;
    h[k++] = pts[i - 1];
  }
  h.resize(k - 1);
  return h;
}

double ellipse_level(const Ellipse& e, const Vec2& p) {
  const double c = std::cos(e.theta), s = std::sin(e.theta);
  const double dx = p.x - e.cx, dy = p.y - e.cy;
  const double u = c * dx + s * dy, v = -s * dx + c * dy;
  return (u * u) / (e.a * e.a) + (v * v) / (e.b * e.b);
}

double ellipse_area(const Ellipse& e) { return M_PI * e.a * e.b; }

namespace {

// Thin ellipse along the points' longest extent (collinear or single point).
Ellipse thin_ellipse(const std::vector<Vec2>& pts, double min_semi_axis) {
  size_t ia = 0, ib = 0;
  double best = -1.0;
  for (size_t i = 0; i < pts.size(); ++i)
    for (size_t j = i + 1; j < pts.size(); ++j) {
      const double d = std::hypot(pts[i].x - pts[j].x, pts[i].y - pts[j].y);
      if (d > best) best = d, ia = i, ib = j;
    }
  Ellipse e;
  e.cx = 0.5 * (pts[ia].x + pts[ib].x);
  e.cy = 0.5 * (pts[ia].y + pts[ib].y);
  e.b = min_semi_axis;
  e.a = std::max(min_semi_axis, 0.5 * std::max(best, 0.0));
  e.theta = best > 0.0 ? wrap_half_pi(std::atan2(pts[ib].y - pts[ia].y, pts[ib].x - pts[ia].x)) : 0.0;
  // every point inside, including ones slightly off the line
  double level = 0.0;
  for (const auto& p : pts) level = std::max(level, ellipse_level(e, p));
  if (level > 1.0) {
    const double s = std::sqrt(level);
    e.a *= s;
    e.b *= s;
  }
  return e;
}

bool invert3(const double m[9], double out[9]) {
  const double c0 = m[4] * m[8] - m[5] * m[7];
  const double c1 = m[5] * m[6] - m[3] * m[8];
  const double c2 = m[3] * m[7] - m[4] * m[6];
  const double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
  if (!(std::abs(det) > 1e-300)) return false;
  const double id = 1.0 / det;
  out[0] = c0 * id;
  out[1] = (m[2] * m[7] - m[1] * m[8]) * id;
  out[2] = (m[1] * m[5] - m[2] * m[4]) * id;
  out[3] = c1 * id;
  out[4] = (m[0] * m[8] - m[2] * m[6]) * id;
  out[5] = (m[2] * m[3] - m[0] * m[5]) * id;
  out[6] = c2 * id;
  out[7] = (m[1] * m[6] - m[0] * m[7]) * id;
  out[8] = (m[0] * m[4] - m[1] * m[3]) * id;
  return true;
}

// Khachiyan's weights with Wolfe-Atwood away steps over the hull points
// (Todd & Yildirim 2007), until every lifted weight is within tolerance of
// d + 1. Returns the iterations run.
int khachiyan_weights(const std::vector<Vec2>& pts, const MbeOptions& opt, std::vector<double>* weights) {
  const size_t n = pts.size();
  constexpr double kD1 = 3.0;  // d + 1 for d = 2
  std::vector<double>& u = *weights;
  u.assign(n, 1.0 / double(n));
  std::vector<double> w(n);
  int it = 0;
  for (; it < opt.max_iterations; ++it) {
    double X[9] = {0};
    for (size_t i = 0; i < n; ++i) {
      const double q[3] = {pts[i].x, pts[i].y, 1.0};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) X[r * 3 + c] += u[i] * q[r] * q[c];
    }
    double Xi[9];
    if (!invert3(X, Xi)) break;
    size_t j = 0, k = n;
    for (size_t i = 0; i < n; ++i) {
      const double q[3] = {pts[i].x, pts[i].y, 1.0};
      double s = 0.0;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) s += q[r] * Xi[r * 3 + c] * q[c];
      w[i] = s;
      if (w[i] > w[j]) j = i;
      if (u[i] > 0.0 && (k == n || w[i] < w[k])) k = i;
    }
    const double eps_plus = w[j] / kD1 - 1.0;
    const double eps_minus = 1.0 - w[k] / kD1;
    if (std::max(eps_plus, eps_minus) <= opt.tolerance) break;
    if (eps_plus >= eps_minus) {
      const double tau = (w[j] - kD1) / (kD1 * (w[j] - 1.0));
      for (auto& ui : u) ui *= (1.0 - tau);
      u[j] += tau;
    } else {  // away step: take weight off the least useful support point
      double tau = w[k] > 1.0 ? (w[k] - kD1) / (kD1 * (w[k] - 1.0)) : -1.0;
      const double limit = -u[k] / (1.0 - u[k]);
      const bool drop = tau <= limit;
      if (drop) tau = limit;
      for (auto& ui : u) ui *= (1.0 - tau);
      u[k] = drop ? 0.0 : u[k] + tau;
    }
  }
  return it;
}

// The ellipse of the weights (A = Sigma^-1 / d), scaled about its centre so
// that the farthest hull point lies on the boundary. False when the weighted
// spread is degenerate.
bool ellipse_from_weights(const std::vector<Vec2>& pts, const std::vector<double>& u, double scale, Ellipse* e) {
  const size_t n = pts.size();
  double cx = 0.0, cy = 0.0;
  for (size_t i = 0; i < n; ++i) cx += u[i] * pts[i].x, cy += u[i] * pts[i].y;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double dx = pts[i].x - cx, dy = pts[i].y - cy;
    sxx += u[i] * dx * dx;
    sxy += u[i] * dx * dy;
    syy += u[i] * dy * dy;
  }
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 1e-18 * scale * scale * scale * scale)) return false;
  double a11 = syy / det / 2.0, a12 = -sxy / det / 2.0, a22 = sxx / det / 2.0;
  // exact enclosure: scale about the centre until the farthest point is on the boundary
  double level = 0.0;
  for (const auto& p : pts) {
    const double dx = p.x - cx, dy = p.y - cy;
    level = std::max(level, a11 * dx * dx + 2.0 * a12 * dx * dy + a22 * dy * dy);
  }
  level *= 1.0 + 1e-12;
  a11 /= level, a12 /= level, a22 /= level;
  const double mean = 0.5 * (a11 + a22);
  const double rad = std::sqrt(0.25 * (a11 - a22) * (a11 - a22) + a12 * a12);
  e->cx = cx;
  e->cy = cy;
  e->a = 1.0 / std::sqrt(mean - rad);  // the smaller eigenvalue lies along the major axis
  e->b = 1.0 / std::sqrt(mean + rad);
  // eigenvector of the larger eigenvalue is at 0.5 atan2(2 a12, a11 - a22); the major axis is normal to it
  e->theta = wrap_half_pi(0.5 * std::atan2(2.0 * a12, a11 - a22) + M_PI / 2);
  return true;
}

}  // namespace

Ellipse min_bounding_ellipse(const std::vector<Vec2>& input, const MbeOptions& opt, int* iterations) {
  if (iterations) *iterations = 0;
  if (input.empty()) return Ellipse{0, 0, opt.min_semi_axis, opt.min_semi_axis, 0};
  // Work relative to the first point (conditioning of the lifted moments).
  const Vec2 ref = input.front();
  std::vector<Vec2> rel(input.size());
  for (size_t i = 0; i < input.size(); ++i) rel[i] = {input[i].x - ref.x, input[i].y - ref.y};
  const std::vector<Vec2> pts = convex_hull(rel);

  double scale = 0.0;  // spread of the hull, for the degeneracy test
  for (const auto& p : pts) scale = std::max(scale, std::hypot(p.x - pts[0].x, p.y - pts[0].y));
  double area2 = 0.0;  // twice the hull area
  for (size_t i = 0; i < pts.size(); ++i) {
    const Vec2& p = pts[i];
    const Vec2& q = pts[(i + 1) % pts.size()];
    area2 += p.x * q.y - q.x * p.y;
  }
  Ellipse e;
  std::vector<double> u;
  if (pts.size() < 3 || std::abs(area2) < 1e-9 * scale * scale) {
    e = thin_ellipse(rel, opt.min_semi_axis);
  } else {
    const int it = khachiyan_weights(pts, opt, &u);
    if (iterations) *iterations = it;
    if (!ellipse_from_weights(pts, u, scale, &e)) e = thin_ellipse(rel, opt.min_semi_axis);
  }
  e.cx += ref.x;
  e.cy += ref.y;
  return e;
}

}  // namespace evade::tracking
