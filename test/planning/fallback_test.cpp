// The one fallback (planning/fallback.h): braking always meets its relaxed
// problem; driving into an obstacle's d_safe by the robot's own motion never
// does, standing while a mover comes does; getting out of a mover's way
// beats standing in it; the own-motion links' Jacobians are right.
#include "planning/fallback.h"

#include <gtest/gtest.h>

#include <cmath>

#include "planning/ceres_solver.h"
#include "planning/problem.h"
#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::bench_problem;
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
  std::vector<double> u(pb.num_controls());
  for (int k = 0; k < pb.N; ++k) {
    u[2 * k] = v;
    u[2 * k + 1] = omega;
  }
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
