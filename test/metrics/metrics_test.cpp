#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bus/core.h"
#include "evade/plan_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "metrics/run_metrics.h"
#include "metrics/trajectory_plot.h"

namespace evade::metrics {
namespace {

TEST(Geometry, RectangleToCircle) {
  OrientedRect r{{0, 0}, 0.0, 2.0, 1.0};
  EXPECT_NEAR(clearance(r, Vec2{3, 0}, 0.5), 1.5, 1e-12);
  EXPECT_NEAR(clearance(r, Vec2{2, 1.5}, 0.0), std::sqrt(2.0), 1e-12);  // nearest: the corner (1, 0.5)
  EXPECT_NEAR(clearance(r, Vec2{0, 0}, 0.1), -0.6, 1e-12);              // centre inside: 0.5 to the edge + r
  // rotated by 90 degrees: the long side now along y
  OrientedRect q{{0, 0}, M_PI / 2, 2.0, 1.0};
  EXPECT_NEAR(clearance(q, Vec2{0, 3}, 0.5), 1.5, 1e-12);
  EXPECT_NEAR(clearance(q, Vec2{3, 0}, 0.5), 2.0, 1e-12);
}

TEST(Geometry, RectangleToRectangle) {
  OrientedRect a{{0, 0}, 0.0, 2.0, 1.0};
  EXPECT_NEAR(clearance(a, OrientedRect{{3, 0}, 0.0, 2.0, 1.0}), 1.0, 1e-12);
  // a diamond whose corner points at a's right edge from 0.5 m away
  double h = 0.5 * std::sqrt(2.0);
  EXPECT_NEAR(clearance(a, OrientedRect{{1.5 + h, 0}, M_PI / 4, 1.0, 1.0}), 0.5, 1e-12);
  EXPECT_LT(clearance(a, OrientedRect{{1.5, 0}, 0.3, 2.0, 1.0}), 0.0);
  // corner to corner along the diagonal
  EXPECT_NEAR(clearance(a, OrientedRect{{3, 2}, 0.0, 2.0, 1.0}), std::hypot(1.0, 1.0), 1e-12);
}

std::vector<bus::LogEvent> straight_run() {
  // Robot along y = 0 at 1 m/s from x = -5 to x = 5 (goal 5, tolerance 0.3),
  // a static cylinder at (0, 1) and a mover crossing far ahead.
  std::vector<bus::LogEvent> ev;
  for (int k = 0; k <= 1100; ++k) {
    double t = k * 0.01;  // 100 Hz
    evade::sim_truth_t s{};
    s.utime = 1'000'000 + k * 10'000;
    s.x = std::min(-5.0 + std::max(t - 0.5, 0.0), 5.0);
    s.v = (t >= 0.5 && s.x < 5.0) ? 1.0 : 0.0;
    s.footprint_length = 0.42;
    s.footprint_width = 0.31;
    s.scenario = "straight";
    s.goal_x = 5.0;
    s.goal_tolerance = 0.3;
    s.obstacles_moving = t >= 0.5;
    evade::sim_obstacle_t o{};
    o.id = 0;
    o.shape = "cylinder";
    o.x = 0.0;
    o.y = 1.0;
    o.radius = 0.25;
    o.height = 0.5;
    s.obstacles.push_back(o);
    evade::sim_obstacle_t m = o;
    m.id = 1;
    m.x = 20.0;
    m.y = -10.0 + (t >= 0.5 ? (t - 0.5) : 0.0);
    m.vy = t >= 0.5 ? 1.0 : 0.0;
    s.obstacles.push_back(m);
    s.num_obstacles = 2;
    ev.push_back({s.utime, "SIM_TRUTH", bus::encode(s)});
    if (k % 10 == 0) {
      evade::plan_t p{};
      p.utime = s.utime;
      p.mode = "dcbf";
      p.status = (k == 500) ? evade::plan_t::STATUS_FALLBACK : evade::plan_t::STATUS_OK;
      p.iterations = 5;
      p.solve_time_us = 1000 + 10 * (k / 10);  // 1.00 .. 2.10 ms
      ev.push_back({s.utime, "PLAN", bus::encode(p)});
    }
  }
  return ev;
}

TEST(RunMetrics, StraightRunKnownAnswers) {
  auto m = compute_metrics(straight_run(), MetricsParams{});
  EXPECT_TRUE(m.reached_goal);
  EXPECT_FALSE(m.collided);
  // footprint half-width 0.155 and radius 0.25 from the centre line at 1 m
  EXPECT_NEAR(m.min_dist_m, 1.0 - 0.155 - 0.25, 1e-9);
  EXPECT_EQ(m.closest_obstacle, 0);
  // moving from t = 0.51 s (first sample above threshold); goal within 0.3 m at x = 4.7
  ASSERT_TRUE(m.time_to_goal_s);
  EXPECT_NEAR(*m.time_to_goal_s, 9.7, 0.02);
  EXPECT_NEAR(m.path_length_m, 9.7, 0.02);
  // the mover enters the 10 m square around the robot when |dx| <= 5 and
  // |dy| <= 5: never here (dx >= 15), so no speed variance and no reaction
  EXPECT_FALSE(m.speed_var);
  EXPECT_EQ(m.solver_failures, 1);
  EXPECT_EQ(m.plans, 111);
  ASSERT_TRUE(m.planner_solve_ms_p50);
  EXPECT_NEAR(*m.planner_solve_ms_p50, 1.55, 1e-9);
  EXPECT_EQ(m.scenario, "straight");
  EXPECT_EQ(m.mode, "dcbf");
}

TEST(RunMetrics, SpeedVarianceWhileADynamicObstacleIsNear) {
  auto ev = straight_run();
  // move the crossing obstacle close: x = 2 so it is inside the map early
  for (auto& e : ev) {
    if (e.channel != "SIM_TRUTH") continue;
    evade::sim_truth_t s;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &s));
    s.obstacles[1].x = 2.0;
    s.obstacles[1].y = 30.0;  // far, then ...
    if (s.x > 0.0) s.obstacles[1].y = 3.0;  // ... inside the map once the robot passes x = 0
    s.v = s.x > 0.0 && s.x < 5.0 ? (std::fmod(s.x, 1.0) < 0.5 ? 0.8 : 1.2) : s.v;
    e.data = bus::encode(s);
  }
  auto m = compute_metrics(ev, MetricsParams{});
  ASSERT_TRUE(m.speed_var);
  EXPECT_NEAR(*m.speed_var, 0.04, 0.002);  // speeds 0.8 and 1.2 in equal shares
}

TEST(RunMetrics, ReactionTimeFromTheFirstActiveConstraintOfAMatchedTrack) {
  auto ev = straight_run();
  // The crossing obstacle enters the local map at t = 4.0 s: put it at
  // x = 2 (robot at x = -1.5 then, |dx| = 3.5 <= 5) with y from -5 upward.
  for (auto& e : ev) {
    if (e.channel == "SIM_TRUTH") {
      evade::sim_truth_t s;
      ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &s));
      double t = (s.utime - 1'000'000) * 1e-6;
      s.obstacles[1].x = 2.0;
      s.obstacles[1].y = t < 4.0 ? -30.0 : -5.0 + (t - 4.0);
      e.data = bus::encode(s);
    } else if (e.channel == "PLAN") {
      evade::plan_t p;
      ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &p));
      double t = (p.utime - 1'000'000) * 1e-6;
      // A track of it from t = 4.5 s, 0.3 m off its true centre; its
      // constraint becomes active at t = 5.5 s. A far track is always active.
      if (t >= 4.5) {
        p.obstacle_id = {7, 9};
        p.obstacle_x = {2.3, 20.0};
        p.obstacle_y = {-5.0 + (t - 4.0), 20.0};
        p.obstacle_slack = {t >= 5.5 ? 0.001 : 0.5, 0.0};
        p.num_obstacles = 2;
      }
      e.data = bus::encode(p);
    }
  }
  auto m = compute_metrics(ev, MetricsParams{});
  ASSERT_TRUE(m.reaction_time_s);
  EXPECT_NEAR(*m.reaction_time_s, 1.5, 0.011);  // 4.0 s -> 5.5 s (plans at 10 Hz)
  EXPECT_EQ(m.reaction_missed, 0);
}

TEST(RunMetrics, CollisionAndPicture) {
  auto ev = straight_run();
  for (auto& e : ev) {
    if (e.channel != "SIM_TRUTH") continue;
    evade::sim_truth_t s;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &s));
    s.obstacles[0].y = 0.3;  // overlaps the footprint as the robot passes
    e.data = bus::encode(s);
  }
  auto m = compute_metrics(ev, MetricsParams{});
  EXPECT_TRUE(m.collided);
  EXPECT_LT(m.min_dist_m, 0.0);
  std::string png = ::testing::TempDir() + "/metrics_test.png";
  plot_trajectory(m, png);
  FILE* f = std::fopen(png.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  unsigned char sig[8];
  ASSERT_EQ(std::fread(sig, 1, 8, f), 8u);
  std::fclose(f);
  EXPECT_EQ(sig[1], 'P');
  EXPECT_EQ(sig[2], 'N');
  EXPECT_EQ(sig[3], 'G');
}

TEST(RunMetrics, NoTruthIsAnError) {
  EXPECT_THROW(compute_metrics({}, MetricsParams{}), std::runtime_error);
}

}  // namespace
}  // namespace evade::metrics
