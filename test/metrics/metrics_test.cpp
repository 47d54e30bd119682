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
    s.duration_s = 11.0;
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
    s.lidar_returns = {40, 40};
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
  // every plan's solve time: 1.00 + 0.01 i ms, i = 0..110; p99 at i = 108.9
  ASSERT_TRUE(m.planner_cycle_ms_p99);
  EXPECT_NEAR(*m.planner_cycle_ms_p99, 2.089, 1e-9);
  EXPECT_TRUE(m.contacts.empty());
  EXPECT_TRUE(m.success);
  EXPECT_FALSE(m.timed_out);
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
    s.obstacles[1].y = 30.0;                // far, then ...
    if (s.x > 0.0) s.obstacles[1].y = 3.0;  // ... inside the map once the robot passes x = 0
    s.v = s.x > 0.0 && s.x < 5.0 ? (std::fmod(s.x, 1.0) < 0.5 ? 0.8 : 1.2) : s.v;
    e.data = bus::encode(s);
  }
  auto m = compute_metrics(ev, MetricsParams{});
  ASSERT_TRUE(m.speed_var);
  EXPECT_NEAR(*m.speed_var, 0.04, 0.002);  // speeds 0.8 and 1.2 in equal shares
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
  EXPECT_EQ(m.contacts.size(), 1u);
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

// Rewrites every SIM_TRUTH of a run with fn(sample, t) (t in s since the first).
template <class Fn>
void edit_truth(std::vector<bus::LogEvent>* ev, Fn fn) {
  for (auto& e : *ev) {
    if (e.channel != "SIM_TRUTH") continue;
    evade::sim_truth_t s;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &s));
    fn(&s, (s.utime - 1'000'000) * 1e-6);
    e.data = bus::encode(s);
  }
}

TEST(Contacts, DrivingIntoAStaticObstacleIsAtFault) {
  auto ev = straight_run();
  // the static cylinder (r 0.25) on the robot's line at x = 0: the front
  // edge (x + 0.21) touches it at x = -0.46 (t = 5.04 s), the rear edge
  // leaves it at x = 0.46 (t = 5.96 s); deepest: centre inside, 0.155 to
  // the side edges, + 0.25
  edit_truth(&ev, [](evade::sim_truth_t* s, double) { s->obstacles[0].y = 0.0; });
  auto m = compute_metrics(ev, MetricsParams{});
  ASSERT_EQ(m.contacts.size(), 1u);
  const Contact& c = m.contacts[0];
  EXPECT_EQ(c.obstacle_id, 0);
  EXPECT_NEAR(c.t_start_s, 5.04, 0.011);
  EXPECT_NEAR(c.t_end_s, 5.96, 0.011);
  EXPECT_NEAR(c.max_penetration_m, 0.405, 1e-9);
  EXPECT_NEAR(c.robot_speed_mps, 1.0, 1e-12);
  EXPECT_NEAR(c.approach_speed_mps, 1.0, 1e-9);  // straight at it
  EXPECT_TRUE(c.at_fault);
  EXPECT_TRUE(m.collided);
  EXPECT_TRUE(m.at_fault);
  EXPECT_EQ(m.collisions_at_fault, 1);
  EXPECT_EQ(m.collisions_not_at_fault, 0);
  EXPECT_TRUE(m.reached_goal);
  EXPECT_FALSE(m.success);  // reached, but hit something on the way
  // a threshold above the approach speed: the same contact is not at fault
  MetricsParams lenient;
  lenient.fault_approach_speed_mps = 1.5;
  EXPECT_FALSE(compute_metrics(ev, lenient).contacts.at(0).at_fault);
}

TEST(Contacts, AMoverWalkingIntoAStandingRobotIsNotAtFaultAndEachPassIsOneContact) {
  auto ev = straight_run();
  // the robot stands at x = -5 for the whole run; the mover walks back and
  // forth across it (y = 2.5 sin(2 pi (t - 1.25) / 5): through y = 0 at
  // t = 1.25, 3.75, 6.25, 8.75 s)
  edit_truth(&ev, [](evade::sim_truth_t* s, double t) {
    s->x = -5.0;
    s->v = 0.0;
    s->obstacles[1].x = -5.0;
    s->obstacles[1].y = 2.5 * std::sin(2 * M_PI * (t - 1.25) / 5.0);
    s->obstacles[1].vy = 2.5 * 2 * M_PI / 5.0 * std::cos(2 * M_PI * (t - 1.25) / 5.0);
  });
  auto m = compute_metrics(ev, MetricsParams{});
  ASSERT_EQ(m.contacts.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(m.contacts[i].obstacle_id, 1);
    EXPECT_NEAR(m.contacts[i].t_start_s, 1.25 + 2.5 * i, 0.15);
    EXPECT_LT(m.contacts[i].t_start_s, 1.25 + 2.5 * i);  // contact starts before the centres meet
    EXPECT_NEAR(m.contacts[i].max_penetration_m, 0.405, 0.01);
    EXPECT_EQ(m.contacts[i].approach_speed_mps, 0.0);
    EXPECT_FALSE(m.contacts[i].at_fault);
  }
  EXPECT_TRUE(m.collided);
  EXPECT_FALSE(m.at_fault);
  EXPECT_EQ(m.collisions_not_at_fault, 4);
  EXPECT_FALSE(m.reached_goal);
  EXPECT_TRUE(m.timed_out);
  EXPECT_FALSE(m.success);
}

TEST(Contacts, HitFromTheSideWhileDrivingPastIsNotAtFault) {
  auto ev = straight_run();
  // the robot drives along y = 0 at 1 m/s; a mover comes down x = 0 from
  // the left at 1 m/s and reaches y = 0.405 (contact) as the robot's
  // centre is under it: the robot's own velocity is across the contact
  // direction, not towards it
  edit_truth(&ev, [](evade::sim_truth_t* s, double t) {
    s->obstacles[1].x = 0.0;
    s->obstacles[1].y = 0.405 + 5.5 - t;
    s->obstacles[1].vy = -1.0;
  });
  auto m = compute_metrics(ev, MetricsParams{});
  ASSERT_GE(m.contacts.size(), 1u);
  const Contact& c = m.contacts[0];
  EXPECT_EQ(c.obstacle_id, 1);
  EXPECT_NEAR(c.t_start_s, 5.5, 0.02);
  EXPECT_NEAR(c.robot_speed_mps, 1.0, 1e-12);
  EXPECT_NEAR(c.approach_speed_mps, 0.0, 0.02);
  EXPECT_FALSE(c.at_fault);
}

TEST(Contacts, PointVelocityIncludesTheTurn) {
  evade::sim_truth_t s{};
  s.x = 1.0;
  s.y = 2.0;
  s.yaw = M_PI / 2;
  s.v = 0.5;    // along +y
  s.omega = 1;  // counter-clockwise
  // the front-left corner of a 0.42 x 0.31 footprint: (1 - 0.155, 2 + 0.21)
  const Vec2 p{1.0 - 0.155, 2.21};
  // v = (0, 0.5) + omega x (p - c) = (0, 0.5) + (-0.21, -0.155)
  EXPECT_NEAR(point_velocity_along(s, p, {0, 1}), 0.5 - 0.155, 1e-12);
  EXPECT_NEAR(point_velocity_along(s, p, {-1, 0}), 0.21, 1e-12);
}

TEST(RunMetrics, NoTruthIsAnError) { EXPECT_THROW(compute_metrics({}, MetricsParams{}), std::runtime_error); }

}  // namespace
}  // namespace evade::metrics
