// What a recovery plan comes to against a mover (planning/outcome.h):
// judged on the mover's own predicted body, not its inflated ellipse; a
// contact is the robot's when its own step closes on the mover where they
// meet, else the mover's; a plan standing in a mover's lane meets it after
// the horizon too.
#include "planning/outcome.h"

#include <gtest/gtest.h>

#include <vector>

#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::constant_controls;
using testing::moving_obstacle;
using testing::straight_problem;

// A walker of radius 0.3 m walking at 1 m/s along y = 0 towards the robot
// (the 0.42 x 0.31 m robot at the origin, heading +x), `gap` m from the
// robot's front to the walker's body at step 0; its ellipse inflated by
// `sigma` at every step.
Problem walker_ahead(double gap, double sigma, int N = 25) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.5, N);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);
  pb.d_safe = 0.15;
  ObstacleTrack w = moving_obstacle(7, 0.21 + gap + 0.3, 0.0, -1.0, 0.0, 0.3 + sigma, 0.3 + sigma, 0.0, 0.9, N, 0.1);
  w.sigma.assign(N + 1, sigma);
  pb.obstacles = {w};
  return pb;
}

std::vector<double> rollout_of(const Problem& pb, double v, double omega) {
  const std::vector<double> u = constant_controls(pb, v, omega);
  std::vector<double> s(3 * (pb.N + 1));
  rollout(pb, u.data(), s.data());
  return s;
}

// states of a robot standing at (x, y), heading +x
std::vector<double> standing_at(const Problem& pb, double x, double y) {
  std::vector<double> s;
  for (int k = 0; k <= pb.N; ++k) s.insert(s.end(), {x, y, 0.0});
  return s;
}

TEST(Outcome, DrivingIntoAWalkerIsOursStandingIsTheirsStandingAsideIsClear) {
  const Problem pb = walker_ahead(1.0, 0.0);
  const double tol = 1e-3;
  // on at 0.5 m/s: they meet by step 7 with the robot still driving on
  const Outcome on = plan_outcome(pb, rollout_of(pb, 0.5, 0.0), tol);
  EXPECT_EQ(on.kind, Outcome::kOurs);
  EXPECT_GE(on.first_contact, 6);
  EXPECT_LE(on.first_contact, 7);
  EXPECT_LT(on.clearance, 0.0);
  // standing where it is: the walker walks into it
  const Outcome stand = plan_outcome(pb, standing_at(pb, 0.0, 0.0), tol);
  EXPECT_EQ(stand.kind, Outcome::kTheirs);
  EXPECT_NEAR(stand.first_contact, 10, 1);  // the front disc overhangs the body
  // standing 0.6 m aside, the walker passes 0.6 - 0.3 - 0.155 m off
  const Outcome aside = plan_outcome(pb, standing_at(pb, 0.0, -0.6), tol);
  EXPECT_EQ(aside.kind, Outcome::kClear);
  EXPECT_EQ(aside.first_contact, -1);
  EXPECT_NEAR(aside.clearance, 0.6 - 0.3 - Footprint::covering(0.42, 0.31, 3).radius, 0.02);
}

TEST(Outcome, TheInflationIsNotTheWalkersBody) {
  // inflated by 0.5 m the walker's ellipse covers the robot 0.6 m aside;
  // its own body does not reach it
  const Problem pb = walker_ahead(1.0, 0.5);
  EXPECT_EQ(plan_outcome(pb, standing_at(pb, 0.0, -0.6), 1e-3).kind, Outcome::kClear);
  EXPECT_EQ(plan_outcome(pb, standing_at(pb, 0.0, 0.0), 1e-3).kind, Outcome::kTheirs);
}

TEST(Outcome, AfterTheHorizonBothGoOnAsAtItsEnd) {
  // 4 m off the walker meets a standing robot at 4 s: past the 2.5 s
  // horizon, within one more
  const Problem pb = walker_ahead(4.0, 0.0);
  EXPECT_EQ(plan_outcome(pb, standing_at(pb, 0.0, 0.0), 1e-3, 0).kind, Outcome::kClear);
  const Outcome later = plan_outcome(pb, standing_at(pb, 0.0, 0.0), 1e-3, pb.N);
  EXPECT_EQ(later.kind, Outcome::kTheirs);
  EXPECT_NEAR(later.first_contact, 40, 1);
  // still driving on at the horizon's end, the robot drives into it
  EXPECT_EQ(plan_outcome(pb, rollout_of(pb, 0.3, 0.0), 1e-3, pb.N).kind, Outcome::kOurs);
}

// A walker of radius 0.3 m crossing the robot's heading from its right at
// 1 m/s along x = 1.5, on the robot's line (y = 0) at t = 2 s.
Problem walker_crossing(int N = 25) {
  Problem pb = straight_problem(0, 0, 0, 0.0, 0.5, N);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);
  pb.d_safe = 0.15;
  ObstacleTrack w = moving_obstacle(8, 1.5, -2.0, 0.0, 1.0, 0.3, 0.3, 0.0, 0.9, N, 0.1);
  w.sigma.assign(N + 1, 0.0);
  pb.obstacles = {w};
  return pb;
}

// where the robot's centre stands when its front disc is `gap` m short of
// the crossing walker's body
double short_of_lane(const Problem& pb, double gap) {
  return 1.5 - 0.3 - gap - pb.footprint.offsets.back() - pb.footprint.radius;
}

// the rollout at v m/s along +x, moved to start at x
std::vector<double> driving_from(const Problem& pb, double x, double v) {
  std::vector<double> s = rollout_of(pb, v, 0.0);
  for (int k = 0; k <= pb.N; ++k) s[3 * k] += x;
  return s;
}

TEST(Outcome, AMarginGrowingWithTheTimeAheadMakesANearPassAContact) {
  const Problem pb = walker_crossing();
  const OutcomeMargin margin{0.15, 0.3};  // against the 1 m/s walker: 0.15 m per s ahead
  EXPECT_NEAR(mean_predicted_speed(pb.obstacles[0], pb.N, pb.dt), 1.0, 1e-9);
  EXPECT_NEAR(margin.at(0.1, 1.0), 0.015, 1e-12);
  EXPECT_NEAR(margin.at(2.0, 1.0), 0.3, 1e-12);
  EXPECT_NEAR(margin.at(5.0, 1.0), 0.3, 1e-12);
  // standing 0.1 m short of the walker's lane, the bodies pass 0.1 m apart
  // 2 s ahead: clear on the bodies alone; within the margin there (0.3 m),
  // the walker's, as the robot stands
  const std::vector<double> stand = standing_at(pb, short_of_lane(pb, 0.1), 0.0);
  const Outcome bodies = plan_outcome(pb, stand, 1e-3, pb.N);
  EXPECT_EQ(bodies.kind, Outcome::kClear);
  EXPECT_NEAR(bodies.clearance, 0.1, 0.01);
  EXPECT_EQ(plan_outcome(pb, stand, 1e-3, pb.N, margin).kind, Outcome::kTheirs);
  // driving on at 0.2 m/s to arrive there as the walker does: clear on the
  // bodies, the robot's within the margin
  const std::vector<double> on = driving_from(pb, short_of_lane(pb, 0.1) - 0.4, 0.2);
  EXPECT_EQ(plan_outcome(pb, on, 1e-3, pb.N).kind, Outcome::kClear);
  EXPECT_EQ(plan_outcome(pb, on, 1e-3, pb.N, margin).kind, Outcome::kOurs);
  // standing 0.5 m short of the lane stays clear with the margin
  EXPECT_EQ(plan_outcome(pb, standing_at(pb, short_of_lane(pb, 0.5), 0.0), 1e-3, pb.N, margin).kind, Outcome::kClear);
}

TEST(Outcome, TheMarginGrowsFromWhereThePlanStarts) {
  // a walker 0.05 m beside the robot's front disc, strolling on ahead of it
  const Problem base = walker_crossing();
  Problem pb = base;
  const double beside = pb.footprint.radius + 0.05 + 0.3;
  pb.obstacles = {moving_obstacle(9, pb.footprint.offsets.back(), beside, 0.1, 0.0, 0.3, 0.3, 0.0, 0.9, pb.N, 0.1)};
  pb.obstacles[0].sigma.assign(pb.N + 1, 0.0);
  const OutcomeMargin margin{1.5, 0.3};  // against the 0.1 m/s stroll: 0.15 m per s ahead
  // within the margin at the start: standing, or moving aside, is clear ...
  EXPECT_EQ(plan_outcome(pb, standing_at(pb, 0.0, 0.0), 1e-3, pb.N, margin).kind, Outcome::kClear);
  EXPECT_EQ(plan_outcome(pb, standing_at(pb, 0.0, -0.2), 1e-3, pb.N, margin).kind, Outcome::kClear);
  // ... and stepping towards it, closer than at the start, is a contact
  std::vector<double> towards = standing_at(pb, 0.0, 0.0);
  for (int k = 1; k <= pb.N; ++k) towards[3 * k + 1] = 0.03;
  EXPECT_EQ(plan_outcome(pb, towards, 1e-3, pb.N).kind, Outcome::kClear);
  EXPECT_NE(plan_outcome(pb, towards, 1e-3, pb.N, margin).kind, Outcome::kClear);
}

// The robot driving on at 0.5 m/s along y = 0 past a body of radius 0.3 m
// whose lane (y = lane_y) its discs pass 0.05 m off, its front disc level
// with the body 1 s ahead; the body predicted at (vx, 0) m/s.
Problem near_pass(double vx) {
  Problem pb = straight_problem(0, 0, 0, 0.5, 0.5);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);
  pb.d_safe = 0.15;
  const double lane_y = pb.footprint.radius + 0.3 + 0.05;
  const double level_x = pb.footprint.offsets.back() + 0.5 * 1.0;  // the front disc's x 1 s ahead
  ObstacleTrack o = moving_obstacle(10, level_x - vx * 1.0, lane_y, vx, 0.0, 0.3, 0.3, 0.0, 0.9, pb.N, pb.dt);
  o.sigma.assign(pb.N + 1, 0.0);
  pb.obstacles = {o};
  return pb;
}

TEST(Outcome, AStandingObstaclePassedByCentimetresIsClear) {
  // a bin, predicted to stand: no margin, whatever the time ahead
  const Problem pb = near_pass(0.0);
  const std::vector<double> on = rollout_of(pb, 0.5, 0.0);
  const OutcomeMargin margin{0.15, 0.3};
  const Outcome bodies = plan_outcome(pb, on, 1e-3, pb.N);
  EXPECT_EQ(bodies.kind, Outcome::kClear);
  EXPECT_NEAR(bodies.clearance, 0.05, 0.01);
  EXPECT_EQ(mean_predicted_speed(pb.obstacles[0], pb.N, pb.dt), 0.0);
  EXPECT_EQ(margin.at(1.0, 0.0), 0.0);
  EXPECT_EQ(plan_outcome(pb, on, 1e-3, pb.N, margin).kind, Outcome::kClear);
}

TEST(Outcome, AWalkerPassedByCentimetresOneSecondAheadIsAContact) {
  // the same pass against a walker coming the other way at 1.2 m/s: 0.05 m
  // apart 1 s ahead, where its prediction may be 0.15 x 1.2 m off
  const Problem pb = near_pass(-1.2);
  const std::vector<double> on = rollout_of(pb, 0.5, 0.0);
  const OutcomeMargin margin{0.15, 0.3};
  EXPECT_NEAR(mean_predicted_speed(pb.obstacles[0], pb.N, pb.dt), 1.2, 1e-9);
  EXPECT_NEAR(margin.at(1.0, 1.2), 0.18, 1e-12);
  const Outcome bodies = plan_outcome(pb, on, 1e-3, pb.N);
  EXPECT_EQ(bodies.kind, Outcome::kClear);
  EXPECT_NEAR(bodies.clearance, 0.05, 0.01);
  // within the margin, and the robot drives on into it: the robot's
  const Outcome judged = plan_outcome(pb, on, 1e-3, pb.N, margin);
  EXPECT_EQ(judged.kind, Outcome::kOurs);
  EXPECT_GE(judged.first_contact, 5);
  EXPECT_LE(judged.first_contact, 10);
}

}  // namespace
}  // namespace evade::planning
