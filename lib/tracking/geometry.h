// Minimum bounding ellipses (paper III-B "Obstacle parameterization").
#pragma once

#include <vector>

namespace evade::tracking {

struct Vec2 {
  double x = 0.0, y = 0.0;
};

// Ellipse {p : ((p - c) rotated by -theta) . diag(1/a^2, 1/b^2) . (...) <= 1}
struct Ellipse {
  double cx = 0.0, cy = 0.0;
  double a = 0.0;      // semi-major axis, m
  double b = 0.0;      // semi-minor axis, m (b <= a)
  double theta = 0.0;  // major-axis direction, rad, in [-pi/2, pi/2)
};

double wrap_half_pi(double a);  // to [-pi/2, pi/2): an ellipse's axis is a line, period pi

// Convex hull (Andrew's monotone chain), counter-clockwise, no collinear points.
std::vector<Vec2> convex_hull(std::vector<Vec2> pts);

// (p - c)^T A (p - c) for the ellipse's shape matrix A (1 = on the boundary).
double ellipse_level(const Ellipse& e, const Vec2& p);
double ellipse_area(const Ellipse& e);

struct MbeOptions {
  // Khachiyan / Todd-Yildirim stopping rule: every point's lifted Mahalanobis
  // weight within (1 + tolerance) of d + 1 and every support point's weight
  // within (1 - tolerance), which bounds the area above the true minimum by
  // a factor of about (1 + 1.5 tolerance) before the final exact scale-up.
  double tolerance = 1e-5;
  int max_iterations = 2000;
  // Semi-axis given to degenerate input (one point; collinear points).
  double min_semi_axis = 0.05;
};

// The minimum-area ellipse enclosing `pts`: Khachiyan's algorithm with
// Wolfe-Atwood away steps (Todd & Yildirim 2007) on the convex hull, then
// scaled about its centre so that every point lies inside (the farthest one
// on the boundary). Degenerate inputs give a thin ellipse of semi-minor axis
// options.min_semi_axis along the points.
Ellipse min_bounding_ellipse(const std::vector<Vec2>& pts, const MbeOptions& options, int* iterations = nullptr);

}  // namespace evade::tracking
