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

// An ellipse: semi-axes a >= b, orientation theta in [-pi/2, pi/2).
struct Ellipse {
  double a = 0.0, b = 0.0, theta = 0.0;
};

// What one predicted step publishes: the ellipse and the uncertainty radius
// sigma (r_p + r_eta + sigma_min: the body's axes grown by it hold the
// position region at the confidence level).
struct PublishedStep {
  Ellipse ellipse;
  double sigma = 0.0;
};

// How the published ellipse of one step is made.
struct StepRule {
  double chi2_2dof = 0.0;      // position quantile
  double tolerance = 1e-9;     // root finder
  double min_axis_m = 0.05;    // floor of the confidence ellipse's axes
  double max_inflation = 0.0;  // > 0: the body grown by min(sigma, this), never oriented
  bool oriented = false;       // also try the confidence ellipse grown by the body's circumradius
};

// The step's ellipse holding body (+) shape disc r_eta (+) the position
// confidence region of covariance [[pxx, pxy], [pxy, pyy]]: the body grown
// by the region's enclosing circle (the paper's), or, when smaller and
// rule.oriented, the region's own ellipse grown by body.a + r_eta.
PublishedStep published_step(const Ellipse& body, double pxx, double pxy, double pyy, double r_eta,
                             const StepRule& rule);

// The spread of a manoeuvre over t seconds for a mover of velocity
// (vx, vy): std along_std * speed * t along its heading and across_std *
// speed * t across it, as a covariance added to (pxx, pxy, pyy).
void add_manoeuvre_spread(double vx, double vy, double t, double along_std, double across_std, double* pxx, double* pxy,
                          double* pyy);

}  // namespace evade::prediction
