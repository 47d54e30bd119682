// CLEAR MOT and the perception metrics on hand-made logs whose scores are
// known, and ReturnCounter; the tool on the golden log.
#include "metrics/perception_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bus/core.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "metrics/clear_mot.h"
#include "sim/return_counter.h"

namespace evade::metrics {
namespace {

TrueObject disc(int id, double x, double y, bool scored = true) {
  TrueObject o;
  o.id = id;
  o.centre = {x, y};
  o.radius = 0.25;
  o.scored = scored;
  return o;
}

TEST(ClearMot, PerfectTrackingScoresOne) {
  ClearMot mot(1.0);
  for (int f = 0; f < 10; ++f)
    mot.add_frame(f * 0.1, 0.1, {disc(0, f * 0.1, 0), disc(1, 5, 5)}, {{7, {f * 0.1 + 0.05, 0}}, {8, {5, 5}}});
  MotTotals t = mot.totals();
  EXPECT_EQ(t.objects, 20);
  EXPECT_EQ(t.matches, 20);
  EXPECT_DOUBLE_EQ(t.mota(), 1.0);
  EXPECT_NEAR(*t.motp_m(), 0.025, 1e-12);
  EXPECT_EQ(t.mostly_tracked, 2);
  EXPECT_NEAR(t.track_s, 2.0, 1e-12);
}

TEST(ClearMot, MissesFalsePositivesSwitchesAndFragmentations) {
  ClearMot mot(1.0);
  mot.add_frame(0.0, 0.1, {disc(0, 0, 0)}, {{1, {0, 0}}});
  mot.add_frame(0.1, 0.1, {disc(0, 0, 0)}, {});             // miss
  mot.add_frame(0.2, 0.1, {disc(0, 0, 0)}, {{2, {0, 0}}});  // tracked again by another id: switch + fragmentation
  mot.add_frame(0.3, 0.1, {disc(0, 0, 0)}, {{2, {0, 0}}, {3, {3, 3}}});    // a false positive
  mot.add_frame(0.4, 0.1, {disc(0, 0, 0)}, {{2, {0, 0}}, {5, {0.3, 0}}});  // a split: two tracks on one object
  MotTotals t = mot.totals();
  EXPECT_EQ(t.objects, 5);
  EXPECT_EQ(t.misses, 1);
  EXPECT_EQ(t.id_switches, 1);
  EXPECT_EQ(t.fragmentations, 1);
  EXPECT_EQ(t.false_positives, 2);
  EXPECT_EQ(t.splits, 1);
  EXPECT_DOUBLE_EQ(t.mota(), 1.0 - 4.0 / 5.0);
}

TEST(ClearMot, ATrackKeepsItsObjectWhileWithinTheGateEvenIfAnotherIsNearer) {
  ClearMot mot(1.0);
  mot.add_frame(0.0, 0.1, {disc(0, 0, 0), disc(1, 1.2, 0)}, {{10, {0, 0}}, {11, {1.2, 0}}});
  // The tracks drift towards each other's object: CLEAR MOT keeps the correspondences.
  mot.add_frame(0.1, 0.1, {disc(0, 0, 0), disc(1, 1.2, 0)}, {{10, {0.7, 0}}, {11, {0.5, 0}}});
  EXPECT_EQ(mot.totals().id_switches, 0);
}

TEST(ClearMot, TwoObjectsUnderOneTrackAreAMissAndAMerge) {
  ClearMot mot(1.0);
  mot.add_frame(0.0, 0.1, {disc(0, 0, 0), disc(1, 0.6, 0)}, {{9, {0.3, 0}}});
  MotTotals t = mot.totals();
  EXPECT_EQ(t.matches, 1);
  EXPECT_EQ(t.misses, 1);
  EXPECT_EQ(t.merges, 1);
  mot.add_frame(0.1, 0.1, {disc(0, 0, 0), disc(1, 5.0, 0)}, {{9, {0.0, 0}}});  // apart, the second unseen
  EXPECT_EQ(mot.totals().merges, 1);
}

TEST(ClearMot, UnscoredObjectsAreNeitherMissedNorFalsePositives) {
  ClearMot mot(1.0);
  // Object 0 hidden (not scored) with a coasting track on it; object 1 out of range, no track.
  mot.add_frame(0.0, 0.1, {disc(0, 0, 0, false), disc(1, 9, 0, false)}, {{4, {0.1, 0}}, {5, {20, 0}, false}});
  MotTotals t = mot.totals();
  EXPECT_EQ(t.objects, 0);
  EXPECT_EQ(t.misses, 0);
  EXPECT_EQ(t.false_positives, 0);
}

TEST(ReturnCounter, CountsPerRevolutionAndForgetsSkippedOnes) {
  sim::ReturnCounter c;
  EXPECT_EQ(c.last_complete(2), std::vector<int32_t>({-1, -1}));
  c.add(0, 1);
  c.add(0, 1);
  EXPECT_EQ(c.last_complete(2), std::vector<int32_t>({-1, -1}));  // revolution 0 not complete
  c.add(1, 0);
  EXPECT_EQ(c.last_complete(2), std::vector<int32_t>({0, 2}));
  c.reach(3);  // revolution 2 passed without any return
  EXPECT_EQ(c.last_complete(3), std::vector<int32_t>({0, 0, 0}));
}

// A log: an obstacle walking along x at 1 m/s, the robot at rest at the
// origin, a tracker that sees it 0.1 m behind, a predictor that extrapolates
// the true velocity from there with a 0.3 m ellipse, publishing
// `track_vx` as the track's velocity.
std::vector<bus::LogEvent> walking_log(double ellipse_m, double track_vx = 1.0) {
  std::vector<bus::LogEvent> ev;
  const int64_t t0 = 1'000'000'000;
  for (int k = 0; k <= 100; ++k) {  // 5 s of truth at 20 Hz
    const int64_t t = t0 + k * 50'000;
    evade::sim_truth_t s{};
    s.utime = t;
    evade::sim_obstacle_t o{};
    o.shape = "cylinder";
    o.radius = 0.25;
    o.height = 1.7;
    o.x = 1.0 + k * 0.05;
    o.y = 2.0;
    o.vx = 1.0;
    s.obstacles = {o};
    s.num_obstacles = 1;
    s.lidar_returns = {40};
    ev.push_back({t, "SIM_TRUTH", bus::encode(s)});
    evade::odometry_t od{};
    od.utime = t;
    ev.push_back({t, "ODOMETRY", bus::encode(od)});
    if (k % 2 || k > 40) continue;
    evade::obstacle_list_t l{};
    l.utime = t;
    evade::obstacle_t ob{};
    ob.id = 3;
    ob.x = o.x - 0.1;
    ob.y = 2.0;
    ob.a = ob.b = 0.25;
    l.obstacles = {ob};
    l.num_obstacles = 1;
    ev.push_back({t, "OBSTACLES", bus::encode(l)});
    evade::prediction_list_t p{};
    p.utime = t;
    p.dt = 0.1;
    p.horizon = 26;
    evade::track_prediction_t tp{};
    tp.id = 3;
    tp.horizon = 26;
    tp.vx = track_vx;
    for (int i = 0; i < 26; ++i) {
      tp.x.push_back(ob.x + 0.1 * i);
      tp.y.push_back(2.0);
      tp.a.push_back(ellipse_m);
      tp.b.push_back(ellipse_m);
      tp.theta.push_back(0.0);
      tp.sigma.push_back(0.0);
    }
    p.tracks = {tp};
    p.num_tracks = 1;
    ev.push_back({t, "OBSTACLE_PREDICTIONS", bus::encode(p)});
  }
  return ev;
}

PerceptionParams params() {
  PerceptionParams p;
  p.min_track_age_s = 0.0;
  return p;
}

TEST(PerceptionMetrics, ConstantOffsetGivesItsErrorsAndCoverageFollowsTheEllipse) {
  PerceptionMetrics m = compute_perception(walking_log(0.3), params());
  EXPECT_EQ(m.mot.objects, 21);
  EXPECT_DOUBLE_EQ(m.mot.mota(), 1.0);
  EXPECT_NEAR(*m.mot.motp_m(), 0.1, 1e-9);
  ASSERT_TRUE(m.ade_1s_m && m.fde_2_5s_m);
  EXPECT_NEAR(*m.ade_1s_m, 0.1, 1e-9);
  EXPECT_NEAR(*m.fde_2_5s_m, 0.1, 1e-9);
  EXPECT_EQ(m.walker_predictions, m.predictions);
  ASSERT_EQ(m.steps.size(), 26u);
  EXPECT_EQ(m.steps[25].inside, m.steps[25].n);  // 0.1 m off, 0.3 m ellipse
  PerceptionMetrics tight = compute_perception(walking_log(0.05), params());
  EXPECT_EQ(tight.steps[25].inside, 0);  // 0.1 m off, 0.05 m ellipse
  EXPECT_NEAR(tight.steps[0].area_sum_m2 / tight.steps[0].n_all, M_PI * 0.05 * 0.05, 1e-12);
}

TEST(PerceptionMetrics, AWalkersErrorIsSplitIntoCentreVelocityAndScriptedMotion) {
  // Seen 0.1 m behind (-x) from the origin while at (1..3, 2): partly
  // towards the robot; published 0.8 m/s against the true 1 m/s; it walks
  // straight, so the true state extrapolated has no error.
  PerceptionMetrics m = compute_perception(walking_log(0.3, 0.8), params());
  ASSERT_TRUE(m.walker_centre_error_m && m.walker_centre_radial_m && m.walker_velocity_error_mps &&
              m.walker_ade_1s_cv_truth_m);
  EXPECT_NEAR(*m.walker_centre_error_m, 0.1, 1e-9);
  EXPECT_LT(*m.walker_centre_radial_m, -0.02);
  EXPECT_GT(*m.walker_centre_radial_m, -0.1);
  EXPECT_NEAR(*m.walker_velocity_error_mps, 0.2, 1e-9);
  EXPECT_NEAR(*m.walker_ade_1s_cv_truth_m, 0.0, 1e-9);
  EXPECT_NEAR(*compute_perception(walking_log(0.3, 1.0), params()).walker_velocity_error_mps, 0.0, 1e-9);
}

// A log: a 10 m wall along y = 2 and a walker at 1 m/s along y = -1, the
// robot at rest at the origin; 2 s of lists from t = 1 s, each with a track
// on the wall at x = 1 published at 0.5 m/s, one on it at x = 3 at 0.1 m/s,
// one on the walker at 1 m/s and one 20 m away at 2 m/s.
std::vector<bus::LogEvent> wall_log() {
  std::vector<bus::LogEvent> ev;
  const int64_t t0 = 1'000'000'000;
  for (int k = 0; k <= 60; ++k) {  // 3 s of truth at 20 Hz
    const int64_t t = t0 + k * 50'000;
    evade::sim_truth_t s{};
    s.utime = t;
    evade::sim_obstacle_t wall{};
    wall.shape = "box";
    wall.length = 10.0;
    wall.width = 0.2;
    wall.height = 1.0;
    wall.y = 2.0;
    evade::sim_obstacle_t walker{};
    walker.id = 1;
    walker.shape = "cylinder";
    walker.radius = 0.25;
    walker.height = 1.7;
    walker.x = -2.0 + k * 0.05;
    walker.y = -1.0;
    walker.vx = 1.0;
    s.obstacles = {wall, walker};
    s.num_obstacles = 2;
    s.lidar_returns = {200, 40};
    ev.push_back({t, "SIM_TRUTH", bus::encode(s)});
    evade::odometry_t od{};
    od.utime = t;
    ev.push_back({t, "ODOMETRY", bus::encode(od)});
    if (k % 2 || k < 20) continue;
    evade::obstacle_list_t l{};
    l.utime = t;
    evade::prediction_list_t p{};
    p.utime = t;
    p.dt = 0.1;
    p.horizon = 1;
    const double tracks[4][4] = {
        {1.0, 2.0, 0.5, 0.0}, {3.0, 2.0, 0.1, 0.0}, {walker.x, -1.0, 1.0, 0.0}, {20.0, 0.0, 2.0, 0.0}};
    for (int i = 0; i < 4; ++i) {
      evade::obstacle_t ob{};
      ob.id = i + 1;
      ob.x = tracks[i][0];
      ob.y = tracks[i][1];
      ob.a = ob.b = 0.25;
      l.obstacles.push_back(ob);
      evade::track_prediction_t tp{};
      tp.id = i + 1;
      tp.horizon = 1;
      tp.vx = tracks[i][2];
      tp.vy = tracks[i][3];
      tp.x = {ob.x};
      tp.y = {ob.y};
      tp.a = {0.25};
      tp.b = {0.25};
      tp.theta = {0.0};
      tp.sigma = {0.0};
      p.tracks.push_back(tp);
    }
    l.num_obstacles = 4;
    p.num_tracks = 4;
    ev.push_back({t, "OBSTACLES", bus::encode(l)});
    ev.push_back({t, "OBSTACLE_PREDICTIONS", bus::encode(p)});
  }
  return ev;
}

TEST(PerceptionMetrics, StaticStructurePublishedMovingIsCounted) {
  const PerceptionMetrics m = compute_perception(wall_log(), params());
  // 21 lists; the wall's two tracks count, the walker's and the far one do not
  EXPECT_EQ(m.static_track_frames, 42);
  EXPECT_EQ(m.static_moving_frames, 21);
  EXPECT_EQ(m.static_moving_tracks, 1);
  EXPECT_NEAR(m.static_speed_sum_mps / m.static_track_frames, 0.3, 1e-9);
  const std::string json = perception_json(m, params());
  EXPECT_NE(json.find("\"static_moving_fraction\": 0.5,"), std::string::npos) << json;
  PerceptionParams slower = params();
  slower.static_max_speed_mps = 0.05;  // now the slow one moves too
  EXPECT_EQ(compute_perception(wall_log(), slower).static_moving_frames, 42);
}

TEST(PerceptionMetrics, AnObjectOutOfRangeOrUnseenIsNotScored) {
  PerceptionParams p = params();
  p.range_m = 1.5;  // the walker starts 2.2 m away
  EXPECT_EQ(compute_perception(walking_log(0.3), p).mot.objects, 0);
  p = params();
  p.min_returns = 41;  // it gave 40
  EXPECT_EQ(compute_perception(walking_log(0.3), p).mot.objects, 0);
}

TEST(PerceptionMetricsTool, ScoresTheGoldenLog) {
  const std::string out = ::testing::TempDir() + "perception_golden.json";
  const std::string cmd = std::string(PERCEPTION_METRICS_BIN) + " " + EVADE_SOURCE_DIR +
                          "/logs/paper_sim_crossing/input.lcmlog --out " + out + " > /dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream f(out);
  nlohmann::json j = nlohmann::json::parse(f);
  // A 3 s cut of a run (its SIM_TRUTH migrated, so every object counts as
  // visible): the counts add up and the matched tracks are near their objects.
  const int objects = j["objects"].get<int>(), matches = j["matches"].get<int>();
  EXPECT_GT(matches, 0);
  EXPECT_EQ(matches + j["misses"].get<int>(), objects);
  EXPECT_NEAR(
      j["mota"].get<double>(),
      1.0 - double(j["misses"].get<int>() + j["false_positives"].get<int>() + j["id_switches"].get<int>()) / objects,
      1e-5);
  EXPECT_LT(j["motp_m"].get<double>(), 0.3);
  EXPECT_EQ(j["coverage"].size(), j["ellipse_area_m2"].size());
  EXPECT_FALSE(j["ade_1s_m"].is_null());
  const std::string bad = std::string(PERCEPTION_METRICS_BIN) + " /nonexistent.lcmlog 2> /dev/null";
  EXPECT_NE(std::system(bad.c_str()), 0);
}

}  // namespace
}  // namespace evade::metrics
