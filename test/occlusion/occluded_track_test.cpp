// A track that vanishes inside a hidden region is kept, its ellipse
// growing at the hidden speed; one that vanishes in plain view is dropped
// after coast_max_s as before (lib/prediction/occluded.h).
#include <gtest/gtest.h>

#include <cmath>

#include "config/config.h"
#include "prediction/predictor.h"

namespace evade::prediction {
namespace {

// robot.yaml's predictor with the hidden tracks on (off by default).
PredictorParams default_params() {
  auto p = PredictorParams::from_config(
      config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml").section("predictor"));
  p.occluded.enabled = true;
  return p;
}

// The shadow behind a van's near face x in [2, 6], y = 2, seen from the origin.
evade::hidden_region_list_t van_shadow(int64_t utime) {
  evade::hidden_region_list_t m;
  m.utime = utime;
  m.sensor_x = m.sensor_y = 0.0;
  evade::hidden_region_t r{};
  const double px[2] = {6.0, 2.0}, py[2] = {2.0, 2.0};
  for (int i = 0; i < 2; ++i) {
    const double d = std::hypot(px[i], py[i]);
    r.near_x[i] = px[i];
    r.near_y[i] = py[i];
    r.far_x[i] = px[i] * (1 + 4.0 / d);
    r.far_y[i] = py[i] * (1 + 4.0 / d);
  }
  m.regions = {r};
  m.num_regions = 1;
  return m;
}

evade::obstacle_list_t walkers(int64_t utime, const std::vector<std::pair<int64_t, std::pair<double, double>>>& at) {
  evade::obstacle_list_t m;
  m.utime = utime;
  for (const auto& [id, xy] : at) {
    evade::obstacle_t o{};
    o.id = id;
    o.x = xy.first;
    o.y = xy.second;
    o.a = o.b = 0.25;
    m.obstacles.push_back(o);
  }
  m.num_obstacles = int32_t(m.obstacles.size());
  return m;
}

const evade::track_prediction_t* find(const evade::prediction_list_t& out, int64_t id) {
  for (const auto& t : out.tracks)
    if (t.id == id) return &t;
  return nullptr;
}

// Walker 1 walks behind the van (from (3, 3) along +x, in the shadow),
// walker 2 walks in the open at y = -2, track 3 stands in the shadow at
// (2.6, 2.3) (a piece of the van the tracker split off); all vanish at
// t = 1 s and are not seen again. Returns the prediction lists from then
// on, one per 0.1 s.
std::vector<evade::prediction_list_t> vanish(const PredictorParams& p, bool with_regions) {
  Predictor pred(p);
  std::vector<evade::prediction_list_t> after;
  for (int i = 0; i <= 50; ++i) {
    const int64_t utime = 1'000'000 + i * 100'000;
    const double t = 0.1 * i, x = 3.0 + 1.0 * t;
    if (with_regions) pred.set_hidden_regions(van_shadow(utime));
    evade::prediction_list_t out;
    FrameStats st;
    const auto list = i <= 10 ? walkers(utime, {{1, {x, 3.0}}, {2, {x, -2.0}}, {3, {2.6, 2.3}}}) : walkers(utime, {});
    EXPECT_TRUE(pred.process(list, &out, &st));
    if (i > 10) after.push_back(out);
  }
  return after;
}

TEST(OccludedTracks, HiddenTrackIsKeptAndGrowsAtTheHiddenSpeed) {
  const PredictorParams p = default_params();
  ASSERT_TRUE(p.occluded.enabled);
  ASSERT_LT(p.coast_max_s, 2.0);
  const auto after = vanish(p, true);
  // 2.5 s unseen: beyond coast_max_s, within occluded.max_s.
  const auto& late = after[24];
  const evade::track_prediction_t* hidden = find(late, 1);
  ASSERT_NE(hidden, nullptr) << "the track that vanished behind the van is dropped";
  EXPECT_EQ(find(late, 2), nullptr) << "the track that vanished in the open is kept";
  EXPECT_EQ(find(late, 3), nullptr) << "the standing piece of the occluder is kept as hidden";
  EXPECT_NE(find(after[2], 3), nullptr);  // it coasts for coast_max_s, as one vanishing in the open
  // Held where last seen (x 4.0 at t = 1 s), both axes grown by 1.6 m/s x 2.5 s at k = 0, more ahead.
  EXPECT_NEAR(hidden->x[0], 4.0, 1e-9);
  EXPECT_NEAR(hidden->y[0], 3.0, 1e-9);
  EXPECT_NEAR(hidden->a[0], 0.25 + p.occluded.max_speed_mps * 2.5, 1e-6);
  const int n = hidden->horizon;
  EXPECT_NEAR(hidden->b[n - 1], 0.25 + p.occluded.max_speed_mps * (2.5 + (n - 1) * p.prediction_dt_s), 1e-6);
  // Not kept beyond max_s.
  const size_t last = size_t(std::llround(p.occluded.max_s / 0.1)) + 1;
  ASSERT_LT(last, after.size());
  EXPECT_EQ(find(after[last], 1), nullptr);
}

TEST(OccludedTracks, WithoutRegionsBothAreDroppedAfterCoasting) {
  const PredictorParams p = default_params();
  const auto after = vanish(p, false);
  EXPECT_EQ(find(after[24], 1), nullptr);
  EXPECT_EQ(find(after[24], 2), nullptr);
  EXPECT_NE(find(after[2], 1), nullptr);  // coasting for coast_max_s, as before
}

TEST(OccludedTracks, QuadrilateralInside) {
  const evade::hidden_region_t r = van_shadow(0).regions[0];
  EXPECT_TRUE(inside(r, 4.0, 3.0));
  EXPECT_FALSE(inside(r, 3.0, 1.0));  // in front of the van
  EXPECT_FALSE(inside(r, 8.0, 1.0));  // beside the shadow
  EXPECT_TRUE(inside(r, 2.6, 2.3));
}

}  // namespace
}  // namespace evade::prediction
