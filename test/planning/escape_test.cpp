// The turn out of a wall's margin (escape.h): a robot standing beside a
// wall's end, where a turn on the spot swings its footprint into the
// margin whichever way round it goes, turns only as far as it can still
// stop short of it; away from the wall the same turn is made whole.
#include "planning/escape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "box_map.h"
#include "planning/static_structure.h"

namespace evade::planning {
namespace {

constexpr int64_t kT0 = 10'000'000;

// A wall x 3.0..3.2 from y 0 (its end) to 6; the default robot (0.42 x
// 0.31 m, 3 discs) standing at (x0, 0.05) heading north, over N steps of
// 0.1 s. At x0
// 2.72 it is 0.08 m outside the field's margin (d_safe 0.03); facing east
// or west there, its front or rear disc would be 0.06 m inside it.
struct BesideAWallsEnd {
  StaticStructure s{StaticFieldParams{}};
  Problem pb;
  explicit BesideAWallsEnd(double x0, int N = 60) {
    s.keep_map(testing::box_map({{3.0, 3.2, 0.0, 6.0}}, kT0, 1.0f));
    evade::prediction_list_t none;
    none.utime = kT0;
    StaticStructure::Inputs in;
    in.odometry_utime = kT0;
    in.predictions = &none;
    in.track_age_s = [](int64_t) { return 5.0; };
    EXPECT_EQ(s.update(in), StaticStructure::Update::kBuilt);
    pb.N = N;
    pb.dt = 0.1;
    pb.x0 = x0;
    pb.y0 = 0.05;
    pb.yaw0 = M_PI / 2;
    pb.lim = Limits{0.0, 1.0, 0.5, 1.0, 1.5, 3.0};
    pb.footprint = Footprint::covering(0.42, 0.31, 3);
    s.apply(pb.x0, pb.y0, 0.9, &pb);
  }
  const ObstacleTrack& field() const { return pb.obstacles.front(); }
  std::vector<double> states(const std::vector<double>& u) const {
    std::vector<double> x(3 * (pb.N + 1));
    rollout(pb, u.data(), x.data());
    return x;
  }
  // Braking from v0 at the limit (as PlannerCore::braking_controls, the
  // robot not turning).
  std::vector<double> brake(double v0) const {
    std::vector<double> u(2 * pb.N, 0.0);
    for (int k = 0; k < pb.N; ++k) u[2 * k] = v0 = std::max(0.0, v0 - pb.lim.decel * pb.dt);
    return u;
  }
  // The turn from north to south-west, the short way (left, through west)
  // or the long way (right, through east), held short of the wall's margin.
  std::vector<double> turn(int side, double v0) const {
    const double yaw_by = side > 0 ? 3 * M_PI / 4 : -5 * M_PI / 4;
    return turn_on_the_spot(pb, yaw_by, brake(v0), 0.0, &field(), 0.01);
  }
};

TEST(Escape, BesideAWallsEndTheTurnStopsShortOfTheMarginWhicheverWayRound) {
  BesideAWallsEnd w(2.72);
  ASSERT_EQ(w.pb.obstacles.size(), 1u);
  ASSERT_TRUE(w.field().field);
  const std::vector<double> x0{w.pb.x0, w.pb.y0, w.pb.yaw0};
  EXPECT_NEAR(barrier_at(w.pb, w.field(), 0, x0.data()).h, 0.08, 0.02);
  for (int side : {1, -1}) {
    const std::vector<double> u = w.turn(side, 0.0);
    const std::vector<double> x = w.states(u);
    for (int k = 0; k < w.pb.N; ++k) EXPECT_EQ(u[2 * k], 0.0) << "on the spot";
    // into the margin by at most 0.01 m (the turn's momentum included),
    // having turned the asked way, short of south-west by more than 30 deg
    EXPECT_LE(structure_intrusion(w.pb, x), 0.01 + 1e-9) << "side " << side;
    EXPECT_GT(side * (x[3 * w.pb.N + 2] - w.pb.yaw0), 0.1) << "side " << side;
    EXPECT_GT(std::fabs(wrap_angle(x[3 * w.pb.N + 2] + 3 * M_PI / 4)), M_PI / 6) << "side " << side;
  }
}

TEST(Escape, AwayFromTheWallTheTurnIsMadeWholeAtTheLimits) {
  BesideAWallsEnd w(2.3, 90);  // 0.5 m further west: the turn sweeps clear
  for (int side : {1, -1}) {
    const std::vector<double> u = w.turn(side, 0.0);
    const std::vector<double> x = w.states(u);
    EXPECT_LT(std::fabs(wrap_angle(x[3 * w.pb.N + 2] + 3 * M_PI / 4)), 0.02) << "side " << side;
    double omega = 0;
    for (int k = 0; k < w.pb.N; ++k) {
      EXPECT_LE(std::fabs(u[2 * k + 1]), w.pb.lim.omega_max + 1e-12);
      EXPECT_LE(std::fabs(u[2 * k + 1] - omega), w.pb.lim.alpha * w.pb.dt + 1e-12);
      omega = u[2 * k + 1];
    }
  }
}

TEST(Escape, TheSpeedIsTheBrakingProfilesAMovingRobotStops) {
  BesideAWallsEnd w(2.3);
  const std::vector<double> u = w.turn(1, 0.6);
  EXPECT_NEAR(u[0], 0.6 - w.pb.lim.decel * w.pb.dt, 1e-12);
  EXPECT_NEAR(u[2], 0.6 - 2 * w.pb.lim.decel * w.pb.dt, 1e-12);
  for (int k = 4; k < w.pb.N; ++k) EXPECT_EQ(u[2 * k], 0.0) << k;
  const std::vector<double> brake = w.brake(0.6);
  for (int k = 0; k < w.pb.N; ++k) EXPECT_EQ(u[2 * k], brake[2 * k]) << k;
}

TEST(Escape, WithoutAFieldTheTurnIsMadeWholeBesideTheWallToo) {
  // the escape turn out of d_safe (PlannerCore::escape_turn) has no field
  BesideAWallsEnd w(2.72, 90);
  const std::vector<double> u = turn_on_the_spot(w.pb, 3 * M_PI / 4, w.brake(0.0), 0.0);
  const std::vector<double> x = w.states(u);
  EXPECT_LT(std::fabs(wrap_angle(x[3 * w.pb.N + 2] + 3 * M_PI / 4)), 0.02);
  EXPECT_GT(structure_intrusion(w.pb, x), 0.01) << "the field would have held it back";
}

TEST(Escape, TheTurnKeepsTheProblemsTurnBounds) {
  // passive safety's turn bound (passive_safety.h) on the first two steps:
  // no left turn at the first, at most 0.1 rad/s at the second
  BesideAWallsEnd w(2.3, 90);
  w.pb.omega_hi = {0.0, 0.1};
  w.pb.omega_lo = {-0.5, -0.5};
  const std::vector<double> u = turn_on_the_spot(w.pb, 3 * M_PI / 4, w.brake(0.0), 0.0);
  EXPECT_EQ(u[1], 0.0);
  EXPECT_NEAR(u[3], 0.1, 1e-12);
  EXPECT_NEAR(u[5], 0.1 + w.pb.lim.alpha * w.pb.dt, 1e-12) << "unbounded again: at the limits";
  // a turn already under way when the bound comes slows at the limit
  w.pb.omega_hi = {0.0};
  const std::vector<double> going = turn_on_the_spot(w.pb, 3 * M_PI / 4, w.brake(0.0), 0.5);
  EXPECT_NEAR(going[1], 0.5 - w.pb.lim.alpha * w.pb.dt, 1e-12);
}

}  // namespace
}  // namespace evade::planning
