// The Ceres MPC solver: barrier derivatives, constraints met to 1e-3 when a
// feasible solution exists, obstacles passed with h >= 0, start inside
// d_safe escaped, never NaN.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "planning/ceres_solver.h"
#include "planning/ipopt_solver.h"
#include "planning/problem.h"
#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::bench_problem;
using testing::moving_obstacle;
using testing::straight_problem;

SolverOptions opts() { return SolverOptions{}; }

// From rest: the hard solve must fail (checked), then the relaxed solve,
// whose result is returned.
SolveResult elastic_where_hard_fails(const Problem& pb) {
  const CeresMpcSolver solver(opts());
  const std::vector<double> rest(2 * pb.N, 0.0);
  EXPECT_FALSE(solver.solve(pb, rest).feasible);
  return solver.solve_elastic(pb, rest);
}

// h(X_k, O_k), k = 0..N, along a solved plan.
std::vector<double> barriers_along(const Problem& pb, const ObstacleTrack& o, const SolveResult& r) {
  std::vector<double> h;
  for (int k = 0; k <= pb.N; ++k) h.push_back(barrier_at(o, k, r.states[3 * k], r.states[3 * k + 1], pb.d_safe).h);
  return h;
}

TEST(Barrier, LineEllipseDistanceMatchesThePaperFormula) {
  // l = sqrt(a^2 b^2 (1 + tan^2 d) / (b^2 + a^2 tan^2 d)), delta from the major axis
  const double a = 0.8, b = 0.3, theta = 0.4, cx = 1.0, cy = -2.0, r = 3.0;
  for (double delta : {0.1, 0.7, 1.2, 2.0, -0.5}) {
    const double px = cx + r * std::cos(theta + delta), py = cy + r * std::sin(theta + delta);
    const double t2 = std::tan(delta) * std::tan(delta);
    const double l = std::sqrt(a * a * b * b * (1 + t2) / (b * b + a * a * t2));
    EXPECT_NEAR(barrier(px, py, cx, cy, a, b, theta, 0.2).h, r - l - 0.2, 1e-12) << delta;
  }
  // along the axes: l = a and l = b
  EXPECT_NEAR(barrier(cx + r * std::cos(theta), cy + r * std::sin(theta), cx, cy, a, b, theta, 0).h, r - a, 1e-12);
  EXPECT_NEAR(barrier(cx - r * std::sin(theta), cy + r * std::cos(theta), cx, cy, a, b, theta, 0).h, r - b, 1e-12);
}

TEST(Barrier, GradientAndHessianMatchFiniteDifferences) {
  const double a = 0.7, b = 0.4, theta = -0.9, cx = 0.3, cy = 0.2, ds = 0.3, e = 1e-6;
  for (auto [px, py] : {std::pair{1.5, 0.7}, std::pair{-0.4, 1.1}, std::pair{0.5, -2.0}}) {
    const BarrierValue v = barrier(px, py, cx, cy, a, b, theta, ds, true);
    const BarrierValue xp = barrier(px + e, py, cx, cy, a, b, theta, ds, true);
    const BarrierValue xm = barrier(px - e, py, cx, cy, a, b, theta, ds, true);
    const BarrierValue yp = barrier(px, py + e, cx, cy, a, b, theta, ds, true);
    const BarrierValue ym = barrier(px, py - e, cx, cy, a, b, theta, ds, true);
    EXPECT_NEAR(v.gx, (xp.h - xm.h) / (2 * e), 1e-6);
    EXPECT_NEAR(v.gy, (yp.h - ym.h) / (2 * e), 1e-6);
    EXPECT_NEAR(v.hxx, (xp.gx - xm.gx) / (2 * e), 1e-5);
    EXPECT_NEAR(v.hxy, (yp.gx - ym.gx) / (2 * e), 1e-5);
    EXPECT_NEAR(v.hyy, (yp.gy - ym.gy) / (2 * e), 1e-5);
  }
}

// The footprint's h (problem.h): derivatives in x, y and yaw of the
// nearest disc, at poses where one disc is clearly the nearest.
TEST(Barrier, FootprintDerivativesMatchFiniteDifferences) {
  const Footprint fp = Footprint::covering(0.93, 0.70, 3);
  const double a = 0.6, b = 0.3, theta = 0.5, cx = 2.0, cy = 1.0, ds = 0.15, e = 1e-6;
  const double c = std::cos(theta), s_ = std::sin(theta);
  auto at = [&](double x, double y, double yaw) {
    return footprint_barrier_cs(x, y, yaw, cx, cy, a, b, c, s_, fp, ds, true);
  };
  for (auto [px, py, yaw] : {std::tuple{0.0, 0.0, 0.3}, std::tuple{3.5, 2.5, -2.0}, std::tuple{2.0, -1.0, 1.4}}) {
    const BarrierValue v = at(px, py, yaw);
    const BarrierValue xp = at(px + e, py, yaw), xm = at(px - e, py, yaw);
    const BarrierValue yp = at(px, py + e, yaw), ym = at(px, py - e, yaw);
    const BarrierValue tp = at(px, py, yaw + e), tm = at(px, py, yaw - e);
    EXPECT_NEAR(v.gx, (xp.h - xm.h) / (2 * e), 1e-6);
    EXPECT_NEAR(v.gy, (yp.h - ym.h) / (2 * e), 1e-6);
    EXPECT_NEAR(v.gth, (tp.h - tm.h) / (2 * e), 1e-6);
    EXPECT_NEAR(v.hxt, (tp.gx - tm.gx) / (2 * e), 1e-5);
    EXPECT_NEAR(v.hyt, (tp.gy - tm.gy) / (2 * e), 1e-5);
    EXPECT_NEAR(v.htt, (tp.gth - tm.gth) / (2 * e), 1e-5);
    EXPECT_NE(v.gth, 0.0);  // an end disc: yaw matters
  }
}

// barrier_slack (the most clearance's shortfall, PLAN.obstacle_slack) is
// the smallest of an obstacle's D-CBF constraints g >= 0 over the horizon:
// negative for a plan that drives on at a bike coming head-on, positive
// for one that stays clear of an obstacle beside the path.
TEST(Barrier, SlackIsTheSmallestOfAnObstaclesConstraints) {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.obstacles.push_back(moving_obstacle(1, 3.0, 0.0, -4.0, 0.0, 0.9, 0.4, 0.0, 0.9, pb.N, pb.dt));
  pb.obstacles.push_back(moving_obstacle(2, 2.0, 2.5, 0.0, 0.0, 0.3, 0.3, 0.0, 0.9, pb.N, pb.dt));
  std::vector<double> u(pb.num_controls());
  for (int k = 0; k < pb.N; ++k) u[2 * k] = 0.8;
  std::vector<double> states, g;
  evaluate_constraints(pb, u.data(), &states, &g);
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    const auto first = g.begin() + pb.num_rate_constraints() + static_cast<int>(i) * pb.N;
    EXPECT_NEAR(barrier_slack(pb, pb.obstacles[i], states), *std::min_element(first, first + pb.N), 1e-12);
  }
  EXPECT_LT(barrier_slack(pb, pb.obstacles[0], states), -0.1);
  EXPECT_GT(barrier_slack(pb, pb.obstacles[1], states), 0.0);
}

// evaluate_constraints computes each barrier once for both links that use
// it; every g_j is constraint<double>'s bit for bit: point robot and
// footprint, decay 0 and not, the own-motion form, relaxations, reach bounds.
TEST(Barrier, EvaluatedConstraintsAreEachConstraintsValue) {
  for (int variant = 0; variant < 5; ++variant) {
    Problem pb = straight_problem(0.1, -0.2, 0.3, 0.6, 0.8);
    if (variant != 0) pb.footprint = Footprint::covering(0.93, 0.70, 3);
    pb.obstacles.push_back(
        moving_obstacle(1, 2.5, 0.4, -1.2, 0.1, 0.5, 0.3, 0.4, variant == 1 ? 0.0 : 0.9, pb.N, pb.dt));
    pb.obstacles.push_back(moving_obstacle(2, 1.0, -0.5, 0.0, 0.0, 0.3, 0.3, 0.0, 0.8, pb.N, pb.dt));
    pb.own_motion = variant == 2;
    if (variant == 3) {
      pb.relax.assign(pb.num_constraints(), 0.0);
      for (size_t j = 0; j < pb.relax.size(); ++j) pb.relax[j] = 0.01 * static_cast<double>(j % 7);
    }
    if (variant == 4) {
      ReachBound r;
      r.x = 2.0, r.y = 0.5, r.a = 0.3, r.b = 0.25, r.theta = 0.2, r.speed_mps = 1.2, r.reaction_s = 0.2;
      r.decel_mps2 = 1.5, r.offset_m = 0.3, r.radius_m = 0.25;
      r.allowance_m.assign(pb.N, 0.05);
      pb.reach.push_back(r);
    }
    std::vector<double> u(pb.num_controls());
    for (int k = 0; k < pb.N; ++k) u[2 * k] = 0.5 + 0.01 * k, u[2 * k + 1] = 0.3 * std::sin(0.4 * k);
    std::vector<double> states, g;
    evaluate_constraints(pb, u.data(), &states, &g);
    ASSERT_EQ(static_cast<int>(g.size()), pb.num_constraints());
    int inside = 0;
    for (int j = 0; j < pb.num_constraints(); ++j) {
      EXPECT_EQ(g[j], constraint(pb, states.data(), u.data(), j)) << "variant " << variant << " j " << j;
      if (g[j] < 0) ++inside;
    }
    EXPECT_GT(inside, 0) << "variant " << variant;  // the head-on mover is met: some links fail
  }
}

// Covering discs hold the whole rectangle, and against a round obstacle h
// + d_safe is the body's clearance less at most the discs' excess.
TEST(Footprint, CoveringDiscsHoldTheRectangle) {
  for (int n : {1, 2, 3, 5}) {
    const double L = 0.93, W = 0.70;
    const Footprint fp = Footprint::covering(L, W, n);
    ASSERT_EQ(fp.offsets.size(), static_cast<size_t>(n));
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) {
        const double x = -L / 2 + L * i / 40, y = -W / 2 + W * j / 40;
        double nearest = 1e9;
        for (double o : fp.offsets) nearest = std::min(nearest, std::hypot(x - o, y));
        EXPECT_LE(nearest, fp.radius + 1e-12) << n << " discs, point " << x << ", " << y;
      }
  }
  const Footprint fp = Footprint::covering(0.93, 0.70, 3);
  EXPECT_NEAR(fp.radius, std::hypot(0.155, 0.35), 1e-12);
  const double ds = 0.15, r = 0.25;
  // beside the middle: the clearance less the excess radius - W/2
  const double side = footprint_barrier_cs(0, 0, 0, 0, 1.0, r, r, 1, 0, fp, ds).h;
  EXPECT_NEAR(side + ds, (1.0 - 0.35 - r) - (fp.radius - 0.35), 1e-12);
  // ahead, the robot turned by 90 deg: the front disc's centre at (0, 0.31)
  const double ahead = footprint_barrier_cs(0, 0, M_PI / 2, 0, 1.0, r, r, 1, 0, fp, ds).h;
  EXPECT_NEAR(ahead + ds, 1.0 - 0.31 - fp.radius - r, 1e-12);
  EXPECT_LE(ahead + ds, 1.0 - 0.465 - r);  // never more than the true clearance
}

TEST(CeresSolver, AnalyticJacobianMatchesFiniteDifferences) {
  // every residual kind: tracking, controls, rates, rate limits and
  // barriers (CBF and distance form) switched on by large multipliers
  Problem pb = bench_problem(8);
  pb.obstacles[1].decay = 0.0;
  ReachBound reach;  // a mover 2 m ahead, 0.6 m aside
  reach.x = 2.0, reach.y = 0.6, reach.a = 0.35, reach.b = 0.25, reach.theta = 0.4;
  reach.speed_mps = 1.2, reach.reaction_s = 0.2, reach.decel_mps2 = 1.5, reach.offset_m = 0.14, reach.radius_m = 0.17;
  reach.allowance_m.assign(static_cast<size_t>(pb.N), 0.05);
  pb.reach.push_back(reach);
  const int n = pb.num_controls(), m = pb.num_constraints();
  std::vector<double> u(n);
  for (int k = 0; k < pb.N; ++k) {
    u[2 * k] = 0.5 + 0.3 * std::sin(0.7 * k);
    u[2 * k + 1] = 0.4 * std::cos(0.5 * k);
  }
  const double rho = 50.0;
  const std::vector<double> lambda(m, 1e3);  // lambda / rho = 20 > g: every AL residual on
  std::vector<double> r, jac;
  ASSERT_TRUE(evaluate_inner_residuals(pb, u.data(), lambda, rho, &r, &jac));
  const int nr = static_cast<int>(r.size());
  ASSERT_EQ(nr, num_cost_residuals(pb) + m);
  const double e = 1e-6;
  int nonzero = 0;
  for (int i = 0; i < n; ++i) {
    std::vector<double> up = u, um = u, rp, rm;
    up[i] += e;
    um[i] -= e;
    ASSERT_TRUE(evaluate_inner_residuals(pb, up.data(), lambda, rho, &rp, nullptr));
    ASSERT_TRUE(evaluate_inner_residuals(pb, um.data(), lambda, rho, &rm, nullptr));
    for (int row = 0; row < nr; ++row) {
      const double fd = (rp[row] - rm[row]) / (2 * e);
      const double an = jac[static_cast<size_t>(row) * n + i];
      EXPECT_NEAR(an, fd, 1e-5 * std::max(1.0, std::fabs(fd))) << "row " << row << " control " << i;
      if (std::fabs(an) > 1e-9) ++nonzero;
    }
  }
  EXPECT_GT(nonzero, nr);  // the check covered real derivatives
  // each AL residual is -sqrt(rho) (g_j - lambda_j / rho) with g_j the
  // constraint that feasibility is judged by (problem.h)
  std::vector<double> states, g;
  evaluate_constraints(pb, u.data(), &states, &g);
  const int nc = num_cost_residuals(pb);
  for (int j = 0; j < m; ++j)
    EXPECT_NEAR(r[static_cast<size_t>(nc + j)], -std::sqrt(rho) * (g[static_cast<size_t>(j)] - lambda[j] / rho), 1e-9)
        << "constraint " << j;
}

TEST(CeresSolver, FreePathTracksTheReference) {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  CeresMpcSolver solver(opts());
  SolveResult r = solver.solve(pb, std::vector<double>(2 * pb.N, 0.0));
  ASSERT_TRUE(r.feasible);
  // Cruising at the reference speed: v stays near 0.8, no turning.
  for (int k = 0; k < pb.N; ++k) {
    EXPECT_NEAR(r.u[2 * k], 0.8, 0.1) << k;
    EXPECT_NEAR(r.u[2 * k + 1], 0.0, 1e-3) << k;
  }
  EXPECT_NEAR(r.states[3 * pb.N], pb.ref_x[pb.N], 0.2);
}

// From rest with the reference running ahead at 0.8 m/s the optimum speeds
// up at the acceleration limit (1 m/s^2: 0.1 m/s per step) until it is near
// the reference speed. The acceleration limits are a chain of constraints
// in the AL loop; a multiplier that overestimates one keeps it off its
// bound while the plan is already feasible (the ramp came out at 3/4 of the
// limit, 32 % costlier, before the loop checked complementarity).
TEST(CeresSolver, FromRestThePlanAcceleratesAtTheLimit) {
  const Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  for (LineSearchInterpolation ls :
       {LineSearchInterpolation::kBisection, LineSearchInterpolation::kQuadratic, LineSearchInterpolation::kCubic}) {
    SolverOptions o = opts();
    o.line_search_interpolation = ls;
    const SolveResult r = CeresMpcSolver(o).solve(pb, std::vector<double>(2 * pb.N, 0.0));
    ASSERT_TRUE(r.feasible) << static_cast<int>(ls);
    for (int k = 0; k < 7; ++k)
      EXPECT_NEAR(r.u[2 * k], pb.lim.accel * pb.dt * (k + 1), 5e-3)
          << "line search " << static_cast<int>(ls) << ", step " << k;
  }
}

TEST(CeresSolver, StaticObstacleOnThePathIsPassedWithPositiveBarrier) {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.obstacles.push_back(moving_obstacle(1, 3.0, 0.05, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt));
  CeresMpcSolver solver(opts());
  SolveResult r = solver.solve(pb, std::vector<double>(2 * pb.N, 0.0));
  ASSERT_TRUE(r.feasible) << r.max_violation;
  EXPECT_LE(r.max_violation, 1e-3);
  // h >= 0 at every step (CBF from h0 >= 0 keeps h >= 0 up to the tolerance)
  for (int k = 0; k <= pb.N; ++k)
    EXPECT_GE(barrier_at(pb.obstacles[0], k, r.states[3 * k], r.states[3 * k + 1], pb.d_safe).h, -1e-3) << k;
  // and so does the plan's own minimum
  EXPECT_GE(r.min_barrier, -1e-3);
}

TEST(CeresSolver, EveryBenchmarkProblemSolvesWithinTolerance) {
  CeresMpcSolver solver(opts());
  for (int k : {0, 4, 8, 16}) {
    Problem pb = bench_problem(k);
    SolveResult r = solver.solve(pb, std::vector<double>(2 * pb.N, 0.0));
    EXPECT_TRUE(r.finite);
    EXPECT_TRUE(r.feasible) << k << " obstacles: violation " << r.max_violation;
    EXPECT_LE(r.max_violation, 1e-3) << k;
  }
}

TEST(CeresSolver, StartInsideSafeDistanceElasticPlanIncreasesH) {
  // Obstacle behind-left, robot at rest 15 cm inside d_safe: the hard D-CBF
  // asks h(X_1) >= (1 - gamma) h(X_0), i.e. 1.5 cm of growth in the first
  // step, but from rest the robot can move only accel dt^2 = 1 cm.
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  const double c = std::cos(2.5), s = std::sin(2.5);
  const double r0 = 0.3 + pb.d_safe - 0.15;  // centre distance giving h0 = -0.15
  pb.obstacles.push_back(moving_obstacle(1, r0 * c, r0 * s, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt));
  const double h0 = barrier_at(pb.obstacles[0], 0, 0, 0, pb.d_safe).h;
  ASSERT_NEAR(h0, -0.15, 1e-9);
  // started from braking to a stop (here: standing still)
  const SolveResult r = elastic_where_hard_fails(pb);
  ASSERT_TRUE(r.finite);
  EXPECT_TRUE(r.feasible);  // for the shifted barrier
  const std::vector<double> h = barriers_along(pb, pb.obstacles[0], r);
  for (int k = 1; k <= pb.N; ++k) EXPECT_GE(h[k], h[k - 1] - 1e-3) << k;  // h never shrinks
  EXPECT_GT(h[5], h0);                                                    // it grows early
  EXPECT_GT(h.back(), 0.0);                                               // out of d_safe by the end
}

TEST(CeresSolver, RelaxationOfAStartInsideDSafeKeepsHFromFalling) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  pb.obstacles.push_back(moving_obstacle(1, -0.5, 0.0, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt));  // h0 = -0.1
  pb.obstacles.push_back(moving_obstacle(2, 3.0, 2.0, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt));   // far, static
  const double h0 = barrier_at(pb.obstacles[0], 0, 0, 0, pb.d_safe).h;
  ASSERT_LT(h0, 0.0);
  const std::vector<double> relax = barrier_relaxation(pb, opts());
  ASSERT_EQ(static_cast<int>(relax.size()), pb.num_constraints());
  const int R = pb.num_rate_constraints();
  for (int j = 0; j < R; ++j) EXPECT_EQ(relax[j], 0.0);
  for (int k = 0; k < pb.N; ++k) {
    EXPECT_NEAR(relax[R + k], -(1.0 - 0.9) * h0, 1e-12) << k;  // h may not fall below its start
    EXPECT_EQ(relax[R + pb.N + k], 0.0) << k;                  // standing meets it
  }
}

// A mover coming at the robot with a swelling ellipse: standing misses its
// barrier, but neither its motion nor its swelling is excused; only a start
// inside d_safe would be.
TEST(CeresSolver, RelaxationExcusesNothingOfAMoverOutsideDSafe) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  ObstacleTrack o = moving_obstacle(1, 1.0, 0.0, -1.0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  for (int k = 0; k <= pb.N; ++k) o.a[k] = o.b[k] = 0.3 + 0.6 * k / pb.N;
  pb.obstacles.push_back(o);
  ASSERT_GT(barrier_at(o, 0, 0, 0, pb.d_safe).h, 0.0);
  pb.obstacles[0].age_s = 10.0;
  const std::vector<double> relax = barrier_relaxation(pb, opts());
  for (double s : relax) EXPECT_EQ(s, 0.0);
  // counted as static (threshold above its 1 m/s): its swelling, which
  // takes h from 0.4 to -0.2 at the robot's place, is excused...
  SolverOptions slow = opts();
  slow.relax_max_obstacle_speed_mps = 2.0;
  const std::vector<double> held = barrier_relaxation(pb, slow);
  EXPECT_GT(*std::max_element(held.begin(), held.end()), 0.0);
  // ...but not while the track is new: its velocity is not known yet
  pb.obstacles[0].age_s = 0.5;
  for (double s : barrier_relaxation(pb, slow)) EXPECT_EQ(s, 0.0);
}

// A static obstacle beside the path whose predicted ellipse swells with
// its uncertainty (0.3 m to 0.8 m over the horizon): even a robot standing
// where it is misses the D-CBF, so the hard problem has no solution. The
// relaxed one has: the D-CBF holds on h + w_k, the barrier with the
// swelling (seen from the start) added back, and the robot moves on.
TEST(CeresSolver, SwellingObstacleElasticPlanMeetsTheDcbfOnTheObstacleAsItIs) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  ObstacleTrack o = moving_obstacle(1, 0.8, 0.5, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  for (int k = 0; k <= pb.N; ++k) o.a[k] = o.b[k] = 0.3 + 0.5 * k / pb.N;
  o.age_s = 10.0;  // long tracked
  pb.obstacles.push_back(o);
  std::vector<double> w;  // swelling seen from the start
  for (int k = 0; k <= pb.N; ++k)
    w.push_back(barrier_at(o, 0, 0, 0, pb.d_safe).h - barrier_at(o, k, 0, 0, pb.d_safe).h);
  ASSERT_GT(barrier_at(o, 0, 0, 0, pb.d_safe).h, 0.0);
  ASSERT_LT(barrier_at(o, pb.N, 0, 0, pb.d_safe).h, 0.0);  // standing ends inside d_safe
  const std::vector<double> relax = barrier_relaxation(pb, opts());
  EXPECT_GT(*std::max_element(relax.begin(), relax.end()), 0.0);

  const SolveResult r = elastic_where_hard_fails(pb);
  ASSERT_TRUE(r.finite);
  EXPECT_TRUE(r.feasible);  // for the relaxed barrier
  std::vector<double> h = barriers_along(pb, o, r);
  for (int k = 0; k <= pb.N; ++k) h[k] += w[k];
  for (int k = 0; k < pb.N; ++k) EXPECT_GE(h[k + 1], 0.9 * h[k] - 1e-3) << k;
  EXPECT_GT(r.states[3 * pb.N], 0.5);  // on its way, not standing
}

// hold_settled: a bin beside the path, still for long and predicted still,
// whose ellipse swells with its velocity's uncertainty (0.3 m to 0.8 m
// over the horizon, as the predictor's does up to max_inflation_m). Standing
// where it is, the robot misses the hard D-CBF of the later steps, so the
// hard problem has no solution at all. Held at its ellipse of step 0, the
// bin is a constraint the robot meets standing and drives past; a mover, a
// track too new to have a known velocity and a walker tracked for long who
// has stood for a moment only keep their prediction.
TEST(CeresSolver, HoldingASettledObstacleLetsTheRobotStandAndPassBesideIt) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  ObstacleTrack bin = moving_obstacle(1, 0.8, 0.6, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  for (int k = 0; k <= pb.N; ++k) bin.a[k] = bin.b[k] = 0.3 + 0.5 * k / pb.N;
  bin.sigma.assign(pb.N + 1, 0.0);
  for (int k = 0; k <= pb.N; ++k) bin.sigma[k] = 0.1 + 0.5 * k / pb.N;
  bin.age_s = bin.still_s = 10.0;
  ObstacleTrack mover = moving_obstacle(2, 3.0, -2.0, 0, 1.0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  mover.age_s = mover.still_s = 10.0;
  ObstacleTrack fresh = moving_obstacle(3, 4.0, 2.0, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  for (int k = 0; k <= pb.N; ++k) fresh.a[k] = 0.3 + 0.5 * k / pb.N;
  fresh.age_s = fresh.still_s = 0.5;
  // a walker turning round: 1 m/s out and back, ending where it began
  ObstacleTrack turning = moving_obstacle(4, -2.0, 2.0, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  for (int k = 0; k <= pb.N; ++k) turning.x[k] = -2.0 + pb.dt * std::min(k, pb.N - k);
  turning.age_s = turning.still_s = 10.0;
  // a walker tracked for long, predicted still, standing for a second
  ObstacleTrack paused = moving_obstacle(5, 4.0, -2.5, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt);
  for (int k = 0; k <= pb.N; ++k) paused.a[k] = 0.3 + 0.5 * k / pb.N;
  paused.age_s = 10.0;
  paused.still_s = 1.0;
  pb.obstacles = {bin, mover, fresh, turning, paused};
  ASSERT_GT(barrier_at(bin, 0, 0, 0, pb.d_safe).h, 0.0);
  ASSERT_LT(barrier_at(bin, pb.N, 0, 0, pb.d_safe).h, 0.0);  // standing ends inside d_safe
  const std::vector<double> standing(2 * pb.N, 0.0);
  const CeresMpcSolver solver(opts());
  EXPECT_FALSE(solver.solve(pb, standing).feasible);  // as predicted: no plan at all

  Problem held = pb;
  EXPECT_EQ(hold_settled_obstacles(&held, opts()), 1);
  const ObstacleTrack& h = held.obstacles[0];
  for (int k = 0; k <= pb.N; ++k) {
    EXPECT_EQ(h.x[k], bin.x[0]);
    EXPECT_EQ(h.a[k], bin.a[0]);
    EXPECT_EQ(h.b[k], bin.b[0]);
    EXPECT_EQ(h.sigma[k], bin.sigma[0]);
  }
  EXPECT_EQ(held.obstacles[1].y, mover.y);    // a mover goes on as predicted
  EXPECT_EQ(held.obstacles[2].a, fresh.a);    // a new track keeps its swelling
  EXPECT_EQ(held.obstacles[3].x, turning.x);  // so does a mover that turns round
  EXPECT_EQ(held.obstacles[4].a, paused.a);   // and a walker who has just stopped

  const SolveResult r = solver.solve(held, standing);
  ASSERT_TRUE(r.finite);
  EXPECT_TRUE(r.feasible);
  EXPECT_GT(r.states[3 * pb.N], 1.0);  // on its way past the bin
  EXPECT_GE(r.min_barrier, -1e-3);
}

// From rest 0.13 m outside d_safe of a static obstacle ahead-left, the AL
// loop ends a few mm outside the tolerance (the penalty at its cap) with a
// plan that swerves and drives on. The solve used to return its start
// (standing, cost 394) and the robot stood there for good; the farthest
// feasible point towards the last iterate then moved 0.10 m (cost 367).
// The projection onto the constraints keeps the loop's plan: measured cost
// 304 and 0.42 m over the horizon (IPOPT, cold, finds 279 and 0.53 m).
// Recovering, the plan grown from the previous one keeps its side of an
// obstacle unless another side is clearly cheaper: an obstacle 3 cm left of
// the path costs about the same to pass on either side, and a robot that
// takes the cheaper one afresh every cycle can turn back and forth in front
// of it (it did, in an oncoming e-bike's way).
TEST(CeresSolver, RecoveringKeepsThePreviousPlansSideOfAnObstacle) {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.obstacles.push_back(moving_obstacle(1, 1.5, 0.03, 0, 0, 0.3, 0.3, 0, 0.9, pb.N, pb.dt));
  // the previous plan, shifted: it swerves to the left (the costlier side)
  std::vector<double> left(2 * pb.N);
  for (int k = 0; k < pb.N; ++k) {
    left[2 * k] = 0.8;
    left[2 * k + 1] = k < 8 ? 0.4 : (k < 16 ? -0.4 : 0.0);
  }
  auto side_at_obstacle = [&](const SolveResult& r) {
    for (int k = 0; k <= pb.N; ++k)
      if (r.states[3 * k] >= 1.5) return r.states[3 * k + 1];
    return r.states[3 * pb.N + 1];
  };
  SolverOptions keep = opts(), cheapest = opts();
  cheapest.recovery_switch_ratio = 1.0;
  const SolveResult kept = CeresMpcSolver(keep).solve_elastic(pb, left);
  const SolveResult fresh = CeresMpcSolver(cheapest).solve_elastic(pb, left);
  ASSERT_TRUE(kept.feasible);
  ASSERT_TRUE(fresh.feasible);
  EXPECT_GT(side_at_obstacle(kept), 0.3);    // left, as the previous plan
  EXPECT_LT(side_at_obstacle(fresh), -0.3);  // the cheapest: right
  EXPECT_LT(fresh.cost, kept.cost);
  EXPECT_GT(fresh.cost, keep.recovery_switch_ratio * kept.cost);  // not clearly cheaper
}

TEST(CeresSolver, ColdStartBesideAnObstacleDoesNotReturnTheStart) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  pb.d_safe = 0.35;
  pb.obstacles.push_back(moving_obstacle(1, 0.8, 0.38, 0, 0, 0.41, 0.41, 0, 0.9, pb.N, pb.dt));
  ASSERT_NEAR(barrier_at(pb.obstacles[0], 0, 0, 0, pb.d_safe).h, 0.126, 0.001);
  const std::vector<double> rest(2 * pb.N, 0.0);
  const double standing = objective(pb, rest.data());
  const SolveResult r = CeresMpcSolver(opts()).solve(pb, rest);
  std::printf(
      "[figures] cold start beside an obstacle: cost %.1f (standing %.1f), x_N %.2f m, %d iterations, %d outer\n",
      r.cost, standing, r.states[3 * pb.N], r.iterations, r.outer_iterations);
  ASSERT_TRUE(r.feasible);
  EXPECT_LT(r.cost, 0.85 * standing);
  EXPECT_GT(r.states[3 * pb.N], 0.3);  // driving on, not creeping
  EXPECT_LE(r.max_violation, 1e-4);    // the projection ends below target_violation
}

// Without the projection the same solve falls back to the segment search
// and keeps much less: the projection is what gets the plan above.
TEST(CeresSolver, ProjectionKeepsMoreThanTheSegmentSearch) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  pb.d_safe = 0.35;
  pb.obstacles.push_back(moving_obstacle(1, 0.8, 0.38, 0, 0, 0.41, 0.41, 0, 0.9, pb.N, pb.dt));
  const std::vector<double> rest(2 * pb.N, 0.0);
  SolverOptions without = opts();
  without.projection_iterations = 0;
  const SolveResult with_projection = CeresMpcSolver(opts()).solve(pb, rest);
  const SolveResult segment_only = CeresMpcSolver(without).solve(pb, rest);
  ASSERT_TRUE(with_projection.feasible);
  ASSERT_TRUE(segment_only.feasible);
  EXPECT_LT(with_projection.cost, segment_only.cost - 20.0);
}

// solve_from_starts splits one solve's budget among its starts: with
// split_budget each gets an equal share of what the starts before it left, so a start that
// converges at once leaves its iterations to the next (the relaxed solve of
// a cycle on a small budget ran four starts on a quarter each).
TEST(CeresSolver, MultiStartPassesUnusedIterationsOn) {
  const Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  const SolveResult solved = CeresMpcSolver(opts()).solve(pb, std::vector<double>(2 * pb.N, 0.0));
  ASSERT_TRUE(solved.feasible);
  std::vector<double> poor(2 * pb.N, 0.0);  // turning on the spot all the way
  for (int k = 0; k < pb.N; ++k) poor[2 * k + 1] = pb.lim.omega_max;
  const int from_poor = CeresMpcSolver(opts()).solve(pb, poor).iterations;
  const int budget = 40;
  ASSERT_GT(from_poor, budget) << "the premise: the poor start needs more than the whole budget";
  SolverOptions o = opts();
  o.max_total_iterations = budget;
  o.split_budget = true;
  const MultiStartResult m = solve_from_starts(o, pb, {solved.u, poor}, /*least_violating=*/true);
  ASSERT_TRUE(m.found);
  const int from_solved = CeresMpcSolver(o).solve(pb, solved.u).iterations;
  ASSERT_LT(from_solved, budget / 4) << "the premise: the solved start converges at once";
  EXPECT_EQ(m.best.iterations, budget);  // the second start ran on all that the first left
}

TEST(CeresSolver, NeverNaNOnDegenerateInput) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  // obstacle centred exactly on the robot, zero-size ellipse axes are not allowed; tiny ones are
  pb.obstacles.push_back(moving_obstacle(1, 0.0, 0.0, 0, 0, 0.2, 0.1, 0, 0.9, pb.N, pb.dt));
  CeresMpcSolver solver(opts());
  SolveResult r = solver.solve(pb, std::vector<double>(2 * pb.N, std::nan("")));
  SolveResult e = solver.solve_elastic(pb, r.u);
  for (double v : e.u) EXPECT_TRUE(std::isfinite(v));
  for (double v : e.states) EXPECT_TRUE(std::isfinite(v));
}

// The IPOPT peer solves the same NLP (the footprint's discs, yaw-dependent
// constraints with their exact Hessian): from zeros it reaches a plan that
// meets problem.h's constraints and costs what Ceres's does.
TEST(IpoptPeer, SolvesTheSameFootprintNlpAsCeres) {
  for (int k : {0, 4, 8}) {
    const Problem pb = bench_problem(k);
    const SolveResult ceres = CeresMpcSolver(opts()).solve(pb, std::vector<double>(2 * pb.N, 0.0));
    const IpoptResult ip = solve_with_ipopt(pb);
    ASSERT_TRUE(ceres.feasible) << k;
    ASSERT_TRUE(ip.solved) << k << " obstacles, IPOPT status " << ip.status;
    EXPECT_LE(ip.max_violation, 1e-3) << k;
    EXPECT_NEAR(ip.cost, ceres.cost, 0.01 * ceres.cost) << k << " obstacles";
  }
}

// IPOPT starts where it is told (bench_planner compares it with Ceres from
// the same start): stopped before its first iteration, it returns the
// given controls (pushed 1e-8 into their bounds), whose rollout costs what
// Ceres's plan does; from zeros it returns the robot standing.
TEST(IpoptPeer, StartsFromTheGivenControls) {
  const Problem pb = bench_problem(4);
  const SolveResult ceres = CeresMpcSolver(opts()).solve(pb, std::vector<double>(2 * pb.N, 0.0));
  ASSERT_TRUE(ceres.feasible);
  IpoptOptions o;
  o.max_iter = 0;
  o.bound_push = 1e-8;
  o.start_u = ceres.u;
  const IpoptResult warm = solve_with_ipopt(pb, o);
  ASSERT_EQ(warm.u.size(), ceres.u.size());
  for (size_t i = 0; i < warm.u.size(); ++i) EXPECT_NEAR(warm.u[i], ceres.u[i], 1e-6) << "control " << i;
  EXPECT_NEAR(warm.cost, ceres.cost, 1e-4 * ceres.cost);
  o.start_u.clear();
  const IpoptResult cold = solve_with_ipopt(pb, o);
  ASSERT_EQ(cold.u.size(), ceres.u.size());
  for (double v : cold.u) EXPECT_NEAR(v, 0.0, 1e-6);
}

}  // namespace
}  // namespace evade::planning
