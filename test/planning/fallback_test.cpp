// The one fallback (planning/fallback.h): braking always meets its relaxed
// problem; driving into an obstacle's d_safe by the robot's own motion never
// does, standing while a mover comes does; getting out of a mover's way
// beats standing in it; the own-motion links' Jacobians are right.
#include "planning/fallback.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "planning/ceres_solver.h"
#include "planning/problem.h"
#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::bench_problem;
using testing::constant_controls;
using testing::moving_obstacle;
using testing::straight_problem;

constexpr double kDecay = 0.9;  // mode evade's 1 - evade_gamma

// Braking at the deceleration limit from the problem's measured speed.
std::vector<double> braking(const Problem& pb) {
  std::vector<double> u(pb.num_controls(), 0.0);
  project_controls(pb, &u);
  return u;
}

// Constant controls (v, omega) over the horizon, projected onto the limits.
std::vector<double> constant(const Problem& pb, double v, double omega) {
  std::vector<double> u = constant_controls(pb, v, omega);
  project_controls(pb, &u);
  return u;
}

// A robot at 0.8 m/s and a bike at 4 m/s head-on on its path, 3 m apart:
// nothing gets out of its way (the hard problem fails).
Problem bike_head_on() {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.obstacles.push_back(moving_obstacle(1, 3.0, 0.0, -4.0, 0.0, 0.9, 0.4, 0.0, kDecay, pb.N, pb.dt));
  return pb;
}

TEST(Fallback, BrakingMeetsTheRelaxedProblem) {
  Problem walker = straight_problem(0, 0, 0, 0.0, 0.8);  // at rest, a walker about to walk into it
  walker.obstacles.push_back(moving_obstacle(1, 1.0, 0.2, -1.5, 0.0, 0.3, 0.3, 0.0, kDecay, walker.N, walker.dt));
  for (const Problem& pb : {bike_head_on(), walker}) {
    const std::vector<double> brake = braking(pb);
    ASSERT_GT(max_violation(pb, brake.data()), 0.01);  // the premise: braking misses the hard problem
    const Problem relaxed = fallback_problem(pb, brake, SolverOptions{});
    EXPECT_LE(max_violation(relaxed, brake.data()), 1e-9);
  }
}

TEST(Fallback, DrivingIntoAnObstacleBreaksTheRelaxedProblemStandingInAMoversWayDoesNot) {
  // a standing obstacle 1.2 m ahead of a robot at rest: driving on into its
  // d_safe is the robot's own doing
  Problem wall = straight_problem(0, 0, 0, 0.0, 0.8);
  wall.obstacles.push_back(moving_obstacle(1, 1.2, 0.0, 0.0, 0.0, 0.3, 0.3, 0.0, kDecay, wall.N, wall.dt));
  const Problem relaxed_wall = fallback_problem(wall, braking(wall), SolverOptions{});
  EXPECT_GT(max_violation(relaxed_wall, constant(wall, 0.8, 0.0).data()), 0.05);
  EXPECT_LE(max_violation(relaxed_wall, braking(wall).data()), 1e-9);
  // a mover walking into a robot at rest: standing meets the relaxed
  // problem (its approach is not the robot's), though not the hard one
  Problem walker = straight_problem(0, 0, 0, 0.0, 0.8);
  walker.obstacles.push_back(moving_obstacle(1, 2.0, 0.0, -1.5, 0.0, 0.3, 0.3, 0.0, kDecay, walker.N, walker.dt));
  const std::vector<double> stand = braking(walker);
  EXPECT_GT(max_violation(walker, stand.data()), 0.05);
  EXPECT_LE(max_violation(fallback_problem(walker, stand, SolverOptions{}), stand.data()), 1e-9);
}

TEST(Fallback, GettingOutOfAWalkersWayBeatsStandingInIt) {
  // a walker 3.5 m ahead coming at 1.2 m/s along the path of a robot at
  // 0.5 m/s: the fallback's plan gets aside, less deep within d_safe than
  // braking and never closing on the walker by its own motion
  Problem pb = straight_problem(0, 0, 0, 0.5, 0.8);
  pb.obstacles.push_back(moving_obstacle(1, 3.5, 0.0, -1.2, 0.0, 0.35, 0.35, 0.0, kDecay, pb.N, pb.dt));
  const CeresMpcSolver solver(SolverOptions{});
  ASSERT_FALSE(solver.solve(pb, constant(pb, 0.5, 0.0)).feasible);  // the premise
  const std::vector<double> brake = braking(pb);
  const SolveResult r = solve_fallback(solver, pb, constant(pb, 0.5, 0.0), brake);
  ASSERT_TRUE(r.feasible);
  std::vector<double> brake_states(3 * (pb.N + 1));
  rollout(pb, brake.data(), brake_states.data());
  EXPECT_LT(squared_penetration(pb, r.states), 0.5 * squared_penetration(pb, brake_states));
  EXPECT_GT(std::fabs(r.states[3 * pb.N + 1]), 0.3);  // aside
  const Problem relaxed = fallback_problem(pb, brake, solver.options());
  EXPECT_LE(max_violation(relaxed, r.u.data()), solver.options().constraint_tolerance);
}

TEST(Fallback, WhileBrakingClosesOnABikeNoPlanIsFasterThanBraking) {
  // braking from 0.8 m/s still closes on a bike (0.3 m in radius) coming
  // at 4.5 m/s 0.25 m left of the path, 2 m ahead: the links are relaxed by
  // what braking misses of them, and a plan that turns aside at speed would
  // spend that allowance and meet the bike still moving; the fallback's plan
  // brakes as hard, and may steer
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);  // robot.yaml's robot
  pb.d_safe = 0.15;
  pb.obstacles.push_back(moving_obstacle(1, 2.0, 0.25, -4.5, 0.0, 0.3, 0.3, 0.0, kDecay, pb.N, pb.dt));
  SolverOptions opts;
  const std::vector<double> brake = braking(pb);
  const Problem relaxed = fallback_problem(pb, brake, opts);
  int capped = 0;  // the steps up to the last at which braking closes in
  while (capped < static_cast<int>(relaxed.v_cap.size()) && relaxed.v_cap[capped] < relaxed.lim.v_max) ++capped;
  ASSERT_GT(capped, 0);
  const SolveResult r = solve_fallback(CeresMpcSolver(opts), pb, constant(pb, 0.8, 0.0), brake);
  ASSERT_TRUE(r.feasible);
  double faster = 0.0;
  for (int k = 0; k < capped; ++k) faster = std::max(faster, r.u[2 * k] - brake[2 * k]);
  EXPECT_LE(faster, 1e-9);
  // without the cap the plan keeps more speed than braking
  opts.fallback_brake_while_closing = false;
  ASSERT_TRUE(fallback_problem(pb, brake, opts).v_cap.empty());
  const SolveResult free = solve_fallback(CeresMpcSolver(opts), pb, constant(pb, 0.8, 0.0), brake);
  ASSERT_TRUE(free.feasible);
  double faster_free = 0.0;
  for (int k = 0; k < capped; ++k) faster_free = std::max(faster_free, free.u[2 * k] - brake[2 * k]);
  std::printf("[figures] bike: %d steps capped, most above braking's speed %.3f m/s, %.3f m/s uncapped\n", capped,
              faster, faster_free);
  EXPECT_GT(faster_free, 0.1);
}

// obstacle o inflated as the predictor does: sigma added to both axes,
// growing linearly from sigma0 at k = 0 to sigma_n at step n_grow, then held.
ObstacleTrack inflated(ObstacleTrack o, double sigma0, double sigma_n, int n_grow) {
  for (size_t k = 0; k < o.a.size(); ++k) {
    const double s = sigma0 + (sigma_n - sigma0) * std::min(1.0, static_cast<double>(k) / n_grow);
    o.sigma.push_back(s);
    o.a[k] += s;
    o.b[k] += s;
  }
  return o;
}

// A Scout-sized robot (0.93 x 0.70 m) at 0.4 m/s in a 2.2 m corridor (two
// walls 0.2 m thick, each ellipse inflated by 0.2 m now and 0.5 m within a
// second, as the predictor does a static track; settled), a walker 0.25 m in
// radius (not settled: its ellipse as given) coming at 1 m/s 0.4 m left of
// the centre line.
Problem corridor_walker() {
  Problem pb = straight_problem(0, 0, 0, 0.4, 0.8);
  pb.footprint = Footprint::covering(0.93, 0.70, 3);
  pb.d_safe = 0.15;
  for (double y : {1.2, -1.2}) {
    pb.obstacles.push_back(
        inflated(moving_obstacle(1, 1.5, y, 0, 0, 4.0, 0.1, 0.0, kDecay, pb.N, pb.dt), 0.2, 0.5, 10));
    pb.obstacles.back().age_s = 5.0;  // settled
  }
  pb.obstacles.push_back(moving_obstacle(2, 3.5, 0.4, -1.0, 0, 0.25, 0.25, 0.0, kDecay, pb.N, pb.dt));
  return pb;
}

TEST(Fallback, InACorridorWhoseInflatedWallsCoverTheRobotItGetsOutOfAWalkersWay) {
  // the inflation covers the robot wherever it stands between the walls by
  // the horizon's end: judged by the inflated ellipses no way aside closes
  // less on them than standing; judged by the walls' own extent the robot
  // moves right, away from the walker's line (whose ellipse stays inflated)
  const Problem pb = corridor_walker();
  SolverOptions opts;
  const CeresMpcSolver solver(opts);
  ASSERT_FALSE(solver.solve(pb, constant(pb, 0.4, 0.0)).feasible);  // the premise
  const std::vector<double> brake = braking(pb);
  const SolveResult own = solve_fallback(solver, pb, constant(pb, 0.4, 0.0), brake);
  opts.fallback_true_extent = false;
  const SolveResult inflated_only = solve_fallback(CeresMpcSolver(opts), pb, constant(pb, 0.4, 0.0), brake);
  ASSERT_TRUE(own.feasible);
  const double y_own = own.states[3 * pb.N + 1], y_inflated = inflated_only.states[3 * pb.N + 1];
  std::printf("[figures] corridor: y at the horizon's end %.3f m (own extent), %.3f m (inflated)\n", y_own, y_inflated);
  EXPECT_LT(y_own, -0.15);
  EXPECT_GT(y_inflated, y_own + 0.1);
  // it gets aside without entering a wall's own extent's d_safe
  Problem own_extent = pb;
  for (ObstacleTrack& o : own_extent.obstacles) remove_inflation(&o);
  own_extent.obstacles.pop_back();  // the walls alone
  EXPECT_GE(min_barrier(own_extent, own.states, 1), -opts.constraint_tolerance);
}

TEST(Fallback, RemovingTheInflationLeavesTheObstaclesOwnEllipse) {
  ObstacleTrack o = inflated(moving_obstacle(1, 1.0, 0.0, 0, 0, 0.4, 0.2, 0.0, kDecay, 25, 0.1), 0.1, 0.5, 10);
  remove_inflation(&o);
  for (size_t k = 0; k < o.a.size(); ++k) {
    EXPECT_NEAR(o.a[k], 0.4, 1e-12);
    EXPECT_NEAR(o.b[k], 0.2, 1e-12);
  }
  ObstacleTrack bare = moving_obstacle(1, 1.0, 0.0, 0, 0, 0.4, 0.2, 0.0, kDecay, 25, 0.1);  // no sigma: unchanged
  remove_inflation(&bare);
  EXPECT_EQ(bare.a[25], 0.4);
}

TEST(Fallback, OwnMotionAndPenetrationJacobiansMatchFiniteDifferences) {
  Problem pb = bench_problem(8);
  pb.own_motion = true;
  pb.penetration_weight = 1e3;
  pb.d_safe = 1.0;  // some barriers inside d_safe and some outside: both forms of the link
  const int n = pb.num_controls(), m = pb.num_constraints();
  std::vector<double> u(n);
  for (int k = 0; k < pb.N; ++k) {
    u[2 * k] = 0.5 + 0.3 * std::sin(0.7 * k);
    u[2 * k + 1] = 0.4 * std::cos(0.5 * k);
  }
  const std::vector<double> lambda(m, 1e3);
  std::vector<double> r, jac;
  ASSERT_TRUE(evaluate_inner_residuals(pb, u.data(), lambda, 50.0, &r, &jac));
  const int nr = static_cast<int>(r.size());
  ASSERT_EQ(nr, num_cost_residuals(pb) + m + static_cast<int>(pb.obstacles.size()) * pb.N);
  const double e = 1e-6;
  int penetrating = 0;
  for (int row = num_cost_residuals(pb) + m; row < nr; ++row) penetrating += r[row] != 0.0;
  EXPECT_GT(penetrating, 0);  // the check covers the penetration rows
  for (int i = 0; i < n; ++i) {
    std::vector<double> up = u, um = u, rp, rm;
    up[i] += e;
    um[i] -= e;
    ASSERT_TRUE(evaluate_inner_residuals(pb, up.data(), lambda, 50.0, &rp, nullptr));
    ASSERT_TRUE(evaluate_inner_residuals(pb, um.data(), lambda, 50.0, &rm, nullptr));
    for (int row = 0; row < nr; ++row) {
      const double fd = (rp[row] - rm[row]) / (2 * e);
      EXPECT_NEAR(jac[static_cast<size_t>(row) * n + i], fd, 1e-4 * std::max(1.0, std::fabs(fd)))
          << "row " << row << " control " << i;
    }
  }
}

}  // namespace
}  // namespace evade::planning
