// Mode evade near a region hidden behind a parked van (OCCLUSIONS): the
// plan's speed is at most the stopping-safe bound of
// lib/planning/occlusion_speed.h, and without the region it is not.
#include "planning/occlusion_speed.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../planning/drive_harness.h"
#include "config/config.h"
#include "evade/hidden_region_list_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/params.h"

namespace evade::planning {
namespace {

// robot.yaml's planner (the speed bound on by default).
PlannerParams default_params() {
  auto p = PlannerParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
  return p;
}

// The shadow of a van's near face x in [3, 7.5], y = 0.9 (the route runs
// along y = 0), seen from (sx, 0): side edges from the face's ends, away
// from the sensor.
evade::hidden_region_list_t van_shadow(double sx, int64_t utime) {
  evade::hidden_region_list_t m;
  m.utime = utime;
  m.sensor_x = sx;
  m.sensor_y = 0.0;
  evade::hidden_region_t r{};
  const double px[2] = {7.5, 3.0}, py[2] = {0.9, 0.9};
  for (int i = 0; i < 2; ++i) {
    const double dx = px[i] - sx, dy = py[i], d = std::hypot(dx, dy);
    r.near_x[i] = px[i];
    r.near_y[i] = py[i];
    r.far_x[i] = px[i] + 4.0 * dx / d;
    r.far_y[i] = py[i] + 4.0 * dy / d;
  }
  r.occluder_height_m = 1.8;
  r.occluder_cells = 45;
  m.regions = {r};
  m.num_regions = 1;
  return m;
}

struct Sample {
  double x, y, yaw, v;  // the plan's start and its first command
  double bound;         // the stopping-safe speed there (at least min_speed_mps)
};

// The robot drives a 12 m route past the van for 30 s, following CMD_VEL
// exactly (DriveHarness); one sample per plan.
std::vector<Sample> drive_past_van(const PlannerParams& p, bool with_region) {
  testing::DriveHarness loop(p);
  const testing::RobotState& robot = loop.robot();
  evade::path_t route{};
  route.n = 2;
  route.x = {0.0, 12.0};
  route.y = {0.0, 0.0};
  loop.bus().inject("ROUTE", route, testing::DriveHarness::kStartUs);
  double reach = 0;
  for (double o : p.footprint.offsets) reach = std::max(reach, std::fabs(o));
  reach += p.footprint.radius;
  std::vector<Sample> out;
  loop.run(
      30.0,
      [&](const testing::DriveHarness::Step& s) {
        if (s.i % 5 != 0) return;
        evade::prediction_list_t none{};
        none.utime = s.now;
        none.dt = 0.1;
        none.horizon = 26;
        if (with_region) loop.bus().inject("OCCLUSIONS", van_shadow(robot.x, s.now), s.now);
        loop.bus().inject("OBSTACLE_PREDICTIONS", none, s.now);
      },
      [&](const evade::plan_t& pl, const testing::DriveHarness::Step& s) {
        if (pl.horizon < 1 || pl.v.empty()) return;
        const double d = distance_to_exit_ahead(van_shadow(robot.x, s.now).regions[0], pl.x[0], pl.y[0], pl.yaw[0]);
        const double bound = std::isfinite(d) ? stopping_safe_speed(p.occlusion, p.limits.decel, d - reach) : 1e9;
        out.push_back({pl.x[0], pl.y[0], pl.yaw[0], pl.v[0], std::max(bound, p.occlusion.min_speed_mps)});
      });
  return out;
}

TEST(OcclusionSpeed, StoppingSafeSpeedFollowsTheBrakingModel) {
  OcclusionSpeedParams p;
  p.walking_speed_mps = 1.5;
  p.reaction_s = 0.3;
  p.clearance_m = 0.3;
  // 1.8 m from the footprint: the person needs 1 s, the robot brakes for 0.7 s.
  EXPECT_NEAR(stopping_safe_speed(p, 1.5, 1.8), 1.05, 1e-12);
  EXPECT_EQ(stopping_safe_speed(p, 1.5, 0.5), 0.0);  // within reaction distance
  EXPECT_LT(stopping_safe_speed(p, 1.5, 1.0), stopping_safe_speed(p, 1.5, 1.2));
}

TEST(OcclusionSpeed, OnlyEdgesAheadOfTheRobotCount) {
  const evade::hidden_region_t r = van_shadow(0.0, 0).regions[0];
  EXPECT_NEAR(distance_to_exit_ahead(r, 7.0, 0.0, 0.0), std::hypot(0.5, 0.9), 1e-9);  // the front corner ahead
  EXPECT_TRUE(std::isinf(distance_to_exit_ahead(r, 7.6, 0.0, 0.0)));                  // just past it
  EXPECT_TRUE(std::isfinite(distance_to_exit_ahead(r, 12.0, 0.0, M_PI)));             // coming back
}

TEST(OcclusionSpeed, PlanPassingAVanKeepsTheStoppingSafeSpeed) {
  const PlannerParams p = default_params();
  ASSERT_TRUE(p.occlusion.enabled);
  const auto samples = drive_past_van(p, true);
  ASSERT_GT(samples.size(), 50u);
  double slowest_near = 1e9, final_x = 0;
  int checked = 0;
  for (const auto& s : samples) {
    final_x = std::max(final_x, s.x);
    if (s.bound >= p.limits.v_max) continue;
    ++checked;
    EXPECT_LE(s.v, s.bound + 0.02) << "at x " << s.x;
    if (s.x > 5.0 && s.x < 7.5) slowest_near = std::min(slowest_near, s.v);
  }
  EXPECT_GT(checked, 10);
  EXPECT_LT(slowest_near, 0.5);
  EXPECT_GT(final_x, 10.0) << "the robot must get past the van";
}

TEST(OcclusionSpeed, WithoutTheRegionThePlanIsFasterThanTheBound) {
  const PlannerParams p = default_params();
  const auto samples = drive_past_van(p, false);
  int over = 0;
  for (const auto& s : samples) over += s.v > s.bound + 0.05;
  EXPECT_GT(over, 5);  // the bound is not met by chance
}

}  // namespace
}  // namespace evade::planning
