// Known-answer tests of the local map: odometry interpolation, the obstacle
// layer on analytic terrains (flat, ramps, steps, data edges), hole filling,
// and whole ray-cast VLP-16 revolutions through the builder and the core.
#include <gtest/gtest.h>
#include <malloc.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include "bus/memory_bus.h"
#include "mapping/elevation_map.h"
#include "mapping/elevation_map_core.h"
#include "mapping/synthetic_scan.h"

namespace evade::mapping {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// The struct's defaults (the values of config/robot.yaml, checked below) on
// the 10 x 10 m map the tests' geometry is laid out on.
ElevationMapParams defaults() {
  ElevationMapParams p;
  p.size_x_m = p.size_y_m = 10.0;
  return p;
}

TEST(Config, RobotYamlSectionLoadsAndMatchesTestDefaults) {
  const auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  const auto p = ElevationMapParams::from_config(root.section("elevation_map"));
  const ElevationMapParams d;
  EXPECT_EQ(p.width(), 240);
  EXPECT_EQ(p.height(), 240);
  EXPECT_EQ(p.width(), d.width());
  EXPECT_EQ(p.height(), d.height());
  EXPECT_DOUBLE_EQ(p.sobel_max, d.sobel_max);
  EXPECT_DOUBLE_EQ(p.laplace_max_per_m, d.laplace_max_per_m);
  EXPECT_DOUBLE_EQ(p.step_max_m, d.step_max_m);
}

// The core's factory takes the whole configuration and returns the core's
// own class, as every core's does (CONTRIBUTING.md, "Add a process").
TEST(Config, TheFactoryBuildsTheCoreFromTheWholeConfig) {
  const auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  static_assert(std::is_same_v<decltype(ElevationMapCore::from_config(root)), std::unique_ptr<ElevationMapCore>>);
  const std::unique_ptr<ElevationMapCore> core = ElevationMapCore::from_config(root);
  ASSERT_NE(core, nullptr);
  EXPECT_EQ(core->name(), "elevation_map");
}

TEST(Config, UnknownKeyIsAnError) {
  const auto root = config::load_string(
      "elevation_map: {size_x_m: 10, size_y_m: 10, resolution_m: 0.1, min_z_m: -1, max_z_m: 2, min_range_m: 0.4,"
      " max_range_m: 100, sweep_slice_s: 0.001, max_sweep_s: 0.2, odometry_history_s: 2, max_extrapolation_s: 0.1,"
      " hole_fill_min_neighbors: 5, sobel_max: 0.6, laplace_max_per_m: 15, step_max_m: 0.15,"
      " step_includes_cell_extent: true, sobel_maxx: 1}",
      "t.yaml");
  EXPECT_THROW(ElevationMapParams::from_config(root.section("elevation_map")), config::ConfigError);
}

// ---------------------------------------------------------------- odometry
OdometrySample odo(int64_t t, double x, double y, double yaw, double v = 0, double w = 0) {
  OdometrySample s;
  s.utime = t;
  s.pose = {x, y, yaw};
  s.v = v;
  s.omega = w;
  return s;
}

TEST(PoseBuffer, InterpolatesPositionAndYawOnTheShortArc) {
  PoseBuffer b(2'000'000);
  b.add(odo(1'000'000, 0, 0, M_PI - 0.1));
  b.add(odo(1'020'000, 1, 2, -M_PI + 0.1));
  const auto p = b.at(1'005'000, 0);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, 0.25, 1e-12);
  EXPECT_NEAR(p->y, 0.5, 1e-12);
  EXPECT_NEAR(std::abs(p->yaw), M_PI - 0.05, 1e-9);  // through +-pi, not through 0
}

TEST(PoseBuffer, ExtrapolatesAlongTheArcWithinTheLimitOnly) {
  PoseBuffer b(2'000'000);
  b.add(odo(1'000'000, 0, 0, 0, 1.0, 0.5));
  const auto p = b.at(1'100'000, 150'000);
  ASSERT_TRUE(p);
  // arc of radius 2 m through 0.05 rad
  EXPECT_NEAR(p->x, 2.0 * std::sin(0.05), 1e-12);
  EXPECT_NEAR(p->y, 2.0 * (1 - std::cos(0.05)), 1e-12);
  EXPECT_NEAR(p->yaw, 0.05, 1e-12);
  EXPECT_FALSE(b.at(1'200'000, 150'000));
  EXPECT_FALSE(b.at(800'000, 150'000));
}

TEST(PoseBuffer, DropsOutOfOrderAndResetsOnALogLoop) {
  PoseBuffer b(1'000'000);
  EXPECT_EQ(b.add(odo(5'000'000, 0, 0, 0)), PoseBuffer::AddResult::kAdded);
  EXPECT_EQ(b.add(odo(4'990'000, 0, 0, 0)), PoseBuffer::AddResult::kOutOfOrder);
  EXPECT_EQ(b.add(odo(1'000'000, 0, 0, 0)), PoseBuffer::AddResult::kReset);
  EXPECT_EQ(b.size(), 1u);
  for (int i = 1; i <= 200; ++i) b.add(odo(1'000'000 + i * 20'000, 0, 0, 0));
  EXPECT_LE(b.size(), 52u);  // bounded by the history length
}

// ---------------------------------------------------------- obstacle layer
ElevationLayers terrain(int w, int h, double res, const std::function<double(double, double)>& z) {
  ElevationLayers L;
  L.reset(0, 0, res, w, h);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const float v = float(z((c + 0.5) * res, (r + 0.5) * res));
      L.z_max[L.index(r, c)] = v;
      L.z_min[L.index(r, c)] = v;
    }
  return L;
}

int count_obstacles(const ElevationLayers& L) {
  int n = 0;
  for (auto o : L.obstacle) n += o;
  return n;
}

TEST(ObstacleLayer, FlatGroundHasNoObstacle) {
  auto L = terrain(40, 30, 0.1, [](double, double) { return 0.3; });
  ObstacleTerms t;
  compute_obstacle_layer(defaults(), &L, &t);
  EXPECT_EQ(count_obstacles(L), 0);
  for (float s : t.sobel) EXPECT_EQ(s, 0.0f);
}

TEST(ObstacleLayer, SobelGivesTheSlopeInMetresPerMetreAtAnyResolution) {
  for (double res : {0.05, 0.1, 0.2}) {
    auto L = terrain(30, 30, res, [](double x, double y) { return 0.3 * x + 0.4 * y; });  // slope 0.5
    ObstacleTerms t;
    compute_obstacle_layer(defaults(), &L, &t);
    EXPECT_NEAR(t.sobel[L.index(15, 15)], 0.5, 1e-4) << res;
    EXPECT_NEAR(t.laplace[L.index(15, 15)], 0.0, 1e-2) << res;
  }
}

TEST(ObstacleLayer, RampBelowTheLimitIsFreeAboveItIsObstacle) {
  auto gentle = terrain(40, 40, 0.1, [](double x, double) { return 0.4 * x; });
  compute_obstacle_layer(defaults(), &gentle);
  EXPECT_EQ(count_obstacles(gentle), 0);
  auto steep = terrain(40, 40, 0.1, [](double x, double) { return 0.8 * x; });
  compute_obstacle_layer(defaults(), &steep);
  // every cell with a full window sees the 0.8 slope (> S_max = 0.6)
  for (int r = 1; r < 39; ++r)
    for (int c = 1; c < 39; ++c) EXPECT_EQ(steep.obstacle[steep.index(r, c)], 1);
}

TEST(ObstacleLayer, StepAboveHmaxMarksBothSidesOfTheEdgeOnly) {
  auto L = terrain(40, 20, 0.1, [](double x, double) { return x > 2.0 ? 0.2 : 0.0; });  // edge between cols 19 and 20
  ObstacleTerms t;
  compute_obstacle_layer(defaults(), &L, &t);
  for (int r = 0; r < 20; ++r)
    for (int c = 0; c < 40; ++c) {
      const bool edge = c == 19 || c == 20;
      EXPECT_EQ(L.obstacle[L.index(r, c)], edge ? 1 : 0) << r << "," << c;
    }
  EXPECT_NEAR(t.step[L.index(5, 19)], 0.2, 1e-6);
}

TEST(ObstacleLayer, StepBelowHmaxIsFree) {
  // 0.05 m: step 0.05 < 0.15, Sobel 4 * 0.05 / 0.8 = 0.25 < 0.6, Laplace 0.05 / 0.01 = 5 < 15
  auto L = terrain(40, 20, 0.1, [](double x, double) { return x > 2.0 ? 0.05 : 0.0; });
  compute_obstacle_layer(defaults(), &L);
  EXPECT_EQ(count_obstacles(L), 0);
}

TEST(ObstacleLayer, EachCriterionAloneTriggers) {
  // a thin ridge of 0.12 m: step 0.12 < h_max, Sobel 0.12*... below, Laplace 2*0.12/0.01 = 24 > L_max
  auto ridge = terrain(20, 20, 0.1, [](double x, double) { return (x > 1.0 && x < 1.1) ? 0.12 : 0.0; });
  ObstacleTerms t;
  auto p = defaults();
  p.sobel_max = 100;
  p.step_max_m = 100;
  compute_obstacle_layer(p, &ridge, &t);
  EXPECT_NEAR(t.laplace[ridge.index(10, 10)], 24.0, 1e-3);
  EXPECT_EQ(ridge.obstacle[ridge.index(10, 10)], 1);
  p = defaults();
  p.laplace_max_per_m = 1000;
  p.step_max_m = 100;
  auto steep = terrain(20, 20, 0.1, [](double x, double) { return 0.7 * x; });
  compute_obstacle_layer(p, &steep);
  EXPECT_EQ(steep.obstacle[steep.index(10, 10)], 1);
}

TEST(ObstacleLayer, EdgesOfTheDataAreNotObstacles) {
  // a raised plateau and a tilted patch, both surrounded by cells without data
  auto L = terrain(60, 60, 0.1, [](double x, double y) {
    if (x > 1 && x < 2 && y > 1 && y < 2) return 0.8;
    if (x > 3 && x < 5 && y > 3 && y < 5) return 1.0 + 0.4 * (x - 3);
    return double(kNaN);
  });
  compute_obstacle_layer(defaults(), &L);
  EXPECT_EQ(count_obstacles(L), 0);
}

TEST(ObstacleLayer, CellsWithoutDataAreNeverObstacles) {
  // a 0.5 m step between columns 9 and 10; column 12 and row 5 have no data
  auto L = terrain(20, 20, 0.1, [](double x, double) { return x > 1.0 ? 0.5 : 0.0; });
  for (int r = 0; r < 20; ++r) L.z_max[L.index(r, 12)] = L.z_min[L.index(r, 12)] = kNaN;
  for (int c = 0; c < 20; ++c) L.z_max[L.index(5, c)] = L.z_min[L.index(5, c)] = kNaN;
  compute_obstacle_layer(defaults(), &L);
  for (int r = 0; r < 20; ++r) EXPECT_EQ(L.obstacle[L.index(r, 12)], 0);
  for (int c = 0; c < 20; ++c) EXPECT_EQ(L.obstacle[L.index(5, c)], 0);
  EXPECT_EQ(L.obstacle[L.index(4, 9)], 1);  // the step still shows where both sides have data
  EXPECT_EQ(L.obstacle[L.index(4, 10)], 1);
  EXPECT_EQ(L.obstacle[L.index(4, 11)], 0);
}

TEST(ObstacleLayer, VerticalSurfaceInsideOneCellCountsOnlyWithCellExtent) {
  ElevationLayers L;
  L.reset(0, 0, 0.1, 5, 5);
  L.z_max[L.index(2, 2)] = 1.2f;  // a pole's returns from 0.1 to 1.2 m in one cell, nothing around
  L.z_min[L.index(2, 2)] = 0.1f;
  auto p = defaults();
  p.step_includes_cell_extent = false;  // the paper's adjacent-cell step only
  compute_obstacle_layer(p, &L);
  EXPECT_EQ(L.obstacle[L.index(2, 2)], 0);
  p.step_includes_cell_extent = true;
  compute_obstacle_layer(p, &L);
  EXPECT_EQ(L.obstacle[L.index(2, 2)], 1);
}

TEST(HoleFilling, ClosesSingleCellsNotGaps) {
  auto L = terrain(20, 20, 0.1, [](double x, double) { return 0.1 * x; });
  L.z_max[L.index(5, 5)] = L.z_min[L.index(5, 5)] = kNaN;  // a single hole
  for (int r = 0; r < 20; ++r)
    for (int c = 12; c < 15; ++c) L.z_max[L.index(r, c)] = L.z_min[L.index(r, c)] = kNaN;  // a 3-wide gap
  L.z_max[L.index(15, 5)] = L.z_min[L.index(15, 5)] = kNaN;  // a hole next to a 0.5 m pole: an edge
  L.z_max[L.index(15, 6)] = L.z_min[L.index(15, 6)] = 0.5f;
  const int64_t filled = fill_holes(&L, 5, 0.15);
  EXPECT_EQ(filled, 1);
  EXPECT_NEAR(L.z_max[L.index(5, 5)], 0.1 * 0.55, 1e-6);  // mean of a plane's neighbours = its centre
  EXPECT_TRUE(L.filled[L.index(5, 5)]);
  EXPECT_TRUE(std::isnan(L.z_max[L.index(7, 13)]));
  EXPECT_TRUE(std::isnan(L.z_max[L.index(15, 5)]));
}

// ---------------------------------------------------------- whole clouds
struct Built {
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  bool ok;
};

Built build_scan(const SynthWorld& world, const SynthScanOptions& opt, bool motion = true,
                 const ElevationMapParams& params = defaults()) {
  const SynthCloud cloud = synth_vlp16(world, opt);
  PoseBuffer poses(2'000'000);
  const int64_t t0 = 10'000'000;
  for (int64_t t = t0 - 200'000; t <= t0 + 300'000; t += 20'000) {
    const Pose2 p = integrate_unicycle(opt.robot_start, opt.v, opt.omega, (t - t0) * 1e-6);
    poses.add(odo(t, p.x, p.y, p.yaw, opt.v, opt.omega));
  }
  CloudView v = view_of(cloud, t0, opt.mount_height_m);
  if (!motion) v.time_offset = nullptr;
  Built b;
  ElevationMapBuilder builder(params);
  b.ok = builder.build(v, poses, &b.L, &b.robot, &b.st);
  return b;
}

TEST(Builder, FlatGroundFromAVlp16RevolutionIsFree) {
  SynthScanOptions opt;
  opt.robot_start = {3.0, -2.0, 0.7};
  opt.range_noise_std_m = 0.01;
  const Built b = build_scan(SynthWorld{}, opt);
  ASSERT_TRUE(b.ok);
  EXPECT_EQ(b.st.points_in, 14400);  // the 8 upward rings see no ground
  EXPECT_GT(b.st.points_binned, 9000);
  EXPECT_EQ(count_obstacles(b.L), 0);
  int known = 0;
  for (float z : b.L.z_max)
    if (!std::isnan(z)) {
      ++known;
      EXPECT_NEAR(z, 0.0, 0.02);
    }
  EXPECT_GT(known, 500);
  // robot-centred: the robot's cell is the middle one
  EXPECT_EQ(int(std::floor((3.0 - b.L.origin_x) / 0.1)), 50);
  EXPECT_EQ(int(std::floor((-2.0 - b.L.origin_y) / 0.1)), 50);
}

// A 0.5 m tall bin 0.3 m beside the robot: the LiDAR (0.5 m up, lowest beam
// -15 deg) sees no ground within 1.87 m, only the bin's own face. Against
// empty neighbours taking the centre's value that face is flat; against
// the ground plane the robot stands on it is a step. Without it the bin
// vanished from the map, the tracker and the planner while the robot stood
// beside it. A gentle ramp starting inside the blind zone stays free (a steep
// one: Builder.RampBelowTheLimitIsFree).
TEST(Builder, AnObjectBesideTheRobotWhereNoGroundIsSeenIsAnObstacle) {
  SynthWorld world;
  world.cylinders.push_back({0.0, 0.55, 0.25, 0.5});  // x, y, radius, height
  SynthScanOptions opt;
  opt.range_noise_std_m = 0.01;
  ElevationMapParams on = defaults(), off = defaults();
  on.blind_ground_radius_m = opt.mount_height_m / std::tan(15.0 * M_PI / 180.0);  // 1.87 m
  off.blind_ground_radius_m = 0.0;
  const Built with = build_scan(world, opt, true, on);
  const Built without = build_scan(world, opt, true, off);
  ASSERT_TRUE(with.ok && without.ok);
  auto near_bin = [](const Built& b) {
    int n = 0;
    for (int r = 0; r < b.L.height; ++r)
      for (int c = 0; c < b.L.width; ++c) {
        const double x = b.L.origin_x + (c + 0.5) * b.L.resolution, y = b.L.origin_y + (r + 0.5) * b.L.resolution;
        if (b.L.obstacle[b.L.index(r, c)] && std::hypot(x - 0.0, y - 0.55) < 0.45) ++n;
      }
    return n;
  };
  std::printf("[figures] bin 0.3 m beside the robot: obstacle cells %d with the ground plane, %d without\n",
              near_bin(with), near_bin(without));
  EXPECT_GE(near_bin(with), 3);                        // a cluster for the tracker (dbscan_min_points)
  EXPECT_GT(near_bin(with), near_bin(without));        // at step_max_m 0.15: 6 against 0
  EXPECT_EQ(count_obstacles(with.L), near_bin(with));  // nothing else
  SynthWorld ramp;
  ramp.ground_slope_x = 0.05;
  ramp.ramp_start_x = 1.0;
  const Built r = build_scan(ramp, opt, true, on);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(count_obstacles(r.L), 0);
}

// A football (0.22 m tall, 0.11 m radius) rolling towards the path: seen
// from 0.5 m up, beyond about 3 m only one or two rings hit it, at 0.05 to
// 0.2 m above the ground, so h_max decides how far away it is an obstacle.
// With 0.15 m a ball in the ball_crossing scenario was found in 24 of 43
// maps 3-4 m away (18 of 41 at 4-5 m); at 3 m/s that is a second of
// warning. With 0.10 m: 43 of 43 and 22 of 41.
TEST(Builder, AFootballAheadIsAnObstacleOutToFourMetres) {
  const ElevationMapParams p = defaults();
  ElevationMapParams high = p;
  high.step_max_m = 0.15;
  int missed_high = 0;
  for (double d = 1.5; d <= 4.0 + 1e-9; d += 0.25) {
    SynthWorld world;
    world.cylinders.push_back({d, 0.3, 0.11, 0.22});  // x, y, radius, height
    SynthScanOptions opt;
    opt.range_noise_std_m = 0.01;
    const Built b = build_scan(world, opt, true, p);
    const Built h = build_scan(world, opt, true, high);
    ASSERT_TRUE(b.ok && h.ok);
    auto near_ball = [&](const Built& m) {
      int n = 0;
      for (int r = 0; r < m.L.height; ++r)
        for (int c = 0; c < m.L.width; ++c) {
          const double x = m.L.origin_x + (c + 0.5) * m.L.resolution, y = m.L.origin_y + (r + 0.5) * m.L.resolution;
          if (m.L.obstacle[m.L.index(r, c)] && std::hypot(x - d, y - 0.3) < 0.3) ++n;
        }
      return n;
    };
    std::printf("[figures] ball %.2f m ahead: %d obstacle cells at h_max %.2f, %d at 0.15\n", d, near_ball(b),
                p.step_max_m, near_ball(h));
    EXPECT_GE(near_ball(b), 3) << d << " m";                     // a cluster for the tracker (dbscan_min_points)
    EXPECT_EQ(count_obstacles(b.L), near_ball(b)) << d << " m";  // nothing else
    missed_high += near_ball(h) < 3;
  }
  EXPECT_GT(missed_high, 0);  // premise: with 0.15 m some of these are missed
}

// One builder and one pose buffer over 600 revolutions of a robot driving
// a circle: the heap the allocator has handed out (mallinfo2) stays flat.
TEST(Builder, LongRunKeepsMemoryFlat) {
  SynthWorld world;
  world.cylinders.push_back({2.0, 1.0, 0.3, 1.0});
  SynthScanOptions opt;
  opt.v = 0.8;
  opt.omega = 0.2;
  const SynthCloud cloud = synth_vlp16(world, opt);  // the same sweep every time: the poses move
  ElevationMapBuilder builder(defaults());
  PoseBuffer poses(2'000'000);
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  CloudView v = view_of(cloud, 0, opt.mount_height_m);
  size_t heap_at_100 = 0;
  int64_t t = 0;
  for (int rev = 0; rev < 600; ++rev) {
    if (rev == 100) heap_at_100 = mallinfo2().uordblks;
    for (int i = 0; i < 5; ++i, t += 20'000) {
      const Pose2 p = integrate_unicycle(Pose2{0, 0, 0}, opt.v, opt.omega, t * 1e-6);
      poses.add(odo(t, p.x, p.y, p.yaw, opt.v, opt.omega));
    }
    v.utime = t - 150'000;
    ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st)) << rev;
  }
  const long long growth = static_cast<long long>(mallinfo2().uordblks) - static_cast<long long>(heap_at_100);
  std::printf("[figures] elevation map heap, revolution 100 -> 600: %+lld bytes\n", growth);
  EXPECT_LT(growth, 64 * 1024);
}

TEST(Builder, RampBelowTheLimitIsFree) {
  SynthWorld w;
  w.ground_slope_x = 0.25;
  w.ramp_start_x = 1.0;
  SynthScanOptions opt;
  const Built b = build_scan(w, opt);
  ASSERT_TRUE(b.ok);
  EXPECT_EQ(count_obstacles(b.L), 0);
}

TEST(Builder, StepAboveHmaxIsObstacleAlongItsEdge) {
  SynthWorld w;
  w.boxes.push_back({4.0, 0.0, 0.0, 3.0, 6.0, 0.3});  // a 0.3 m platform from x = 2.5
  SynthScanOptions opt;
  const Built b = build_scan(w, opt);
  ASSERT_TRUE(b.ok);
  int edge = 0, elsewhere = 0;
  for (int r = 0; r < b.L.height; ++r)
    for (int c = 0; c < b.L.width; ++c) {
      if (!b.L.obstacle[b.L.index(r, c)]) continue;
      const double x = b.L.origin_x + (c + 0.5) * 0.1, y = b.L.origin_y + (r + 0.5) * 0.1;
      const bool near_edge =
          (std::abs(x - 2.5) < 0.25 && std::abs(y) < 3.05) || (x > 2.3 && std::abs(std::abs(y) - 3.0) < 0.25);
      (near_edge ? edge : elsewhere) += 1;
    }
  EXPECT_GT(edge, 40);  // most of the 6 m front edge
  EXPECT_EQ(elsewhere, 0);
}

// Obstacle cells of a cylinder: cells holding its surface (centre within
// r + res/sqrt(2)) and their 8-neighbours on the ground side (one diagonal,
// res*sqrt(2), farther), plus noise: all within r + 0.25 m of the axis.
void expect_cylinder_obstacle(const Built& b, double cx, double cy, double r) {
  int near = 0, far = 0;
  for (int row = 0; row < b.L.height; ++row)
    for (int c = 0; c < b.L.width; ++c) {
      if (!b.L.obstacle[b.L.index(row, c)]) continue;
      const double x = b.L.origin_x + (c + 0.5) * 0.1, y = b.L.origin_y + (row + 0.5) * 0.1;
      (std::hypot(x - cx, y - cy) < r + 0.25 ? near : far) += 1;
    }
  EXPECT_GE(near, 4);
  EXPECT_EQ(far, 0);
}

TEST(Builder, CylinderIsObstacleAndNothingElseIs) {
  SynthWorld w;
  w.cylinders.push_back({3.5, 1.0, 0.25, 1.0});
  w.cylinders.push_back({-2.0, -3.0, 0.3, 0.5});
  SynthScanOptions opt;
  opt.range_noise_std_m = 0.01;
  const Built b = build_scan(w, opt);
  ASSERT_TRUE(b.ok);
  int near1 = 0, near2 = 0, far = 0;
  for (int row = 0; row < b.L.height; ++row)
    for (int c = 0; c < b.L.width; ++c) {
      if (!b.L.obstacle[b.L.index(row, c)]) continue;
      const double x = b.L.origin_x + (c + 0.5) * 0.1, y = b.L.origin_y + (row + 0.5) * 0.1;
      if (std::hypot(x - 3.5, y - 1.0) < 0.25 + 0.25)
        ++near1;
      else if (std::hypot(x + 2.0, y + 3.0) < 0.3 + 0.25)
        ++near2;
      else {
        ++far;
        ADD_FAILURE() << "obstacle at " << x << "," << y << " z " << b.L.z_max[b.L.index(row, c)] << " min "
                      << b.L.z_min[b.L.index(row, c)];
      }
    }
  EXPECT_GE(near1, 4);
  EXPECT_GE(near2, 4);
  EXPECT_EQ(far, 0);
}

TEST(Builder, MotionCompensationKeepsAStaticCylinderSharpAtSpeed) {
  SynthWorld w;
  w.cylinders.push_back({3.0, 0.0, 0.25, 1.0});
  SynthScanOptions opt;
  opt.v = 2.0;  // 0.2 m during the sweep
  opt.omega = 0.5;
  expect_cylinder_obstacle(build_scan(w, opt, true), 3.0, 0.0, 0.25);
  // the same sweep with every point at the cloud's time smears it (the check above can fail)
  const Built smeared = build_scan(w, opt, false);
  int far = 0;
  for (int row = 0; row < smeared.L.height; ++row)
    for (int c = 0; c < smeared.L.width; ++c) {
      const double x = smeared.L.origin_x + (c + 0.5) * 0.1, y = smeared.L.origin_y + (row + 0.5) * 0.1;
      far += smeared.L.obstacle[smeared.L.index(row, c)] && std::hypot(x - 3.0, y) >= 0.5;
    }
  EXPECT_GT(far, 0);
}

TEST(Builder, EachPointUsesThePoseAtItsFiringTime) {
  // one point 2.04 m ahead, fired 150 ms into the sweep of a robot driving +x at 1 m/s
  PoseBuffer poses(2'000'000);
  for (int64_t t = 0; t <= 400'000; t += 20'000) poses.add(odo(t, t * 1e-6, 0, 0, 1.0, 0));
  const float x[1] = {2.04f}, y[1] = {0.0f}, z[1] = {-0.2f};
  const int32_t off[1] = {150'000};
  CloudView v;
  v.utime = 120'000;
  v.n = 1;
  v.x = x;
  v.y = y;
  v.z = z;
  v.time_offset = off;
  v.mount_z = 0.5;
  ElevationMapBuilder builder(defaults());
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st));
  EXPECT_NEAR(robot.x, 0.12, 1e-12);
  // the robot is at x = 0.2705 mid-slice at 270 ms: the point lies at 2.3105 (cell 72 of a grid from -4.9)
  EXPECT_NEAR(L.origin_x, -4.9, 1e-9);
  EXPECT_NEAR(L.z_max[L.index(50, 72)], 0.3f, 1e-6);
  v.time_offset = nullptr;  // all at utime: 0.12 + 2.04 = 2.16 -> cell 70
  ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st));
  EXPECT_NEAR(L.z_max[L.index(50, 70)], 0.3f, 1e-6);
}

TEST(Builder, TransformsWithMountAndRobotPose) {
  PoseBuffer poses(2'000'000);
  poses.add(odo(0, 10.0, 5.0, M_PI / 2));
  const float x[1] = {2.0f}, y[1] = {0.0f}, z[1] = {0.1f};
  CloudView v;
  v.utime = 0;
  v.n = 1;
  v.x = x;
  v.y = y;
  v.z = z;
  v.mount_x = 0.2;  // sensor 0.2 m ahead of the base, 0.5 m up
  v.mount_z = 0.5;
  ElevationMapBuilder builder(defaults());
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st));
  // facing +y: the point is at (10, 7.2), 0.6 m above the ground
  const int c = int(std::floor((10.0 + 0.05 - L.origin_x) / 0.1)), r = int(std::floor((7.2 + 0.05 - L.origin_y) / 0.1));
  EXPECT_NEAR(L.z_max[L.index(r, c)], 0.6f, 1e-6);
  EXPECT_EQ(st.points_binned, 1);
}

TEST(Builder, MountPitchAndRollRotateThePoint) {
  PoseBuffer poses(2'000'000);
  poses.add(odo(0, 0, 0, 0));
  // pitched 0.2 rad nose-down (positive pitch about y tilts x towards -z):
  // a return 3 m along the sensor's x lies 3 cos 0.2 ahead, 3 sin 0.2 lower
  const float x[1] = {3.0f}, y[1] = {0.0f}, z[1] = {0.0f};
  CloudView v;
  v.n = 1;
  v.x = x;
  v.y = y;
  v.z = z;
  v.mount_z = 0.8;
  v.mount_pitch = 0.2;
  ElevationMapBuilder builder(defaults());
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st));
  const double px = 3.0 * std::cos(0.2), pz = 0.8 - 3.0 * std::sin(0.2);
  EXPECT_NEAR(L.z_max[L.index(50, int(std::floor((px - L.origin_x) / 0.1)))], pz, 1e-6);
  // rolled +90 deg about x (right-hand rule): the sensor's y axis points up
  const float x2[1] = {0.0f}, y2[1] = {0.6f}, z2[1] = {0.0f};
  v.x = x2;
  v.y = y2;
  v.z = z2;
  v.mount_pitch = 0.0;
  v.mount_roll = M_PI / 2;
  ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st));
  EXPECT_NEAR(L.z_max[L.index(50, 50)], 1.4f, 1e-6);
}

TEST(Builder, CropsSelfReturnsHeightBandAndInvalidPoints) {
  PoseBuffer poses(2'000'000);
  poses.add(odo(0, 0, 0, 0));
  const float nan = kNaN;
  const float x[5] = {0.1f, 3.0f, 3.0f, nan, 30.0f};
  const float y[5] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
  const float z[5] = {0.0f, 3.0f, -0.5f, 0.0f, -0.5f};
  const int32_t off[5] = {0, 0, -5, 0, 0};
  CloudView v;
  v.n = 5;
  v.x = x;
  v.y = y;
  v.z = z;
  v.time_offset = off;
  v.mount_z = 0.5;
  ElevationMapBuilder builder(defaults());
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  ASSERT_TRUE(builder.build(v, poses, &L, &robot, &st));
  EXPECT_EQ(st.points_binned, 0);
  EXPECT_EQ(st.points_cropped, 3);  // self, too high, outside the grid
  EXPECT_EQ(st.points_invalid, 2);  // NaN, negative time offset
}

TEST(Builder, NoOdometryMeansNoMap) {
  PoseBuffer poses(2'000'000);
  CloudView v;
  ElevationMapBuilder builder(defaults());
  ElevationLayers L;
  Pose2 robot;
  CloudStats st;
  EXPECT_FALSE(builder.build(v, poses, &L, &robot, &st));
  poses.add(odo(1'000'000, 0, 0, 0));
  v.utime = 1'500'000;  // 0.5 s past the newest odometry
  EXPECT_FALSE(builder.build(v, poses, &L, &robot, &st));
}

// ---------------------------------------------------------- the process core
evade::pointcloud_t cloud_msg(int64_t utime, const SynthCloud& c) {
  evade::pointcloud_t m;
  m.utime = utime;
  m.sensor_model = "vlp16";
  m.mount = {};
  m.mount.z = 0.5;
  m.packets = 0;
  m.n = int32_t(c.x.size());
  m.x = c.x;
  m.y = c.y;
  m.z = c.z;
  m.intensity.assign(c.x.size(), 0.0f);
  m.ring.assign(c.x.size(), 0);
  m.time_offset = c.time_offset;
  return m;
}

TEST(Core, PublishesTheMapStampedWithTheCloudTime) {
  bus::MemoryBus bus;
  ElevationMapCore core(defaults());
  bus.add(core);
  SynthWorld w;
  w.cylinders.push_back({2.0, 2.0, 0.3, 1.0});
  SynthScanOptions opt;
  opt.robot_start = {1.0, 1.0, 0.0};
  const SynthCloud c = synth_vlp16(w, opt);
  // a cloud before any odometry is skipped and counted
  bus.inject("LIDAR_POINTS", cloud_msg(900'000, c), 900'000);
  EXPECT_EQ(core.counter("cloud_skipped_no_odometry"), 1);
  for (int64_t t = 1'000'000; t <= 1'300'000; t += 20'000) {
    evade::odometry_t o{};
    o.utime = t;
    o.x = 1.0;
    o.y = 1.0;
    bus.inject("ODOMETRY", o, t);
  }
  bus.inject("LIDAR_POINTS", cloud_msg(1'100'000, c), 1'300'000);
  const auto maps = bus.decoded<evade::grid_map_t>("ELEVATION_MAP");
  ASSERT_EQ(maps.size(), 1u);
  const auto& m = maps[0];
  EXPECT_EQ(m.utime, 1'100'000);
  const ElevationMapParams p = defaults();
  EXPECT_EQ(m.width, std::lround(p.size_x_m / 0.1));
  EXPECT_EQ(m.height, std::lround(p.size_y_m / 0.1));
  EXPECT_DOUBLE_EQ(m.resolution, 0.1);
  EXPECT_NEAR(m.robot_x, 1.0, 1e-12);
  EXPECT_NEAR(m.origin[0], 1.0 - 0.5 * p.size_x_m, 1e-9);  // robot-centred
  int obstacles = 0;
  for (const auto& row : m.obstacle)
    for (auto o : row) obstacles += o;
  EXPECT_GT(obstacles, 4);
  // malformed input is counted, not fatal
  auto bad = cloud_msg(1'200'000, c);
  bad.mount.z = std::numeric_limits<double>::quiet_NaN();
  bus.inject("LIDAR_POINTS", bad, 1'300'000);
  EXPECT_EQ(core.counter("cloud_invalid"), 1);
  const uint8_t junk[7] = {1, 2, 3, 4, 5, 6, 7};
  bus.inject("LIDAR_POINTS", junk, sizeof junk, 1'300'000);
  EXPECT_EQ(bus.decoded<evade::grid_map_t>("ELEVATION_MAP").size(), 1u);
}

// Issue 20: base_driver restarted (a new odometry epoch, its pose reset to
// the origin): a cloud is placed with the new frame's poses only.
TEST(Core, ANewOdometryEpochDropsThePosesOfTheOldFrame) {
  bus::MemoryBus bus;
  ElevationMapCore core(defaults());
  bus.add(core);
  SynthWorld w;
  w.cylinders.push_back({2.0, 2.0, 0.3, 1.0});
  SynthScanOptions opt;
  opt.robot_start = {1.0, 1.0, 0.0};
  const SynthCloud c = synth_vlp16(w, opt);
  auto odometry = [&](int64_t t, double x, int64_t epoch) {
    evade::odometry_t o{};
    o.utime = t;
    o.x = x;
    o.y = 1.0;
    o.epoch = epoch;
    bus.inject("ODOMETRY", o, t);
  };
  for (int64_t t = 1'000'000; t <= 1'300'000; t += 20'000) odometry(t, 5.0, 1);
  // restarted at 1.32 s: the robot is at x = 1 in the new frame
  for (int64_t t = 1'320'000; t <= 1'500'000; t += 20'000) odometry(t, 1.0, 2);
  EXPECT_EQ(core.counter("odometry_epoch_changed"), 1);
  // a cloud from before the restart has no pose in the new frame
  bus.inject("LIDAR_POINTS", cloud_msg(1'100'000, c), 1'500'000);
  EXPECT_TRUE(bus.decoded<evade::grid_map_t>("ELEVATION_MAP").empty());
  bus.inject("LIDAR_POINTS", cloud_msg(1'400'000, c), 1'500'000);
  const auto maps = bus.decoded<evade::grid_map_t>("ELEVATION_MAP");
  ASSERT_EQ(maps.size(), 1u);
  EXPECT_NEAR(maps[0].robot_x, 1.0, 1e-9);
}

TEST(Core, HostileInputNeitherCrashesNorPoisonsLaterMaps) {
  bus::MemoryBus bus;
  ElevationMapCore core(defaults());
  bus.add(core);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> wild(-1e6f, 1e6f);
  const float specials[] = {std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(),
                            3.4e38f,
                            -3.4e38f,
                            0.0f};
  for (int k = 0; k < 200; ++k) {
    evade::odometry_t o{};
    o.utime = 1'000'000 + k * 20'000 - (k % 7 == 0 ? 5'000'000 : 0);  // some go back in time
    o.x = (k % 11 == 0) ? std::numeric_limits<double>::quiet_NaN() : wild(rng) * 1e-3;
    o.y = wild(rng) * 1e-3;
    o.yaw = wild(rng);
    o.v = wild(rng) * 1e-6;
    bus.inject("ODOMETRY", o, o.utime);
    evade::pointcloud_t m;
    m.utime = 1'000'000 + k * 20'000;
    m.sensor_model = "?";
    m.mount = {};
    m.mount.z = 0.5;
    m.mount.yaw = wild(rng);
    m.packets = 0;
    m.n = 64;
    for (int i = 0; i < m.n; ++i) {
      m.x.push_back(i % 3 ? wild(rng) * 1e-5f : specials[rng() % 6]);
      m.y.push_back(wild(rng) * 1e-5f);
      m.z.push_back(i % 5 ? wild(rng) * 1e-6f : specials[rng() % 6]);
      m.intensity.push_back(0);
      m.ring.push_back(0);
      m.time_offset.push_back(int32_t(rng()));
    }
    bus.inject("LIDAR_POINTS", m, m.utime);
  }
  EXPECT_GT(core.counter("odometry_invalid"), 0);
  EXPECT_GT(core.counter("points_invalid"), 0);
  // a clean world afterwards still maps correctly
  bus.clear();
  for (int64_t t = 20'000'000; t <= 20'300'000; t += 20'000) {
    evade::odometry_t o{};
    o.utime = t;
    bus.inject("ODOMETRY", o, t);
  }
  SynthWorld w;
  w.cylinders.push_back({2.0, 0.0, 0.3, 1.0});
  bus.inject("LIDAR_POINTS", cloud_msg(20'100'000, synth_vlp16(w, SynthScanOptions{})), 20'300'000);
  const auto maps = bus.decoded<evade::grid_map_t>("ELEVATION_MAP");
  ASSERT_EQ(maps.size(), 1u);
  int obstacles = 0;
  for (const auto& row : maps[0].obstacle)
    for (auto o : row) obstacles += o;
  EXPECT_GT(obstacles, 4);
  EXPECT_NEAR(maps[0].robot_x, 0.0, 1e-12);
}

}  // namespace
}  // namespace evade::mapping
