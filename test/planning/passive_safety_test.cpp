// The recovery's passive-safety bound (planning/passive_safety.h): the
// speed from which the robot stands before a mover going at its own speed
// in any direction could reach its front; a mover predicted to walk away
// bounds it as one walking towards it; far from every mover, or beside only
// settled obstacles, nothing is bounded.
#include "planning/passive_safety.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::moving_obstacle;
using testing::straight_problem;

constexpr double kDecel = 1.5;  // testing::default_limits()

// The 0.42 x 0.31 m robot at the origin heading +x at 1 m/s, and a walker of
// radius 0.3 m at (x, y) walking at (vx, vy), tracked age_s.
Problem robot_and_walker(double x, double y, double vx, double vy, double age_s) {
  Problem pb = straight_problem(0, 0, 0, 1.0, 1.0);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);
  pb.d_safe = 0.15;
  ObstacleTrack w = moving_obstacle(3, x, y, vx, vy, 0.3, 0.3, 0.0, 0.9, pb.N, pb.dt);
  w.age_s = age_s;
  pb.obstacles = {w};
  return pb;
}

// the gap from the front disc of robot_and_walker's robot to a walker at (x, y)
double front_gap(double x, double y) {
  const Footprint f = Footprint::covering(0.42, 0.31, 3);
  return std::hypot(x - f.offsets.back(), y) - f.radius - 0.3;
}

TEST(PassiveSafety, FromTheBoundTheRobotStandsBeforeTheMoverCanReachIt) {
  const double tau = 0.3;
  for (double s : {0.0, 0.5, 1.4, 5.0}) {
    for (double gap : {0.2, 0.5, 1.0, 2.0, 6.0}) {
      const double v = passive_safe_speed(gap, s, tau, kDecel);
      if (gap <= s * tau) {
        EXPECT_EQ(v, 0.0) << "s " << s << " gap " << gap;
        continue;
      }
      ASSERT_GT(v, 0.0);
      // the robot's way and the mover's until the robot stands fill the gap
      const double stop_s = tau + v / kDecel;
      EXPECT_NEAR(v * tau + v * v / (2 * kDecel) + s * stop_s, gap, 1e-9) << "s " << s << " gap " << gap;
    }
  }
  // nearer or faster: slower
  EXPECT_LT(passive_safe_speed(0.8, 1.4, tau, kDecel), passive_safe_speed(1.2, 1.4, tau, kDecel));
  EXPECT_LT(passive_safe_speed(1.2, 2.0, tau, kDecel), passive_safe_speed(1.2, 1.4, tau, kDecel));
}

TEST(PassiveSafety, AWalkerBesideBoundsTheSpeedWhereverItIsPredictedToGo) {
  const PassiveSafetyParams p;
  // 1 m beside the robot, predicted to walk away from it at 1 m/s
  const Problem away = robot_and_walker(0.0, -1.3, 0.0, -1.0, 3.0);
  const double bound = passive_speed_bound(p, away);
  EXPECT_NEAR(bound, passive_safe_speed(front_gap(0.0, -1.3), 1.0, p.reaction_s, kDecel), 0.01);
  EXPECT_LT(bound, 0.5);
  // walking towards it at the same speed: the same bound
  EXPECT_NEAR(passive_speed_bound(p, robot_and_walker(0.0, -1.3, 0.0, 1.0, 3.0)), bound, 1e-9);
  // the bound goes into the problem's v_cap at every step
  Problem pb = away;
  ASSERT_TRUE(bound_passively(p, &pb));
  ASSERT_EQ(pb.v_cap.size(), static_cast<size_t>(pb.N));
  for (double cap : pb.v_cap) EXPECT_NEAR(cap, bound, 1e-12);
  // an existing lower cap (a hidden region's) stays
  pb = away;
  pb.v_cap.assign(pb.N, 0.1);
  ASSERT_TRUE(bound_passively(p, &pb));
  for (double cap : pb.v_cap) EXPECT_NEAR(cap, 0.1, 1e-12);
}

TEST(PassiveSafety, FarFromEveryMoverNothingIsBounded) {
  const PassiveSafetyParams p;
  Problem pb = robot_and_walker(0.0, -8.0, 0.0, 1.0, 3.0);
  EXPECT_EQ(passive_speed_bound(p, pb), pb.lim.v_max);
  EXPECT_FALSE(bound_passively(p, &pb));
  EXPECT_TRUE(pb.v_cap.empty());
  // no obstacle at all
  pb.obstacles.clear();
  EXPECT_FALSE(bound_passively(p, &pb));
}

TEST(PassiveSafety, SettledObstaclesAreNotMoversYoungTracksAreFast) {
  const PassiveSafetyParams p;
  // a bin 0.4 m ahead, tracked 3 s, standing: the constraints' alone
  const Problem bin = robot_and_walker(0.21 + 0.4 + 0.3, 0.0, 0.0, 0.0, 3.0);
  EXPECT_EQ(passive_speed_bound(p, bin), bin.lim.v_max);
  // the same track seen for the first time: its speed is not known yet
  const Problem young = robot_and_walker(0.21 + 0.4 + 0.3, 0.0, 0.0, 0.0, 0.1);
  const double gap = front_gap(0.21 + 0.4 + 0.3, 0.0);
  EXPECT_NEAR(passive_speed_bound(p, young), passive_safe_speed(gap, p.unknown_speed_mps, p.reaction_s, kDecel), 0.01);
  // a young track faster than that keeps its own speed
  const Problem fast = robot_and_walker(5.0, 0.0, -4.0, 0.0, 0.1);
  EXPECT_NEAR(passive_speed_bound(p, fast), passive_safe_speed(front_gap(5.0, 0.0), 4.0, p.reaction_s, kDecel), 0.01);
}

TEST(PassiveSafety, AMoverBehindIsFartherFromTheFrontThanOneAhead) {
  const PassiveSafetyParams p;
  const double ahead = passive_speed_bound(p, robot_and_walker(1.3, 0.0, 1.0, 0.0, 3.0));
  const double behind = passive_speed_bound(p, robot_and_walker(-1.3, 0.0, -1.0, 0.0, 3.0));
  EXPECT_LT(ahead, behind);
}

}  // namespace
}  // namespace evade::planning
