// The way round settled obstacles on the route (detour.h): clear routes
// are left alone, a blocked one is gone round with the planner's own
// barrier above the margin, the side is kept against a small change, a
// blocked route end gives no way, and the settled memory expires.
#include "planning/detour.h"

#include <gtest/gtest.h>

#include <cmath>

#include "config/config.h"
#include "planning/params.h"
#include "planning/problem.h"
#include "planning/reference.h"

namespace evade::planning {
namespace {

DetourParams repo_params() {
  return PlannerParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml")).detour;
}
constexpr double kDsafe = 0.35;

RouteFollower straight(double x0, double x1) {
  RouteFollower r;
  EXPECT_TRUE(r.set_route({x0, x1}, {0.0, 0.0}));
  r.update_progress(x0, 0.0, 3.0);
  return r;
}

Ellipse circle(double x, double y, double r) { return {x, y, r, r, 0.0}; }

// Largest lateral offset of a path within [x_lo, x_hi] (signed, by magnitude).
double offset_near(const std::vector<double>& x, const std::vector<double>& y, double x_lo, double x_hi) {
  double best = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (x[i] >= x_lo && x[i] <= x_hi && std::fabs(y[i]) > std::fabs(best)) best = y[i];
  return best;
}

// The lowest barrier h of an obstacle over the points of a way.
double lowest_h(const std::vector<double>& x, const std::vector<double>& y, const Ellipse& o) {
  double h = 1e9;
  for (size_t i = 0; i < x.size(); ++i) h = std::min(h, barrier(x[i], y[i], o.x, o.y, o.a, o.b, o.theta, kDsafe).h);
  return h;
}

TEST(Detour, ARouteThatIsClearIsFollowedAsItIs) {
  DetourPlanner d(repo_params(), kDsafe);
  RouteFollower route = straight(0, 20);
  std::vector<double> x, y;
  // 2.5 m beside the route: far more than d_safe + margin
  EXPECT_EQ(d.plan(route, 0, 0, {circle(5, 2.5, 0.5)}, &x, &y), DetourPlanner::Result::kClear);
  EXPECT_TRUE(x.empty());
  // on the route but beyond the lookahead
  EXPECT_EQ(d.plan(route, 0, 0, {circle(15, 0, 0.5)}, &x, &y), DetourPlanner::Result::kClear);
  EXPECT_EQ(d.plan(route, 0, 0, {}, &x, &y), DetourPlanner::Result::kClear);
}

TEST(Detour, ANarrowBlockageIsLeftToTheMpc) {
  // a bin whose keep-out just reaches over the route: a way round within
  // min_offset_m of it, the MPC's own swerve
  const DetourParams p = repo_params();
  DetourPlanner d(p, kDsafe);
  RouteFollower route = straight(0, 20);
  const Ellipse bin = circle(4, 0.65, 0.3);
  ASSERT_LT(barrier(4, 0, bin.x, bin.y, bin.a, bin.b, bin.theta, kDsafe).h, p.margin_m) << "the route is blocked";
  std::vector<double> x, y;
  EXPECT_EQ(d.plan(route, 0, 0, {bin}, &x, &y), DetourPlanner::Result::kClear);
  EXPECT_TRUE(x.empty());
  DetourParams always = p;
  always.min_offset_m = 0;
  DetourPlanner every(always, kDsafe);
  EXPECT_EQ(every.plan(route, 0, 0, {bin}, &x, &y), DetourPlanner::Result::kDetour);
}

TEST(Detour, AWideObstacleOnTheRouteIsGoneRoundAboveTheMargin) {
  const DetourParams p = repo_params();
  DetourPlanner d(p, kDsafe);
  RouteFollower route = straight(0, 20);
  const std::vector<Ellipse> obs = {circle(4, 0.2, 1.0)};  // a bit to the left: right is shorter
  std::vector<double> x, y;
  ASSERT_EQ(d.plan(route, 0, 0, obs, &x, &y), DetourPlanner::Result::kDetour);
  ASSERT_GE(x.size(), 3u);
  EXPECT_DOUBLE_EQ(x.front(), 0.0);
  EXPECT_DOUBLE_EQ(y.front(), 0.0);
  EXPECT_DOUBLE_EQ(x.back(), 20.0);  // then the rest of the route
  EXPECT_DOUBLE_EQ(y.back(), 0.0);
  // every point of the way keeps the planner's barrier above the margin (the
  // moving average may cut a corner by less than a cell)
  EXPECT_GE(lowest_h(x, y, obs[0]), p.margin_m - p.cell_m);
  EXPECT_LT(offset_near(x, y, 3, 5), -1.0) << "round the right, the shorter side";
  // ...and not much farther than needed: 1.4 m from the centre's line plus the comfort zone
  EXPECT_GT(offset_near(x, y, 3, 5), -(1.0 + kDsafe + p.comfort_m + 0.2 + 0.3));
}

TEST(Detour, TheWayRoundKeepsItsSideWhenTheOtherBecomesSlightlyShorter) {
  DetourPlanner d(repo_params(), kDsafe);
  RouteFollower route = straight(0, 20);
  std::vector<double> x, y;
  ASSERT_EQ(d.plan(route, 0, 0, {circle(4, -0.1, 1.0)}, &x, &y), DetourPlanner::Result::kDetour);
  const double side = offset_near(x, y, 3, 5);
  ASSERT_GT(side, 1.0) << "left, the shorter side at first";
  // the obstacle now sits a little to the left: right is shorter
  const std::vector<Ellipse> moved = {circle(4, 0.1, 1.0)};
  ASSERT_EQ(d.plan(route, 0.3, 0, moved, &x, &y), DetourPlanner::Result::kDetour);
  EXPECT_GT(offset_near(x, y, 3, 5), 1.0) << "kept the left";
  // a planner without that history takes the right
  DetourPlanner fresh(repo_params(), kDsafe);
  ASSERT_EQ(fresh.plan(route, 0.3, 0, moved, &x, &y), DetourPlanner::Result::kDetour);
  EXPECT_LT(offset_near(x, y, 3, 5), -1.0);
}

TEST(Detour, TheWayRoundStaysNearTheRoute) {
  // A wall across the route from y = -1 to y = 2, the robot 1.8 m to the
  // left of the route: over the wall's upper end is a little shorter, round
  // its lower end keeps nearer the route. The lower end is taken.
  DetourPlanner d(repo_params(), kDsafe);
  RouteFollower route = straight(0, 20);
  std::vector<Ellipse> wall;
  for (double wy = -1.0; wy <= 2.01; wy += 0.5) wall.push_back(circle(5, wy, 0.3));
  std::vector<double> x, y;
  ASSERT_EQ(d.plan(route, 0, 1.8, wall, &x, &y), DetourPlanner::Result::kDetour);
  EXPECT_LT(offset_near(x, y, 4.5, 5.5), -1.0);
  // without the cost of leaving the route, the upper end
  DetourParams p = repo_params();
  p.deviation_cost = 0;
  DetourPlanner shortest(p, kDsafe);
  ASSERT_EQ(shortest.plan(route, 0, 1.8, wall, &x, &y), DetourPlanner::Result::kDetour);
  EXPECT_GT(offset_near(x, y, 4.5, 5.5), 2.0);
}

TEST(Detour, AnObstacleOnARoutesCornerIsGoneRoundAndTheRouteResumed) {
  // route (0, 0) -> (6, 0) -> (6, 8), an obstacle on the corner
  const DetourParams p = repo_params();
  DetourPlanner d(p, kDsafe);
  RouteFollower route;
  ASSERT_TRUE(route.set_route({0, 6, 6}, {0, 0, 8}));
  route.update_progress(2, 0, 3.0);
  const Ellipse o = circle(6, 0, 0.8);
  std::vector<double> x, y;
  ASSERT_EQ(d.plan(route, 2, 0, {o}, &x, &y), DetourPlanner::Result::kDetour);
  EXPECT_DOUBLE_EQ(x.back(), 6.0);
  EXPECT_DOUBLE_EQ(y.back(), 8.0);
  EXPECT_GE(lowest_h(x, y, o), p.margin_m - p.cell_m);
  // it cuts inside the corner (up and left of it: the shorter way, nearer the route)
  EXPECT_GT(offset_near(x, y, 4.5, 5.5), 0.5);
}

TEST(Detour, ABlockedRouteEndOrATooLargeGridGivesNoWay) {
  DetourPlanner d(repo_params(), kDsafe);
  RouteFollower route = straight(0, 6);
  std::vector<double> x, y;
  EXPECT_EQ(d.plan(route, 0, 0, {circle(5.5, 0, 1.0)}, &x, &y), DetourPlanner::Result::kNoWay);
  EXPECT_TRUE(x.empty());
  // a long route blocked far beyond the reach of any grid
  RouteFollower long_blocked = straight(0, 1000);
  EXPECT_EQ(d.plan(long_blocked, 0, 0, {{500, 0, 498, 1.0, 0.0}}, &x, &y), DetourPlanner::Result::kNoWay);
  // a robot reported far off its route (a bad odometry fix)
  EXPECT_EQ(d.plan(long_blocked, 1e12, -1e12, {circle(4, 0, 1.0)}, &x, &y), DetourPlanner::Result::kNoWay);
  // progress 1e17 m along a route, where a 0.1 m step does not change the
  // arc length: the scan ends (it counts its steps; adding them hung here)
  // and whatever comes out is finite
  RouteFollower far_route;
  ASSERT_TRUE(far_route.set_route({0.0, 2e17}, {0.0, 0.0}));
  far_route.update_progress(1e17, 0, 3.0);
  ASSERT_GT(far_route.progress(), 9e16);
  d.plan(far_route, 1e17, 0, {circle(1e17, 0, 1.0)}, &x, &y);
  for (size_t i = 0; i < x.size(); ++i) EXPECT_TRUE(std::isfinite(x[i]) && std::isfinite(y[i])) << i;
  // a wall across the whole grid: no gap, the route is followed as it is
  std::vector<Ellipse> wall;
  for (double wy = -5.0; wy <= 5.01; wy += 0.4) wall.push_back(circle(5, wy, 0.3));
  RouteFollower through = straight(0, 20);
  EXPECT_EQ(d.plan(through, 0, 0, wall, &x, &y), DetourPlanner::Result::kNoWay);
  EXPECT_TRUE(x.empty());
  DetourParams small = repo_params();
  small.max_cells = 100;
  DetourPlanner tiny(small, kDsafe);
  RouteFollower long_route = straight(0, 20);
  EXPECT_EQ(tiny.plan(long_route, 0, 0, {circle(4, 0, 1.0)}, &x, &y), DetourPlanner::Result::kNoWay);
}

TEST(Detour, ARobotInsideTheMarginIsLedOut) {
  const DetourParams p = repo_params();
  DetourPlanner d(p, kDsafe);
  RouteFollower route = straight(0, 20);
  // the robot at (3, -0.9) is 0.1 m beyond the ellipse: h < 0
  const Ellipse o = circle(4, 0, 1.0);
  ASSERT_LT(barrier(3.0, -0.9, o.x, o.y, o.a, o.b, o.theta, kDsafe).h, 0.0);
  route.update_progress(3.0, -0.9, 3.0);
  std::vector<double> x, y;
  ASSERT_EQ(d.plan(route, 3.0, -0.9, {o}, &x, &y), DetourPlanner::Result::kDetour);
  // the way leaves the blocked zone and does not cross the obstacle
  bool out = false;
  for (size_t i = 0; i < x.size(); ++i) {
    const double h = barrier(x[i], y[i], o.x, o.y, o.a, o.b, o.theta, kDsafe).h;
    EXPECT_GT(h, -0.2) << "point " << i;
    out = out || h >= p.margin_m;
  }
  EXPECT_TRUE(out);
  EXPECT_DOUBLE_EQ(x.back(), 20.0);
}

TEST(SettledMemory, KeepsEachTracksLastEllipseForItsMemoryThenForgetsIt) {
  SettledMemory m(3.0);
  m.update(1'000'000, {{1, circle(1, 1, 0.5)}, {2, circle(2, 2, 0.5)}});
  m.update(2'000'000, {{1, circle(1.1, 1, 0.5)}});  // 2 not seen settled now
  ASSERT_EQ(m.size(), 2u);
  const auto now = m.obstacles();
  ASSERT_EQ(now.size(), 2u);
  EXPECT_DOUBLE_EQ(now[0].x, 1.1);                  // id 1 updated
  m.update(4'500'000, {{1, circle(1.2, 1, 0.5)}});  // 2 last seen 3.5 s ago
  ASSERT_EQ(m.size(), 1u);
  EXPECT_DOUBLE_EQ(m.obstacles()[0].x, 1.2);
  m.update(1'000'000, {});  // time went back (a new log): nothing stale survives
  EXPECT_EQ(m.size(), 0u);
}

TEST(SettledMemory, ForgetsATrackSeenMovingAtOnce) {
  SettledMemory m(3.0);
  m.update(1'000'000, {{1, circle(1, 1, 0.5)}, {2, circle(2, 2, 0.5)}});
  m.update(1'100'000, {{2, circle(2, 2, 0.5)}}, {1});  // 1 walks on
  ASSERT_EQ(m.size(), 1u);
  EXPECT_DOUBLE_EQ(m.obstacles()[0].x, 2.0);
}

}  // namespace
}  // namespace evade::planning
