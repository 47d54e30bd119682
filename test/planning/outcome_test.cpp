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
  std::vector<double> u(pb.num_controls());
  for (int k = 0; k < pb.N; ++k) {
    u[2 * k] = v;
    u[2 * k + 1] = omega;
  }
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

}  // namespace
}  // namespace evade::planning
