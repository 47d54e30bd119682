#include "prediction/inflation.h"

#include <algorithm>
#include <cmath>

namespace evade::prediction {
namespace {

// g(s) and g'(s), see the header.
void g_and_derivative(double a, double b, double s, double* g, double* dg) {
  const double c = a + b;
  const double d = 2.0 * a * b;
  const double num = 2.0 * s * s * (c * s + d);
  const double den = c * (c + 2.0 * s);
  *g = num / den;
  const double dnum = 2.0 * (3.0 * c * s * s + 2.0 * d * s);
  const double dden = 2.0 * c;
  *dg = (dnum * den - num * dden) / (den * den);
}

}  // namespace

double inflation_residual(double a, double b, double r, double sigma) {
  const double s = sigma + r;
  return 2.0 * s * s * ((a + b) * s + 2.0 * a * b) / ((a + b) * (a + b + 2.0 * s)) - r * r;
}

Inflation solve_inflation(double a, double b, double r, double tol) {
  Inflation out;
  if (!(r > 0.0)) return out;  // no uncertainty, no inflation (also catches NaN)
  const double target = r * r;
  double lo = r;                                       // g(r) <= r^2
  double hi = r * (a + b) / (2.0 * std::sqrt(a * b));  // g(hi) >= r^2
  if (hi - lo <= tol) {                                // (near-)circle: the root is r itself
    out.total = r;
    out.sigma_min = 0.0;
    return out;
  }
  double s = 0.5 * (lo + hi);
  constexpr int kMaxIterations = 200;
  for (int it = 1; it <= kMaxIterations; ++it) {
    out.iterations = it;
    double g, dg;
    g_and_derivative(a, b, s, &g, &dg);
    const double h = g - target;
    if (h == 0.0) break;
    if (h < 0.0)
      lo = s;
    else
      hi = s;
    double next = s - h / dg;
    if (!(dg > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const double step = std::fabs(next - s);
    s = next;
    if (step < tol || hi - lo < tol) break;
  }
  out.total = s;
  out.sigma_min = std::max(0.0, s - r);
  return out;
}

double chi_square_2dof_quantile(double p) { return -2.0 * std::log1p(-p); }

double normal_two_sided_quantile(double p) {
  // P(|Z| <= z) = erf(z / sqrt 2) is increasing in z: bisection.
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200 && hi - lo > 1e-14; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (std::erf(mid / std::sqrt(2.0)) < p)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

double position_radius(double pxx, double pxy, double pyy, double chi2_2dof) {
  const double mean = 0.5 * (pxx + pyy);
  const double half_diff = 0.5 * (pxx - pyy);
  const double lambda_max = mean + std::sqrt(half_diff * half_diff + pxy * pxy);
  return std::sqrt(chi2_2dof * std::max(0.0, lambda_max));
}

double shape_radius(double var_a, double var_b, double var_theta, double elongation, double z) {
  const double v = std::max(std::max(var_a, var_b), 0.0) + elongation * elongation * std::max(var_theta, 0.0);
  return z * std::sqrt(v);
}

double combined_radius(double r_p, double r_eta, const std::string& combine) {
  if (combine == "rss") return std::hypot(r_p, r_eta);
  if (combine == "position") return r_p;
  return r_p + r_eta;
}

}  // namespace evade::prediction
