// Uncertainty radius of a predicted ellipse and the paper's inflation
// sigma_min (section III-B, "Trajectory prediction", last equation).
//
// The paper writes, for an ellipse with semi-axes a, b and uncertainty r:
//   2 (sigma+r)^2 ((a+b)(sigma+r) + 2ab) / ((a+b)(a+b+2 sigma+2 r)) - r^2 = 0.
// With s = sigma + r this is g(s) = r^2, g(s) = 2 s^2 ((a+b)s + 2ab) / ((a+b)(a+b+2s)).
// g is strictly increasing for s > 0 and 4ab/(a+b)^2 s^2 <= g(s) <= s^2, so the
// root lies in [r, r (a+b) / (2 sqrt(ab))]: sigma_min >= 0 is the extra beyond r
// and the axes grow by s = r + sigma_min. For a circle (a = b) sigma_min = 0
// and the result is the exact Minkowski sum with a disc of radius r; for an
// elongated ellipse the enlarged ellipse (a+s, b+s) is the smallest of that
// family that still contains the Minkowski sum (checked in the tests).
#pragma once

#include <string>

namespace evade::prediction {

// Left-hand side of the paper's equation at sigma (0 at sigma_min).
double inflation_residual(double a, double b, double r, double sigma);

struct Inflation {
  double sigma_min = 0.0;  // root of the paper's equation (>= 0)
  double total = 0.0;      // r + sigma_min: what is added to both semi-axes
  int iterations = 0;
};

// Safeguarded Newton inside a shrinking bracket (bisection whenever the
// Newton step leaves it), until the step or the bracket is below tol.
// a, b > 0, r >= 0.
Inflation solve_inflation(double a, double b, double r, double tol);

// Quantiles of the chi-square distribution used for the confidence radii.
double chi_square_2dof_quantile(double p);   // exact: -2 ln(1 - p)
double normal_two_sided_quantile(double p);  // z with P(|N(0,1)| <= z) = p

// r_p: radius of the circle enclosing the position confidence ellipse
// (covariance [[pxx, pxy], [pxy, pyy]]): sqrt(chi2_2(p) * lambda_max).
double position_radius(double pxx, double pxy, double pyy, double chi2_2dof);

// r_eta: how far the boundary may move because of shape uncertainty:
// z * sqrt(max(var_a, var_b) + (a - b)^2 var_theta); (a - b) * dtheta is the
// largest boundary displacement a rotation dtheta causes.
double shape_radius(double var_a, double var_b, double var_theta, double elongation, double z);

// One radius from r_p and r_eta: "sum" r_p + r_eta (the paper), "rss"
// sqrt(r_p^2 + r_eta^2), "position" r_p.
double combined_radius(double r_p, double r_eta, const std::string& combine);

}  // namespace evade::prediction
