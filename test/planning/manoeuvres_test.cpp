// The recovery's open-loop manoeuvres (planning/manoeuvres.h): a swerve
// holds the measured speed and turns to its side, then back; a dash gets
// away to its side from rest, accelerating at the limit, where a swerve
// only turns on the spot.
#include "planning/manoeuvres.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::straight_problem;

std::vector<double> states_of(const Problem& pb, const std::vector<double>& u) {
  std::vector<double> s(3 * (pb.N + 1));
  rollout(pb, u.data(), s.data());
  return s;
}

TEST(Manoeuvres, ASwerveHoldsTheSpeedAndTurnsToItsSideThenBack) {
  const Problem pb = straight_problem(0, 0, 0, 0.6, 0.8);
  for (double side : {1.0, -1.0}) {
    const std::vector<double> u = swerve_controls(pb, side);
    ASSERT_EQ(u.size(), static_cast<size_t>(pb.num_controls()));
    for (int k = 0; k < pb.N; ++k) {
      EXPECT_EQ(u[2 * k], 0.6);
      EXPECT_EQ(u[2 * k + 1], (k < pb.N / 2 ? side : -side) * pb.lim.omega_max);
    }
    const std::vector<double> s = states_of(pb, u);
    EXPECT_GT(side * s[3 * pb.N + 1], 0.3);  // off to its side by the horizon's end, heading back
    EXPECT_NEAR(s[3 * pb.N + 2], side * (pb.N / 2 - (pb.N - pb.N / 2)) * pb.lim.omega_max * pb.dt, 1e-9);
  }
}

TEST(Manoeuvres, ADashFromRestAcceleratesAtTheLimitAndGetsAwayToItsSide) {
  const Problem pb = straight_problem(0, 0, 0, 0.0, 0.8);
  const std::vector<double> swerve = swerve_controls(pb, 1.0);
  for (double side : {1.0, -1.0}) {
    const std::vector<double> u = dash_controls(pb, side);
    for (int k = 0; k < pb.N; ++k) EXPECT_NEAR(u[2 * k], std::min(pb.lim.v_max, (k + 1) * pb.lim.accel * pb.dt), 1e-12);
    const std::vector<double> s = states_of(pb, u);
    EXPECT_GT(side * s[3 * pb.N + 1], 0.5);
    EXPECT_GT(std::hypot(s[3 * pb.N], s[3 * pb.N + 1]), 1.5);
  }
  // from rest the swerve only turns on the spot
  const std::vector<double> s = states_of(pb, swerve);
  EXPECT_EQ(std::hypot(s[3 * pb.N], s[3 * pb.N + 1]), 0.0);
}

TEST(Manoeuvres, PullingOverHeadsForTheLaneBesideTheReferenceAndStands) {
  for (double v0 : {0.0, 0.8}) {
    for (double side : {1.0, -1.0}) {
      // on the reference (along x): into the lane 0.3 m to the side
      const Problem pb = straight_problem(0, 0, 0, v0, 0.8);
      const std::vector<double> u = pull_over_controls(pb, side, 0.3, 1.0);
      const std::vector<double> s = states_of(pb, u);
      const int N = pb.N;
      EXPECT_EQ(u[2 * (N - 1)], 0.0) << side << " " << v0;   // standing by the horizon's end
      EXPECT_NEAR(s[3 * N], 1.0, 0.1) << side << " " << v0;  // 1 m on
      EXPECT_GT(side * s[3 * N + 1], 0.15) << side << " " << v0;
      EXPECT_LT(side * s[3 * N + 1], 0.35) << side << " " << v0;
      for (int k = 0; k < N; ++k) {
        EXPECT_GE(u[2 * k], 0.0);
        EXPECT_LE(u[2 * k], pb.lim.v_max + 1e-12);
        EXPECT_LE(std::fabs(u[2 * k + 1]), pb.lim.omega_max + 1e-12);
      }
      // the lane is the reference's, not the robot's: from 0.3 m to the
      // side already, the same lane keeps the robot there
      Problem beside = straight_problem(0, side * 0.3, 0, v0, 0.8);
      for (double& y : beside.ref_y) y = 0.0;
      const std::vector<double> t = states_of(beside, pull_over_controls(beside, side, 0.3, 1.0));
      EXPECT_NEAR(t[3 * N + 1], side * 0.3, 0.05) << side << " " << v0;
    }
  }
}

}  // namespace
}  // namespace evade::planning
