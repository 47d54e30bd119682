// evade-viz without a window: which primitives for which message, layer
// switches, keys, and the log timeline's seek.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>

#include "bus/core.h"
#include "bus/log.h"
#include "config/config.h"
#include "mapping/synthetic_scan.h"
#include "moments.h"
#include "playback.h"
#include "scene.h"

namespace {

using namespace evade::viz;

evade::config::Node robot_config() {
  return evade::config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
}

std::unique_ptr<WorldState> make_state() {
  const auto root = robot_config();
  return std::make_unique<WorldState>(evade::sensing::LidarDriverParams::from_config(root),
                                      evade::mapping::ElevationMapParams::from_config(root.section("elevation_map")));
}

VizParams params() { return VizParams::from_config(robot_config()); }

template <class Msg>
void feed(WorldState& w, const std::string& ch, const Msg& m, int64_t t) {
  const auto bytes = evade::bus::encode(m);
  ASSERT_TRUE(w.apply(ch, bytes.data(), bytes.size(), t)) << ch;
}

const LinesPrim* find_lines(const Scene& s, const std::string& id) {
  for (const auto& l : s.lines)
    if (l.id == id) return &l;
  return nullptr;
}
const PointsPrim* find_points(const Scene& s, const std::string& id) {
  for (const auto& p : s.points)
    if (p.id == id) return &p;
  return nullptr;
}

WorldPoint centre(const std::vector<WorldPoint>& strip) {
  // closed strip: the last point repeats the first
  double x = 0, y = 0;
  for (size_t i = 0; i + 1 < strip.size(); ++i) {
    x += strip[i].x;
    y += strip[i].y;
  }
  return {float(x / (strip.size() - 1)), float(y / (strip.size() - 1)), 0};
}

constexpr int64_t kT = 1'000'000'000;

// The robot at (1, 2) facing +y, a route and a plan that fell back.
void feed_robot_route_plan(WorldState& w) {
  evade::odometry_t o{};
  for (int k = 0; k <= 20; ++k) {
    o.utime = kT + k * 10'000;
    o.x = 1.0;
    o.y = 2.0;
    o.yaw = M_PI / 2;
    feed(w, "ODOMETRY", o, o.utime);
  }
  evade::path_t route{};
  route.x = {-10, 9};
  route.y = {0, 0};
  route.n = 2;
  feed(w, "ROUTE", route, kT);
  evade::plan_t plan{};
  plan.mode = "dcbf";
  plan.status = evade::plan_t::STATUS_FALLBACK;
  plan.horizon = 2;
  plan.num_states = 3;
  plan.x = {1, 1, 1};
  plan.y = {2, 2.1, 2.2};
  plan.yaw = {0, 0, 0};
  plan.v = {0.1, 0.1};
  plan.omega = {0, 0};
  plan.min_barrier = 0.42;
  feed(w, "PLAN", plan, kT);
}

// Track 7 at (3, 1) going +x at 1 m/s with 5 predicted steps.
void feed_track_and_prediction(WorldState& w) {
  evade::obstacle_list_t obs{};
  evade::obstacle_t t{};
  t.id = 7;
  t.x = 3;
  t.y = 1;
  t.a = 0.4;
  t.b = 0.2;
  obs.obstacles = {t};
  obs.num_obstacles = 1;
  feed(w, "OBSTACLES", obs, kT);
  evade::prediction_list_t pl{};
  pl.horizon = 5;
  pl.dt = 0.1;
  evade::track_prediction_t tp{};
  tp.id = 7;
  tp.vx = 1.0;
  tp.horizon = 5;
  for (int k = 0; k < 5; ++k) {
    tp.x.push_back(3 + 0.1 * k);
    tp.y.push_back(1);
    tp.a.push_back(0.4 + 0.05 * k);
    tp.b.push_back(0.2 + 0.05 * k);
    tp.theta.push_back(0);
    tp.sigma.push_back(0.05 * k);
  }
  pl.tracks = {tp};
  pl.num_tracks = 1;
  feed(w, "OBSTACLE_PREDICTIONS", pl, kT);
}

// Two obstacle cells and one true cylinder.
void feed_map_and_truth(WorldState& w) {
  evade::grid_map_t m{};
  m.origin[0] = 0;
  m.origin[1] = 0;
  m.resolution = 0.5;
  m.width = 3;
  m.height = 2;
  m.elevation.assign(2, std::vector<float>(3, 0.0f));
  m.obstacle.assign(2, std::vector<int8_t>(3, 0));
  m.obstacle[0][1] = 1;
  m.obstacle[1][2] = 1;
  m.elevation[1][2] = 0.3f;
  feed(w, "ELEVATION_MAP", m, kT);
  evade::sim_truth_t truth{};
  truth.x = 1;
  truth.y = 2;
  truth.footprint_length = 0.42;
  truth.footprint_width = 0.31;
  evade::sim_obstacle_t so{};
  so.shape = "cylinder";
  so.x = 3.1;
  so.y = 1.0;
  so.radius = 0.25;
  so.height = 0.5;
  truth.obstacles = {so};
  truth.num_obstacles = 1;
  truth.lidar_returns = {40};
  feed(w, "SIM_TRUTH", truth, kT);
}

// A ray-cast revolution of the true cylinder from the robot's pose.
void feed_cloud(WorldState& w) {
  evade::mapping::SynthWorld world;
  world.cylinders.push_back({3.1, 1.0, 0.25, 0.5});
  evade::mapping::SynthScanOptions opt;
  opt.robot_start = {1.0, 2.0, M_PI / 2};
  opt.azimuth_steps = 360;
  const auto sc = evade::mapping::synth_vlp16(world, opt);
  evade::pointcloud_t c{};
  c.utime = kT + 10'000;
  c.sensor_model = "vlp16";
  c.mount.z = 0.5;
  c.x = sc.x;
  c.y = sc.y;
  c.z = sc.z;
  c.n = int32_t(sc.x.size());
  c.intensity.assign(c.n, 1.0f);
  c.ring.assign(c.n, 0);
  c.time_offset = sc.time_offset;
  feed(w, "LIDAR_POINTS", c, kT + 120'000);
}

// A small world: the robot at (1, 2) facing +y, a route, a plan that fell
// back, track 7 at (3, 1) going +x at 1 m/s with 5 predicted steps, two
// obstacle cells, one true cylinder and a ray-cast revolution.
void populate(WorldState& w) {
  feed_robot_route_plan(w);
  feed_track_and_prediction(w);
  feed_map_and_truth(w);
  feed_cloud(w);
}

// The cloud in the world frame: the ground at z 0, the cylinder up to 0.5,
// coloured by height.
void expect_cloud(const Scene& s, const VizParams& p) {
  const PointsPrim* cloud = find_points(s, "cloud");
  ASSERT_NE(cloud, nullptr);
  EXPECT_GT(cloud->xyz.size(), 1000u);
  ASSERT_EQ(cloud->rgb.size(), cloud->xyz.size());
  int on_cylinder = 0;
  for (size_t i = 0; i < cloud->xyz.size(); ++i) {
    const auto& q = cloud->xyz[i];
    const Rgb want = height_colour(q.z, p.cloud_min_z_m, p.cloud_max_z_m);
    ASSERT_EQ(cloud->rgb[i].r, want.r);
    ASSERT_EQ(cloud->rgb[i].b, want.b);
    ASSERT_GT(q.z, -0.05);
    ASSERT_LT(q.z, 0.55);
    if (q.z > 0.1) {
      EXPECT_NEAR(std::hypot(q.x - 3.1, q.y - 1.0), 0.25, 0.01);
      ++on_cylinder;
    }
  }
  EXPECT_GT(on_cylinder, 10);
}

// Map cells, route, the plan and its HUD line.
void expect_map_route_plan(const Scene& s) {
  const PointsPrim* cells = find_points(s, "map_obstacles");
  ASSERT_NE(cells, nullptr);
  ASSERT_EQ(cells->xyz.size(), 2u);
  EXPECT_FLOAT_EQ(cells->xyz[0].x, 0.75f);  // row 0, column 1
  EXPECT_FLOAT_EQ(cells->xyz[0].y, 0.25f);
  EXPECT_FLOAT_EQ(cells->xyz[1].x, 1.25f);  // row 1, column 2, at its elevation
  EXPECT_FLOAT_EQ(cells->xyz[1].z, 0.3f);

  const LinesPrim* route = find_lines(s, "route");
  ASSERT_NE(route, nullptr);
  ASSERT_EQ(route->strips.size(), 1u);
  EXPECT_EQ(route->strips[0].size(), 2u);
  EXPECT_FLOAT_EQ(route->strips[0][0].x, -10.0f);

  const LinesPrim* plan = find_lines(s, "plan");
  ASSERT_NE(plan, nullptr);
  EXPECT_EQ(plan->strips[0].size(), 3u);
  EXPECT_FLOAT_EQ(plan->rgb.r, plan_colour(evade::plan_t::STATUS_FALLBACK).r);
  EXPECT_NE(s.hud[0].find("fallback"), std::string::npos) << s.hud[0];
  EXPECT_NE(s.hud[0].find("0.42"), std::string::npos) << s.hud[0];
}

// The track, its label and velocity arrow, the fading predicted steps.
void expect_track_and_prediction(const Scene& s, const VizParams& p) {
  const LinesPrim* tracks = find_lines(s, "tracks");
  ASSERT_NE(tracks, nullptr);
  ASSERT_EQ(tracks->strips.size(), 1u);
  EXPECT_NEAR(centre(tracks->strips[0]).x, 3.0, 1e-5);
  EXPECT_NEAR(centre(tracks->strips[0]).y, 1.0, 1e-5);
  ASSERT_EQ(s.labels.size(), 1u);
  EXPECT_EQ(s.labels[0].text, "#7 1.0 m/s");
  const LinesPrim* arrows = find_lines(s, "track_velocity");
  ASSERT_NE(arrows, nullptr);
  ASSERT_EQ(arrows->strips.size(), 3u);  // shaft and two head strokes
  EXPECT_NEAR(arrows->strips[0][1].x, 3.0 + 1.0 * p.velocity_arrow_s, 1e-5);

  // predicted steps 1..4, fading from opaque to prediction_min_opacity
  std::vector<float> opacity;
  for (int k = 1; k < 5; ++k) {
    const LinesPrim* step = find_lines(s, "prediction_" + std::to_string(k));
    ASSERT_NE(step, nullptr) << k;
    EXPECT_NEAR(centre(step->strips[0]).x, 3.0 + 0.1 * k, 1e-5);
    opacity.push_back(step->opacity);
  }
  EXPECT_FLOAT_EQ(opacity.front(), 1.0f);
  EXPECT_FLOAT_EQ(opacity.back(), float(p.prediction_min_opacity));
  EXPECT_TRUE(std::is_sorted(opacity.rbegin(), opacity.rend()));
}

// The robot's footprint and the true obstacles.
void expect_robot_and_truth(const Scene& s, const VizParams& p) {
  const LinesPrim* robot = find_lines(s, "robot");
  ASSERT_NE(robot, nullptr);
  const auto& fp = robot->strips[0];  // facing +y: length along y
  EXPECT_NEAR(std::abs(fp[0].y - fp[2].y), p.footprint_length_m, 1e-5);
  EXPECT_NEAR(std::abs(fp[0].x - fp[2].x), p.footprint_width_m, 1e-5);
  EXPECT_TRUE(s.have_robot);
  EXPECT_NEAR(s.robot_yaw, M_PI / 2, 1e-9);

  const LinesPrim* truth = find_lines(s, "truth");
  ASSERT_NE(truth, nullptr);
  EXPECT_EQ(truth->strips.size(), 3u);  // the cylinder's base and top, the true footprint
  EXPECT_NEAR(centre(truth->strips[0]).x, 3.1, 1e-5);
}

TEST(VizScene, EachMessageBecomesItsPrimitives) {
  auto w = make_state();
  populate(*w);
  const VizParams p = params();
  const Scene s = build_scene(*w, all_layers_on(), p);
  expect_cloud(s, p);
  expect_map_route_plan(s);
  expect_track_and_prediction(s, p);
  expect_robot_and_truth(s, p);
}

TEST(VizScene, ALayerSwitchedOffIsNotDrawn) {
  auto w = make_state();
  populate(*w);
  const VizParams p = params();
  for (int l = 0; l < kNumLayers; ++l) {
    LayerSwitches on = all_layers_on();
    on[l] = false;
    const Scene s = build_scene(*w, on, p);
    for (const auto& q : s.points) EXPECT_NE(q.layer, l) << layer_name(Layer(l));
    for (const auto& q : s.lines) EXPECT_NE(q.layer, l) << layer_name(Layer(l));
    for (const auto& q : s.labels) EXPECT_NE(q.layer, l) << layer_name(Layer(l));
    EXPECT_NE(s.hud.back().find(std::string(layer_name(Layer(l))) + "(off)"), std::string::npos) << s.hud.back();
  }
  const Scene all = build_scene(*w, all_layers_on(), p);
  for (int l = 0; l < kNumLayers; ++l) {
    bool drawn = false;
    for (const auto& q : all.points) drawn |= q.layer == l;
    for (const auto& q : all.lines) drawn |= q.layer == l;
    EXPECT_TRUE(drawn) << layer_name(Layer(l));
  }
}

TEST(VizScene, HeightColourRunsBlueToRed) {
  const Rgb lo = height_colour(-5, 0, 1), hi = height_colour(5, 0, 1), mid = height_colour(0.5, 0, 1);
  EXPECT_EQ(lo.b, 1.0f);
  EXPECT_EQ(lo.r, 0.0f);
  EXPECT_EQ(hi.r, 1.0f);
  EXPECT_EQ(hi.b, 0.0f);
  EXPECT_EQ(mid.g, 1.0f);
  EXPECT_EQ(mid.r, 0.0f);
}

TEST(VizControls, KeysSwitchLayersCameraPauseStepSpeedAndSeek) {
  Controls c;
  EXPECT_TRUE(c.on_key("t", 5.0));
  EXPECT_FALSE(c.layers[kTracks]);
  EXPECT_TRUE(c.layers[kCloud]);
  EXPECT_TRUE(c.on_key("t", 5.0));
  EXPECT_TRUE(c.layers[kTracks]);
  EXPECT_TRUE(c.on_key("v", 5.0));
  EXPECT_FALSE(c.layers[kTruth]);
  EXPECT_TRUE(c.on_key("k", 5.0));
  EXPECT_FALSE(c.follow);
  EXPECT_TRUE(c.on_key("space", 5.0));
  EXPECT_TRUE(c.paused);
  EXPECT_TRUE(c.on_key("period", 5.0));
  EXPECT_EQ(c.steps, 1);
  EXPECT_TRUE(c.on_key("bracketright", 5.0));
  EXPECT_EQ(c.speed, 2.0);
  c.on_key("bracketleft", 5.0);
  c.on_key("bracketleft", 5.0);
  EXPECT_EQ(c.speed, 0.5);
  c.on_key("Left", 5.0);
  c.on_key("Left", 5.0);
  c.on_key("Right", 5.0);
  EXPECT_EQ(c.seek_by_s, -5.0);
  c.on_key("Home", 5.0);
  EXPECT_TRUE(c.seek_to_start);
  EXPECT_FALSE(c.on_key("p", 5.0));  // PCL's own
  EXPECT_NE(c.status(1.0, 2.0).find("paused"), std::string::npos);
}

// The golden paper_sim window: no LIDAR_POINTS, so LIDAR_SCAN is decoded;
// seeking to a time gives the same picture as playing up to it.
TEST(VizTimeline, SeekingMatchesPlayingAndScansAreDecoded) {
  const auto events = evade::bus::read_log(std::string(EVADE_SOURCE_DIR) + "/logs/paper_sim_crossing/input.lcmlog");
  LogTimeline a(events), b(events);
  EXPECT_GT(a.duration_s(), 2.5);
  auto wa = make_state(), wb = make_state();
  a.seek(wa.get(), 0.0);
  for (int i = 0; i < 20; ++i) a.advance(wa.get(), 0.1);
  b.seek(wb.get(), 2.0);
  EXPECT_DOUBLE_EQ(a.position_s(), b.position_s());
  EXPECT_FALSE(wa->heard_points());
  ASSERT_GT(wa->cloud.size(), 10000u);
  EXPECT_EQ(wa->cloud_utime, wb->cloud_utime);
  ASSERT_EQ(wa->cloud.size(), wb->cloud.size());
  for (size_t i = 0; i < wa->cloud.size(); i += 97) EXPECT_EQ(wa->cloud[i].x, wb->cloud[i].x) << i;
  ASSERT_TRUE(wa->plan && wb->plan && wa->obstacles && wb->obstacles && wa->truth && wb->truth);
  EXPECT_EQ(wa->plan->utime, wb->plan->utime);
  EXPECT_EQ(wa->obstacles->utime, wb->obstacles->utime);
  EXPECT_EQ(wa->odometry->utime, wb->odometry->utime);
  EXPECT_EQ(wa->truth->utime, wb->truth->utime);
  EXPECT_EQ(wa->malformed(), 0);
  // and back: a seek forgets what came later
  b.seek(wb.get(), 0.5);
  EXPECT_LT(wb->plan->utime, wa->plan->utime);
}

}  // namespace

namespace {

// --snapshot-moments' times land on the SIM_TRUTH samples the metrics chose.
TEST(VizMoments, ClosestApproachAndFirstSightsLandOnTheirSamples) {
  const auto events = evade::bus::read_log(std::string(EVADE_SOURCE_DIR) + "/logs/paper_sim_crossing/input.lcmlog");
  const auto mp = evade::metrics::MetricsParams::from_config(robot_config().section("metrics"));
  const auto moments = key_moments(events, mp);
  const auto m = evade::metrics::compute_metrics(events, mp);
  int64_t t0 = std::numeric_limits<int64_t>::max();
  for (const auto& e : events) {
    evade::sim_truth_t t;
    if (e.channel == "SIM_TRUTH" && evade::bus::decode(e.data.data(), e.data.size(), &t)) t0 = std::min(t0, t.utime);
  }
  ASSERT_FALSE(moments.empty());
  EXPECT_EQ(moments.back().name, "closest");
  LogTimeline t(events);
  auto w = make_state();
  for (const auto& mo : moments) {
    EXPECT_GE(mo.t_s, 0.0);
    EXPECT_LE(mo.t_s, t.duration_s());
    t.seek(w.get(), mo.t_s);
    ASSERT_TRUE(w->truth) << mo.name;
    double want_s = -1;
    if (mo.name == "closest") {
      want_s = m.robot_t_s[size_t(m.closest_sample)];
    } else {
      for (const auto& o : m.obstacles)
        if (mo.name == "obstacle_" + std::to_string(o.id)) want_s = *o.t_enter_s;
    }
    ASSERT_GE(want_s, 0.0) << mo.name;
    EXPECT_NEAR((w->truth->utime - t0) * 1e-6, want_s, 1e-3) << mo.name;
  }
}

}  // namespace
