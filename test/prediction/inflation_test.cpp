// sigma_min: satisfies the paper's equation, is monotone in r, gives the exact
// Minkowski sum for a circle and a tight bound for elongated ellipses.
#include "prediction/inflation.h"

#include <gtest/gtest.h>

#include <cmath>

namespace evade::prediction {
namespace {

constexpr double kTol = 1e-9;

TEST(Inflation, SigmaMinSatisfiesThePaperEquationTo1e9) {
  for (double a : {0.1, 0.3, 1.0, 2.5})
    for (double ratio : {1.0, 0.8, 0.5, 0.2, 0.05})
      for (double r : {0.001, 0.02, 0.1, 0.5, 2.0}) {
        const double b = a * ratio;
        const Inflation inf = solve_inflation(a, b, r, kTol);
        EXPECT_GE(inf.sigma_min, 0.0);
        EXPECT_NEAR(inf.total, inf.sigma_min + r, 1e-15 + 1e-12 * r);
        // The root is bracketed within the tolerance: the residual changes sign
        // across [sigma - tol, sigma + tol] (the residual is increasing in sigma).
        EXPECT_LE(inflation_residual(a, b, r, inf.sigma_min - kTol), 0.0) << a << " " << b << " " << r;
        EXPECT_GE(inflation_residual(a, b, r, inf.sigma_min + kTol), 0.0) << a << " " << b << " " << r;
        EXPECT_LT(inf.iterations, 60);
      }
}

TEST(Inflation, CircleGivesTheExactMinkowskiSum) {
  for (double r : {0.01, 0.3, 1.7}) {
    const Inflation inf = solve_inflation(0.4, 0.4, r, kTol);
    EXPECT_NEAR(inf.sigma_min, 0.0, 1e-12);
    EXPECT_NEAR(inf.total, r, 1e-12);
  }
}

TEST(Inflation, ZeroUncertaintyNoInflation) {
  const Inflation inf = solve_inflation(0.5, 0.2, 0.0, kTol);
  EXPECT_EQ(inf.total, 0.0);
  EXPECT_EQ(inf.sigma_min, 0.0);
}

// Every point of the Minkowski sum of the ellipse (a, b) and a disc of radius r
// (boundary point + r * outward normal) lies inside the inflated ellipse
// (a + total, b + total), and some point touches it: the bound is tight.
TEST(Inflation, InflatedEllipseBoundsTheMinkowskiSumTightly) {
  const double kPi = 3.14159265358979323846;
  for (double a : {0.5, 1.0, 2.0})
    for (double ratio : {0.9, 0.5, 0.15})
      for (double r : {0.05, 0.2, 0.6}) {
        const double b = a * ratio;
        const double s = solve_inflation(a, b, r, kTol).total;
        double worst = 0.0;
        for (int i = 0; i < 20000; ++i) {
          const double t = 2.0 * kPi * i / 20000.0;
          const double x = a * std::cos(t), y = b * std::sin(t);
          double nx = x / (a * a), ny = y / (b * b);
          const double n = std::hypot(nx, ny);
          nx /= n;
          ny /= n;
          const double px = x + r * nx, py = y + r * ny;
          worst = std::max(worst, px * px / ((a + s) * (a + s)) + py * py / ((b + s) * (b + s)));
        }
        EXPECT_LE(worst, 1.0 + 1e-9) << a << " " << b << " " << r;
        EXPECT_GE(worst, 1.0 - 1e-6) << a << " " << b << " " << r;
        // and inflating by r alone would NOT contain it when the ellipse is elongated
        if (ratio < 0.6) {
          EXPECT_GT(s, r + 1e-4);
        }
      }
}

TEST(Inflation, MonotoneInR) {
  for (double ratio : {1.0, 0.5, 0.1}) {
    double prev_total = 0.0, prev_sigma = 0.0;
    for (int i = 1; i <= 400; ++i) {
      const double r = 0.005 * i;
      const Inflation inf = solve_inflation(0.8, 0.8 * ratio, r, kTol);
      EXPECT_GT(inf.total, prev_total);
      EXPECT_GE(inf.sigma_min, prev_sigma - kTol);
      prev_total = inf.total;
      prev_sigma = inf.sigma_min;
    }
  }
}

TEST(Inflation, ConfidenceQuantilesKnownValues) {
  EXPECT_NEAR(chi_square_2dof_quantile(0.95), 5.991464547107979, 1e-12);
  EXPECT_NEAR(chi_square_2dof_quantile(0.99), 9.210340371976184, 1e-12);
  EXPECT_NEAR(normal_two_sided_quantile(0.95), 1.959963984540054, 1e-10);
  EXPECT_NEAR(normal_two_sided_quantile(0.6826894921370859), 1.0, 1e-10);
}

TEST(Inflation, RadiiFromCovariance) {
  // circle of variance 0.04: r_p = sqrt(chi2 * 0.04)
  EXPECT_NEAR(position_radius(0.04, 0.0, 0.04, 5.991464547107979), std::sqrt(5.991464547107979 * 0.04), 1e-12);
  // eigenvalues of [[2, 1], [1, 2]] are 1 and 3
  EXPECT_NEAR(position_radius(2.0, 1.0, 2.0, 1.0), std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(shape_radius(0.01, 0.04, 0.25, 0.2, 2.0), 2.0 * std::sqrt(0.04 + 0.04 * 0.25), 1e-12);
}

TEST(Inflation, CombinedRadiusSumRssOrPosition) {
  EXPECT_DOUBLE_EQ(combined_radius(0.12, 0.05, "sum"), 0.17);
  EXPECT_DOUBLE_EQ(combined_radius(0.12, 0.05, "rss"), 0.13);  // 0.0144 + 0.0025 = 0.13^2
  EXPECT_DOUBLE_EQ(combined_radius(0.12, 0.05, "position"), 0.12);
  // rss is never more than the sum and never less than either part
  for (double r_eta : {0.0, 0.01, 0.1, 1.0}) {
    EXPECT_LE(combined_radius(0.3, r_eta, "rss"), combined_radius(0.3, r_eta, "sum"));
    EXPECT_GE(combined_radius(0.3, r_eta, "rss"), std::max(0.3, r_eta));
  }
}

}  // namespace
}  // namespace evade::prediction
