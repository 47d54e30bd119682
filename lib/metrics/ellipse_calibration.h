// Where a published predicted ellipse's size comes from and what it covers,
// split by the kind of object and by the track's age (issue 23 item 2:
// "no larger than needed"). A published ellipse is the tracker's extent
// (semi-axes a - sigma, b - sigma) grown by the predictor's inflation sigma
// (track_prediction_t.sigma). For every scored step it counts:
// - coverage: the true centre inside the published ellipse;
// - inflation coverage: the centre error at most sigma (the inflation alone,
//   the covariance's own radius, covers the centre);
// - body coverage: the whole true body (a disc, or a box's corners) inside
//   the published ellipse (what the planner's hard constraints assume);
// - area pi a b, sigma and the centre error; and once per prediction (step 0) the extent's
//   excess: sqrt((a - sigma)(b - sigma)) less the body's radius (a box:
//   half the geometric mean of its length and width).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "evade/sim_obstacle_t.hpp"
#include "evade/track_prediction_t.hpp"
#include "metrics/clear_mot.h"

namespace evade::metrics {

// walker: a cylinder at least 1 m high (joggers included); ball: a cylinder
// no higher than 2.5 radii and no wider than 0.12 m; dog: a lower cylinder;
// bike: a box at most 2.5 m long; static: any object that has not moved for
// the last second (it is that first); other: the rest (moving large boxes).
enum class ObjectClass { kWalker, kBike, kBall, kDog, kStatic, kOther };
constexpr int kObjectClasses = 6;
const char* class_name(ObjectClass c);
ObjectClass classify(const evade::sim_obstacle_t& o, bool still);

// Track-age bins (s since the track's first OBSTACLES appearance).
constexpr int kAgeBins = 5;
constexpr std::array<double, kAgeBins> kAgeBinStart = {0.0, 0.5, 1.0, 2.0, 5.0};
const char* age_bin_name(int bin);
int age_bin(double age_s);

struct EllipseStep {
  int64_t n = 0, inside = 0, inflation_inside = 0, body_inside = 0;
  double area_sum_m2 = 0.0, sigma_sum_m = 0.0, error_sum_m = 0.0;
};

struct EllipseTally {
  std::vector<EllipseStep> steps;  // index k = horizon step
  double excess_sum_m = 0.0;       // step 0's extent excess, summed over predictions
  int64_t predictions = 0;
};

struct EllipseCalibration {
  std::array<EllipseTally, kObjectClasses> by_class;  // tracks at least min_track_age_s old
  std::array<EllipseTally, kAgeBins> by_age;          // every track
};

// Whether the whole body (a disc when radius > 0, else the box) lies inside
// the ellipse (centre c, semi-axes a, b, orientation theta).
bool body_inside_ellipse(const TrueObject& body, Vec2 c, double a, double b, double theta);

// One scored prediction: truth[k] is the object's true shape at step k
// (truth.size() <= tp.horizon).
void add_calibration(const evade::track_prediction_t& tp, const std::vector<TrueObject>& truth, ObjectClass cls,
                     double age_s, double min_track_age_s, EllipseCalibration* cal);

// The JSON members (without braces), each line "  \"key\": value" joined by ",\n".
std::string calibration_json(const EllipseCalibration& cal);

}  // namespace evade::metrics
