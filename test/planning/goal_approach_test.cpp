#include "planning/goal_approach.h"

#include <gtest/gtest.h>

#include <cmath>

namespace evade::planning {
namespace {

Problem at(double x, double y, double yaw, double v) {
  Problem pb;
  pb.N = 25;
  pb.dt = 0.1;
  pb.x0 = x;
  pb.y0 = y;
  pb.yaw0 = yaw;
  pb.v_prev = v;
  pb.lim.v_max = 1.0;
  pb.lim.omega_max = 0.5;
  pb.lim.decel = 1.5;
  return pb;
}

TEST(GoalApproach, TheCaptureSpeedIsTheArcThroughTheGoal) {
  // straight ahead: any speed
  EXPECT_TRUE(std::isinf(goal_capture_speed(0, 0, 0, 2, 0, 0.5)));
  // 1 m to the side: the circle of radius 0.5 m, at 0.5 rad/s 0.25 m/s
  EXPECT_NEAR(goal_capture_speed(0, 0, 0, 0, 1, 0.5), 0.25, 1e-12);
  EXPECT_NEAR(goal_capture_speed(0, 0, 0, 0, -1, 0.5), 0.25, 1e-12);
  // 30 deg off at 2 m: radius 2 / (2 sin 30) = 2 m, 1 m/s
  EXPECT_NEAR(goal_capture_speed(0, 0, 0, 2 * std::cos(M_PI / 6), 2 * std::sin(M_PI / 6), 0.5), 1.0, 1e-12);
  // behind the beam: d / 2 (here 1.5 m behind: 0.375 m/s)
  EXPECT_NEAR(goal_capture_speed(0, 0, 0, -1.5, 0, 0.5), 0.375, 1e-12);
  EXPECT_NEAR(goal_capture_speed(0, 0, 0, -1.0, 0.2, 0.5), 0.5 * std::hypot(1.0, 0.2) / 2, 1e-12);
}

TEST(GoalApproach, CapsTheWholePlanNoFasterThanBrakingAllows) {
  GoalApproachParams p;
  // beside the goal, 1 m to the left, going 0.8 m/s
  const Problem pb = at(0, 0, 0, 0.8);
  const std::vector<double> caps = goal_approach_caps(p, pb, 0, 1, 1.0);
  ASSERT_EQ(caps.size(), 25u);
  for (int k = 0; k < 25; ++k) {
    const double braked = 0.8 - 1.5 * 0.1 * (k + 1);
    EXPECT_NEAR(caps[size_t(k)], std::max(0.25, braked), 1e-12) << k;
  }
}

TEST(GoalApproach, NoCapAheadOnALoopingRouteOrWhenOff) {
  GoalApproachParams p;
  const Problem pb = at(0, 0, 0, 0.8);
  EXPECT_TRUE(goal_approach_caps(p, pb, 3, 0, 3.0).empty());   // straight ahead
  EXPECT_TRUE(goal_approach_caps(p, pb, 0, 1, 2.5).empty());   // the route left loops: 2.5 m > 2 x 1 m
  EXPECT_FALSE(goal_approach_caps(p, pb, 0, 1, 2.0).empty());  // at the ratio
  p.enabled = false;
  EXPECT_TRUE(goal_approach_caps(p, pb, 0, 1, 1.0).empty());
}

TEST(GoalApproach, NeverBelowTheCrawl) {
  GoalApproachParams p;
  p.min_speed_mps = 0.1;
  const Problem pb = at(0, 0, 0, 0.0);
  const std::vector<double> caps = goal_approach_caps(p, pb, 0, 0.3, 0.3);  // 0.075 m/s by the arc
  ASSERT_FALSE(caps.empty());
  for (double c : caps) EXPECT_DOUBLE_EQ(c, 0.1);
}

TEST(GoalApproach, TightenCapsTakesTheStepwiseMinimum) {
  std::vector<double> caps;
  tighten_caps({}, &caps);
  EXPECT_TRUE(caps.empty());
  tighten_caps({0.5, 0.7}, &caps);
  EXPECT_EQ(caps, (std::vector<double>{0.5, 0.7}));
  tighten_caps({0.6, 0.3}, &caps);
  EXPECT_EQ(caps, (std::vector<double>{0.5, 0.3}));
  tighten_caps({}, &caps);
  EXPECT_EQ(caps, (std::vector<double>{0.5, 0.3}));
}

}  // namespace
}  // namespace evade::planning
