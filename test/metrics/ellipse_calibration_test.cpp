// The published ellipses' calibration by class and age (ellipse_calibration.h).
#include "metrics/ellipse_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace evade::metrics {
namespace {

TrueObject disc(double x, double y, double r) {
  TrueObject o;
  o.centre = {x, y};
  o.radius = r;
  return o;
}

evade::sim_obstacle_t cylinder(double radius, double height) {
  evade::sim_obstacle_t o;
  o.shape = "cylinder";
  o.radius = radius;
  o.height = height;
  return o;
}

// A still prediction at the origin: extent 0.3 m, inflation sigma at every step.
evade::track_prediction_t circle(int horizon, double extent, double sigma) {
  evade::track_prediction_t tp;
  tp.horizon = horizon;
  for (int k = 0; k < horizon; ++k) {
    tp.x.push_back(0.0);
    tp.y.push_back(0.0);
    tp.theta.push_back(0.0);
    tp.a.push_back(extent + sigma);
    tp.b.push_back(extent + sigma);
    tp.sigma.push_back(sigma);
  }
  return tp;
}

TEST(EllipseCalibration, ClassesFromTheTrueShape) {
  EXPECT_STREQ(class_name(classify(cylinder(0.25, 1.7), false)), "walker");
  EXPECT_STREQ(class_name(classify(cylinder(0.11, 0.22), false)), "ball");
  EXPECT_STREQ(class_name(classify(cylinder(0.2, 0.5), false)), "dog");
  EXPECT_STREQ(class_name(classify(cylinder(0.25, 1.7), true)), "static");
  evade::sim_obstacle_t bike;
  bike.shape = "box";
  bike.length = 1.8;
  bike.width = 0.6;
  EXPECT_STREQ(class_name(classify(bike, false)), "bike");
  bike.length = 4.5;
  EXPECT_STREQ(class_name(classify(bike, false)), "other");
}

TEST(EllipseCalibration, AgeBins) {
  EXPECT_EQ(age_bin(0.0), 0);
  EXPECT_EQ(age_bin(0.49), 0);
  EXPECT_EQ(age_bin(0.5), 1);
  EXPECT_EQ(age_bin(1.5), 2);
  EXPECT_EQ(age_bin(4.9), 3);
  EXPECT_EQ(age_bin(60.0), 4);
  EXPECT_STREQ(age_bin_name(4), "5+");
}

TEST(EllipseCalibration, BodyInsideNeedsTheWholeDisc) {
  // Ellipse 1 x 0.5 along x: a 0.2 m disc at the centre fits, 0.35 m above
  // the centre does not (0.35 + 0.2 > 0.5), nor does one near the tip.
  EXPECT_TRUE(body_inside_ellipse(disc(0.0, 0.0, 0.2), {0.0, 0.0}, 1.0, 0.5, 0.0));
  EXPECT_FALSE(body_inside_ellipse(disc(0.0, 0.35, 0.2), {0.0, 0.0}, 1.0, 0.5, 0.0));
  EXPECT_FALSE(body_inside_ellipse(disc(0.9, 0.0, 0.2), {0.0, 0.0}, 1.0, 0.5, 0.0));
  EXPECT_TRUE(body_inside_ellipse(disc(0.7, 0.0, 0.2), {0.0, 0.0}, 1.0, 0.5, 0.0));
  // Rotated by 90 deg the long axis is y.
  EXPECT_TRUE(body_inside_ellipse(disc(0.0, 0.7, 0.2), {0.0, 0.0}, 1.0, 0.5, M_PI / 2));
  TrueObject box;
  box.box = OrientedRect{{0.0, 0.0}, 0.0, 1.2, 0.4};
  EXPECT_TRUE(body_inside_ellipse(box, {0.0, 0.0}, 1.0, 0.5, 0.0));
  box.box.length = 1.9;  // corner (0.95, 0.2): 0.9025 + 0.16 > 1
  EXPECT_FALSE(body_inside_ellipse(box, {0.0, 0.0}, 1.0, 0.5, 0.0));
}

TEST(EllipseCalibration, CountsCentreInflationAndBodyPerStep) {
  // Extent 0.3 m, inflation 0.1 m; the true walker (radius 0.25 m) 0.05 m
  // off at step 0 (inside everything), 0.2 m off at step 1 (centre inside
  // the ellipse but beyond sigma, body sticking out).
  const evade::track_prediction_t tp = circle(2, 0.3, 0.1);
  EllipseCalibration cal;
  add_calibration(tp, {disc(0.05, 0.0, 0.25), disc(0.2, 0.0, 0.25)}, ObjectClass::kWalker, 3.0, 0.5, &cal);
  const EllipseTally& w = cal.by_class[static_cast<size_t>(ObjectClass::kWalker)];
  ASSERT_EQ(w.steps.size(), 2u);
  EXPECT_EQ(w.steps[0].inside + w.steps[0].inflation_inside + w.steps[0].body_inside, 3);
  EXPECT_EQ(w.steps[1].inside, 1);
  EXPECT_EQ(w.steps[1].inflation_inside, 0);
  EXPECT_EQ(w.steps[1].body_inside, 0);
  EXPECT_NEAR(w.excess_sum_m, 0.05, 1e-12);  // extent 0.3 against the 0.25 m body
  EXPECT_NEAR(w.steps[1].area_sum_m2, M_PI * 0.4 * 0.4, 1e-12);
  EXPECT_NEAR(w.steps[1].error_sum_m, 0.2, 1e-12);
  EXPECT_EQ(cal.by_age[static_cast<size_t>(age_bin(3.0))].steps[1].n, 1);
  // A young track counts by age only.
  add_calibration(tp, {disc(0.0, 0.0, 0.25)}, ObjectClass::kWalker, 0.2, 0.5, &cal);
  EXPECT_EQ(w.predictions, 1);
  EXPECT_EQ(cal.by_age[0].predictions, 1);
  const std::string json = calibration_json(cal);
  EXPECT_NE(json.find("\"class_body_coverage\": {\"walker\": [1, 0]}"), std::string::npos) << json;
  EXPECT_NE(json.find("\"age_n\": {\"0-0.5\": [1], \"2-5\": [1, 1]}"), std::string::npos) << json;
}

}  // namespace
}  // namespace evade::metrics
