// The obstacle module's treatment of predicted steps too uncertain to be
// useful (bound_uncertain): the reachable disc where it is the smaller bound.
#include "planning/obstacles.h"

#include <gtest/gtest.h>

#include <cmath>

namespace evade::planning {
namespace {

// A track of 26 steps 0.1 s apart at (x0, 0) moving at vx, its body a disc
// of radius body, its uncertainty radius sigma0 + growth * t.
evade::track_prediction_t track(double vx, double body, double sigma0, double growth) {
  evade::track_prediction_t t{};
  t.id = 4;
  t.vx = vx;
  t.horizon = 26;
  for (int k = 0; k < t.horizon; ++k) {
    const double s = sigma0 + growth * 0.1 * k;
    t.x.push_back(2.0 + vx * 0.1 * k);
    t.y.push_back(1.0);
    t.a.push_back(body + s);
    t.b.push_back(body + s);
    t.theta.push_back(0.0);
    t.sigma.push_back(s);
  }
  return t;
}

TEST(ObstaclesUncertain, NewTrackBecomesTheReachableDiscHeldAfterReach) {
  UncertainParams u;                          // max_sigma 1.0 m, reach 0.5 s, small bodies 3 m/s
  const auto t = track(0.0, 0.25, 0.1, 4.0);  // velocity unknown: sigma 4 m per s
  ObstacleTrack o = align_track(t, 0.1, 0.0, 25, 0.1);
  bound_uncertain(t, u, 0.1, 0.0, 0.1, &o);
  for (int k = 0; k <= 5; ++k) {
    const double tau = 0.1 * k;
    if (t.sigma[k] <= u.max_sigma_m) {  // useful: as published
      EXPECT_DOUBLE_EQ(o.a[k], t.a[k]) << k;
      continue;
    }
    EXPECT_NEAR(o.a[k], std::min(t.a[0] + 3.0 * tau, t.a[k]), 1e-12) << k;
  }
  EXPECT_NEAR(o.a[5], t.a[0] + 1.5, 1e-12);  // the disc is the smaller bound at 0.5 s
  EXPECT_DOUBLE_EQ(o.x[5], t.x[0]);
  for (int k = 6; k <= 25; ++k) EXPECT_DOUBLE_EQ(o.a[k], o.a[5]) << k;  // held after reach_s
}

TEST(ObstaclesUncertain, AMoverCertainPastReachHoldsItsLastCertainStep) {
  UncertainParams u;
  const auto t = track(1.0, 0.25, 0.05, 0.5);  // sigma crosses 1 m at 1.9 s
  ObstacleTrack o = align_track(t, 0.1, 0.0, 25, 0.1);
  const ObstacleTrack published = o;
  bound_uncertain(t, u, 0.1, 0.0, 0.1, &o);
  for (int k = 0; k <= 19; ++k) EXPECT_DOUBLE_EQ(o.a[k], published.a[k]) << k;
  for (int k = 20; k <= 25; ++k) {
    EXPECT_DOUBLE_EQ(o.a[k], published.a[19]) << k;
    EXPECT_DOUBLE_EQ(o.x[k], published.x[19]) << k;
  }
}

TEST(ObstaclesUncertain, ConfidentTrackAndDisabledRuleKeepThePublishedEllipses) {
  UncertainParams u;
  const auto steady = track(1.2, 0.25, 0.05, 0.2);  // sigma stays below 1 m
  ObstacleTrack o = align_track(steady, 0.1, 0.05, 25, 0.1);
  const ObstacleTrack before = o;
  bound_uncertain(steady, u, 0.1, 0.05, 0.1, &o);
  EXPECT_EQ(o.a, before.a);
  EXPECT_EQ(o.x, before.x);
  const auto fresh = track(0.0, 0.25, 0.1, 2.0);
  ObstacleTrack f = align_track(fresh, 0.1, 0.0, 25, 0.1);
  const ObstacleTrack published = f;
  u.enabled = false;
  bound_uncertain(fresh, u, 0.1, 0.0, 0.1, &f);
  EXPECT_EQ(f.a, published.a);
}

TEST(ObstaclesUncertain, LargeBodiesReachAtTheirOwnSpeed) {
  UncertainParams u;
  const auto bike = track(0.0, 0.9, 0.1, 8.0);
  ObstacleTrack o = align_track(bike, 0.1, 0.0, 25, 0.1);
  bound_uncertain(bike, u, 0.1, 0.0, 0.1, &o);
  EXPECT_NEAR(o.a[25], bike.a[0] + 5.0 * 0.5, 1e-12);
}

}  // namespace
}  // namespace evade::planning
