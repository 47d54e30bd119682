// Obstacle motion models against their definitions, and the robot's
// kinematics (exact arc, acceleration limits, command timeout).
#include "sim/motion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/robot.h"

namespace evade::sim {
namespace {

ObstacleSpec walker(WaypointMode mode) {
  ObstacleSpec s;
  s.x = 0.0;
  s.y = 0.0;
  s.motion = MotionKind::kWaypoints;
  // An L: 3 m along x, then 4 m along y (7 m in all; closing it adds 5 m).
  s.waypoints = {Vec2{0.0, 0.0}, Vec2{3.0, 0.0}, Vec2{3.0, 4.0}};
  s.speed = 1.0;
  s.mode = mode;
  return s;
}

void expect_state(const ObstacleState& st, double x, double y, double vx, double vy) {
  EXPECT_NEAR(st.x, x, 1e-12);
  EXPECT_NEAR(st.y, y, 1e-12);
  EXPECT_NEAR(st.vx, vx, 1e-12);
  EXPECT_NEAR(st.vy, vy, 1e-12);
}

TEST(Motion, StaticNeverMoves) {
  ObstacleSpec s;
  s.x = 1.5;
  s.y = -2.0;
  expect_state(obstacle_state(s, 0.0), 1.5, -2.0, 0, 0);
  expect_state(obstacle_state(s, 100.0), 1.5, -2.0, 0, 0);
}

TEST(Motion, ConstantVelocityIsAStraightLine) {
  ObstacleSpec s;
  s.x = -4.5;
  s.y = 0.5;
  s.motion = MotionKind::kConstantVelocity;
  s.vx = -1.0;
  s.vy = 0.5;
  expect_state(obstacle_state(s, -1.0), -4.5, 0.5, 0, 0);  // not started: at rest
  expect_state(obstacle_state(s, 0.0), -4.5, 0.5, 0, 0);
  expect_state(obstacle_state(s, 2.0), -6.5, 1.5, -1.0, 0.5);
  expect_state(obstacle_state(s, 10.0), -14.5, 5.5, -1.0, 0.5);
}

TEST(Motion, OnceStopsAtTheLastWaypoint) {
  ObstacleSpec s = walker(WaypointMode::kOnce);
  expect_state(obstacle_state(s, 1.0), 1.0, 0.0, 1.0, 0.0);
  expect_state(obstacle_state(s, 5.0), 3.0, 2.0, 0.0, 1.0);
  expect_state(obstacle_state(s, 7.0), 3.0, 4.0, 0.0, 0.0);
  expect_state(obstacle_state(s, 50.0), 3.0, 4.0, 0.0, 0.0);
}

TEST(Motion, PingpongGoesBackAlongThePath) {
  ObstacleSpec s = walker(WaypointMode::kPingpong);
  expect_state(obstacle_state(s, 5.0), 3.0, 2.0, 0.0, 1.0);
  // 9 s: 7 m out, 2 m back down the y leg.
  expect_state(obstacle_state(s, 9.0), 3.0, 2.0, 0.0, -1.0);
  // 12 s: 5 m back: on the x leg, heading -x.
  expect_state(obstacle_state(s, 12.0), 2.0, 0.0, -1.0, 0.0);
  // period 14 s
  expect_state(obstacle_state(s, 15.0), 1.0, 0.0, 1.0, 0.0);
  expect_state(obstacle_state(s, 14.0 * 3 + 5.0), 3.0, 2.0, 0.0, 1.0);
}

TEST(Motion, LoopClosesThePolygon) {
  ObstacleSpec s = walker(WaypointMode::kLoop);
  // Closing leg (3,4) -> (0,0) is 5 m, direction (-0.6, -0.8).
  expect_state(obstacle_state(s, 9.5), 3.0 - 0.6 * 2.5, 4.0 - 0.8 * 2.5, -0.6, -0.8);
  // period 12 s
  expect_state(obstacle_state(s, 13.0), 1.0, 0.0, 1.0, 0.0);
  expect_state(obstacle_state(s, 12.0 * 10 + 5.0), 3.0, 2.0, 0.0, 1.0);
}

TEST(Motion, FirstWaypointAwayFromTheStartIsVisited) {
  ObstacleSpec s;
  s.x = 0.0;
  s.y = 3.0;
  s.motion = MotionKind::kWaypoints;
  s.waypoints = {Vec2{0.0, -3.0}};
  s.speed = 1.2;
  s.mode = WaypointMode::kPingpong;
  expect_state(obstacle_state(s, 2.5), 0.0, 0.0, 0.0, -1.2);
  expect_state(obstacle_state(s, 7.5), 0.0, -3.0 + 1.2 * 2.5, 0.0, 1.2);
}

TEST(Motion, StartDelayHoldsTheObstacleThenShiftsItsMotion) {
  ObstacleSpec s = walker(WaypointMode::kOnce);
  s.start_delay_s = 2.5;
  expect_state(obstacle_state(s, 0.0), 0.0, 0.0, 0.0, 0.0);
  expect_state(obstacle_state(s, 2.5), 0.0, 0.0, 0.0, 0.0);  // still waiting
  expect_state(obstacle_state(s, 3.5), 1.0, 0.0, 1.0, 0.0);  // 1 s into its own motion
  expect_state(obstacle_state(s, 7.5), 3.0, 2.0, 0.0, 1.0);
  expect_state(obstacle_state(s, 9.5), 3.0, 4.0, 0.0, 0.0);
  ObstacleSpec c;
  c.motion = MotionKind::kConstantVelocity;
  c.vx = 2.0;
  c.start_delay_s = 1.0;
  expect_state(obstacle_state(c, 0.9), 0.0, 0.0, 0.0, 0.0);
  expect_state(obstacle_state(c, 1.5), 1.0, 0.0, 2.0, 0.0);
}

RobotLimits limits() {
  RobotLimits l;
  l.max_accel_mps2 = 1.0;
  l.max_decel_mps2 = 2.0;
  l.max_alpha_radps2 = 4.0;
  l.command_timeout_us = 250'000;
  l.step_us = 1000;
  return l;
}

TEST(Robot, ArcIsExact) {
  // Quarter circle of radius 2: v = 1, omega = 0.5, t = pi.
  Pose2 p = integrate_arc(Pose2{0, 0, 0}, 1.0, 0.5, M_PI);
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_NEAR(p.y, 2.0, 1e-12);
  EXPECT_NEAR(p.yaw, M_PI / 2, 1e-12);
}

TEST(Robot, AcceleratesAtTheLimitAndStopsAfterTheTimeout) {
  const int64_t t0 = 1'000'000'000;
  UnicycleRobot r(Pose2{0, 0, 0}, limits(), t0);
  EXPECT_EQ(r.first_motion_us(), -1);
  r.command(0.5, 0.0, t0);
  r.advance_to(t0 + 200'000);
  EXPECT_NEAR(r.v(), 0.2, 1e-9);  // 1 m/s^2 for 0.2 s
  EXPECT_EQ(r.first_motion_us(), t0 + 1000);
  r.advance_to(t0 + 250'000);
  EXPECT_NEAR(r.v(), 0.25, 1e-9);
  // Distance while ramping: sum over steps of v_k dt = dt^2 * sum k.
  double expect_x = 1e-6 * 249 * 250 / 2.0;
  EXPECT_NEAR(r.pose().x, expect_x, 1e-12);
  // No further command: after 0.25 s the target is 0 -> brakes at 2 m/s^2.
  r.advance_to(t0 + 300'000);
  EXPECT_NEAR(r.v(), 0.25 - 2.0 * 0.05, 1e-9);
  r.advance_to(t0 + 500'000);
  EXPECT_EQ(r.v(), 0.0);
}

TEST(Robot, CommandsKeepItGoingAndYawRateIsLimited) {
  const int64_t t0 = 0;
  UnicycleRobot r(Pose2{0, 0, 0}, limits(), t0);
  for (int64_t t = 0; t <= 2'000'000; t += 20'000) {
    r.command(1.0, -0.4, t);
  }
  EXPECT_NEAR(r.v(), 1.0, 1e-9);
  EXPECT_NEAR(r.omega(), -0.4, 1e-9);
  UnicycleRobot w(Pose2{0, 0, 0}, limits(), t0);
  w.command(0.0, 1.0, 0);
  w.advance_to(100'000);
  EXPECT_NEAR(w.omega(), 0.4, 1e-9);  // 4 rad/s^2 for 0.1 s
}

TEST(Robot, PoseInThePastComesFromHistory) {
  UnicycleRobot r(Pose2{0, 0, 0}, limits(), 0);
  r.command(1.0, 0.0, 0);
  r.advance_to(10'000);
  Pose2 at5 = r.pose_at(5'500);
  r.advance_to(40'000);
  Pose2 again = r.pose_at(5'500);
  EXPECT_DOUBLE_EQ(at5.x, again.x);
  EXPECT_GT(r.pose_at(40'000).x, again.x);
}

}  // namespace
}  // namespace evade::sim
