// The planner's input gate (issue 20): late, future and extreme
// timestamps, a non-finite track near the robot, an odometry epoch change,
// base_driver's "stopped" odometry after a lost link; and what the planner
// keeps of the predictions it takes (how long a track has stood still).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bus/memory_bus.h"
#include "config/config.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/input_checks.h"
#include "planning/params.h"
#include "planning/planner_core.h"

namespace evade::planning {
namespace {

constexpr int64_t kT0 = 1'700'000'000'000'000;
constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
constexpr int64_t kMin = std::numeric_limits<int64_t>::min();

PlannerParams params() {
  return PlannerParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
}

evade::path_t route() {
  evade::path_t r{};
  r.n = 2;
  r.x = {0.0, 20.0};
  r.y = {0.0, 0.0};
  return r;
}

// One static track at (x, y), radius 0.3, stamped `utime`.
evade::prediction_list_t one_track(int64_t utime, double x, double y) {
  evade::prediction_list_t m{};
  m.utime = utime;
  m.dt = 0.1;
  m.horizon = 26;
  evade::track_prediction_t t{};
  t.id = 1;
  t.horizon = m.horizon;
  for (int k = 0; k < m.horizon; ++k) {
    t.x.push_back(x);
    t.y.push_back(y);
    t.a.push_back(0.3);
    t.b.push_back(0.3);
    t.theta.push_back(0.0);
    t.sigma.push_back(0.0);
  }
  m.tracks.push_back(t);
  m.num_tracks = 1;
  return m;
}

evade::odometry_t odom(int64_t utime, double x = 0.0, double v = 0.5, int64_t epoch = 7) {
  evade::odometry_t o{};
  o.utime = utime;
  o.x = x;
  o.v = v;
  o.epoch = epoch;
  return o;
}

struct Rig {
  explicit Rig(const PlannerParams& p = params()) : core(p) {
    core.set_measure_latency(false);
    bus.add(core);
    bus.inject("ROUTE", route(), kT0);
  }
  std::vector<evade::plan_t> plans() { return bus.decoded<evade::plan_t>("PLAN"); }
  bus::MemoryBus bus;
  PlannerCore core;
};

TEST(InputChecks, AgesSaturateInsteadOfOverflowing) {
  EXPECT_EQ(age_us(10, 4), 6);
  EXPECT_EQ(age_us(0, kMin), kMax);
  EXPECT_EQ(age_us(kT0, kMax), kT0 - kMax);  // no overflow here
  EXPECT_EQ(age_us(kMax, kMin), kMax);
  EXPECT_EQ(age_us(kMin, kMax), -kMax);
  EXPECT_EQ(arrival(kT0, kT0 - 1'000'000, 250'000), Arrival::kLate);
  EXPECT_EQ(arrival(kT0, kT0 + 10'000'000, 250'000), Arrival::kFuture);
  EXPECT_EQ(arrival(kT0, kT0 - 100'000, 250'000), Arrival::kOnTime);
}

TEST(PlannerInputs, PredictionsOneSecondOldOnArrivalAreStale) {
  Rig r;
  const int64_t t = kT0 + 2'000'000;
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t - 1'000'000, 8.0, 5.0), t);
  r.bus.inject("ODOMETRY", odom(t), t);
  ASSERT_EQ(r.plans().size(), 1u);
  EXPECT_EQ(r.plans()[0].status, int8_t{evade::plan_t::STATUS_STALE_INPUT});
  EXPECT_EQ(r.core.counter("predictions_late"), 1);
  // the same predictions on time: planned
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t + 100'000, 8.0, 5.0), t + 100'000);
  r.bus.inject("ODOMETRY", odom(t + 120'000), t + 120'000);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_OK});
}

TEST(PlannerInputs, AFutureOrExtremeTimestampDoesNotPoisonLaterCycles) {
  Rig r;
  const int64_t t = kT0 + 2'000'000;
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t + 10'000'000, 8.0, 5.0), t);  // 10 s ahead
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(kMax, 8.0, 5.0), t);
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(kMin, 8.0, 5.0), t);
  r.bus.inject("ODOMETRY", odom(t + 10'000'000), t);
  r.bus.inject("ODOMETRY", odom(kMax), t);
  r.bus.inject("ODOMETRY", odom(kMin), t);
  EXPECT_EQ(r.core.counter("predictions_future"), 2);
  EXPECT_EQ(r.core.counter("predictions_late"), 1);
  EXPECT_EQ(r.core.counter("odometry_future"), 2);
  EXPECT_EQ(r.core.counter("odometry_late"), 1);
  EXPECT_TRUE(r.plans().empty());
  // On-time inputs right after are planned at once, as if nothing happened.
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t + 10'000, 8.0, 5.0), t + 10'000);
  r.bus.inject("ODOMETRY", odom(t + 20'000), t + 20'000);
  ASSERT_EQ(r.plans().size(), 1u);
  EXPECT_EQ(r.plans()[0].status, int8_t{evade::plan_t::STATUS_OK});
  for (double v : r.plans()[0].v) EXPECT_TRUE(std::isfinite(v));
}

TEST(PlannerInputs, ANonFiniteTrackNearTheRobotBrakes) {
  Rig r;
  const int64_t t = kT0 + 2'000'000;
  auto m = one_track(t, 1.5, 0.0);
  m.tracks[0].x[5] = NAN;
  r.bus.inject("OBSTACLE_PREDICTIONS", m, t);
  r.bus.inject("ODOMETRY", odom(t), t);
  ASSERT_EQ(r.plans().size(), 1u);
  EXPECT_EQ(r.plans()[0].status, int8_t{evade::plan_t::STATUS_STOPPING});
  EXPECT_LT(r.plans()[0].v[0], 0.5);  // braking from 0.5 m/s
  EXPECT_EQ(r.core.counter("tracks_invalid_near"), 1);
  // ... also when its position itself is unknown
  m = one_track(t + 100'000, NAN, 0.0);
  r.bus.inject("OBSTACLE_PREDICTIONS", m, t + 100'000);
  r.bus.inject("ODOMETRY", odom(t + 120'000), t + 120'000);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_STOPPING});
}

TEST(PlannerInputs, ANonFiniteTrackFarAwayIsDroppedAndCounted) {
  Rig r;
  const int64_t t = kT0 + 2'000'000;
  auto m = one_track(t, 500.0, 0.0);
  m.tracks[0].a[3] = INFINITY;
  r.bus.inject("OBSTACLE_PREDICTIONS", m, t);
  r.bus.inject("ODOMETRY", odom(t), t);
  ASSERT_EQ(r.plans().size(), 1u);
  EXPECT_EQ(r.plans()[0].status, int8_t{evade::plan_t::STATUS_OK});
  EXPECT_EQ(r.core.counter("tracks_invalid_near"), 0);
}

TEST(PlannerInputs, ANewOdometryEpochStopsAndPlansFromScratch) {
  Rig r;
  int64_t t = kT0 + 2'000'000;
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t, 8.0, 5.0), t);
  r.bus.inject("ODOMETRY", odom(t, 3.0, 0.6, 7), t);
  ASSERT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_OK});
  // base_driver restarted: pose reset to 0, a new epoch
  t += 100'000;
  r.bus.inject("ODOMETRY", odom(t, 0.0, 0.0, 8), t);
  EXPECT_EQ(r.core.counter("odometry_epoch_changed"), 1);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_STALE_INPUT});
  EXPECT_EQ(r.bus.decoded<evade::cmd_vel_t>("CMD_VEL").back().v, 0.0);
  // predictions perceived before the change belong to the old frame
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t - 50'000, 8.0, 5.0), t + 10'000);
  EXPECT_EQ(r.core.counter("predictions_before_epoch"), 1);
  t += 100'000;
  r.bus.inject("ODOMETRY", odom(t, 0.0, 0.0, 8), t);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_STALE_INPUT});
  // fresh perception in the new frame: planning resumes
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t + 10'000, 8.0, 5.0), t + 10'000);
  t += 100'000;
  r.bus.inject("ODOMETRY", odom(t, 0.0, 0.0, 8), t);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_OK});
}

TEST(PlannerInputs, OdometryNotNewerThanTheLastIsNotUsed) {
  Rig r;
  const int64_t t = kT0 + 2'000'000;
  r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t, 8.0, 5.0), t);
  r.bus.inject("ODOMETRY", odom(t, 1.0, 0.6), t);
  const size_t n = r.plans().size();
  // base_driver's link-lost message: the last pose, v = 0, the last stamp
  r.bus.inject("ODOMETRY", odom(t, 1.0, 0.0), t + 200'000);
  EXPECT_EQ(r.core.counter("odometry_not_newer"), 1);
  EXPECT_EQ(r.plans().size(), n);
  // nothing fresh follows: the watchdog brakes (STALE_INPUT)
  r.bus.advance_to(t + 400'000);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_STALE_INPUT});
}

// The modes that read OBSTACLES (mpc, cbf, cbf_curvefit) gate them alike.
TEST(PlannerInputs, ObservedObstaclesLateOrBrokenAreNotUsed) {
  PlannerParams p = params();
  p.mode = parse_mode("mpc");
  Rig r(p);
  const int64_t t = kT0 + 2'000'000;
  evade::obstacle_list_t m{};
  m.utime = t - 1'000'000;  // 1 s old on arrival
  m.num_obstacles = 1;
  evade::obstacle_t o{};
  o.id = 1;
  o.x = 1.5;
  o.a = o.b = 0.3;
  m.obstacles.push_back(o);
  r.bus.inject("OBSTACLES", m, t);
  r.bus.inject("ODOMETRY", odom(t), t);
  EXPECT_EQ(r.core.counter("obstacles_late"), 1);
  ASSERT_EQ(r.plans().size(), 1u);
  EXPECT_EQ(r.plans()[0].status, int8_t{evade::plan_t::STATUS_STALE_INPUT});
  // on time but non-finite, 1.5 m ahead: brake
  m.utime = t + 100'000;
  m.obstacles[0].a = NAN;
  r.bus.inject("OBSTACLES", m, t + 100'000);
  r.bus.inject("ODOMETRY", odom(t + 120'000), t + 120'000);
  EXPECT_EQ(r.plans().back().status, int8_t{evade::plan_t::STATUS_STOPPING});
  EXPECT_EQ(r.core.counter("tracks_invalid_near"), 1);
}

// hold_settled holds a track whose centre has stayed within
// solver.still_radius_m for solver.hold_still_s, counted from the last
// time it moved, not from its first sighting: a track that stands 2 s,
// steps 0.5 m and stands again is held only 3 s after the step, its
// centre's jitter (0.05 m here) notwithstanding.
TEST(PlannerInputs, ATrackIsHeldOnlyOnceItsCentreHasStoodStillForHoldStillS) {
  PlannerParams p = params();
  p.solver.hold_settled = true;
  ASSERT_NEAR(p.solver.hold_still_s, 3.0, 1e-9);
  Rig r(p);
  const auto held_at = [&](double until_s, int64_t* step) {
    for (; *step * 100'000 <= std::llround(until_s * 1e6); ++*step) {
      const int64_t t = kT0 + *step * 100'000;
      const double jitter = (*step % 2 ? 0.05 : -0.05), x = 1.5 + (*step >= 20 ? 0.5 : 0.0);
      r.bus.inject("OBSTACLE_PREDICTIONS", one_track(t, x + jitter, 1.0), t);
      r.bus.inject("ODOMETRY", odom(t, 0.0, 0.0), t + 1);
    }
    return r.core.counter("settled_held");
  };
  int64_t step = 0;
  EXPECT_EQ(held_at(1.95, &step), 0);  // still for 2 s: not yet
  EXPECT_EQ(held_at(4.95, &step), 0);  // stepped at 2 s: 3 s only after it
  EXPECT_GT(held_at(5.5, &step), 0);
  EXPECT_EQ(r.core.counter("predictions_late"), 0);
}

}  // namespace
}  // namespace evade::planning
