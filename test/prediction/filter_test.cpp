// The 9-state filter: the paper's A and H in our state order, the sparse
// propagation, the adaptive position noise law, and pi-periodic orientation.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "prediction/track_filter.h"
#include "scenario.h"

namespace evade::prediction {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The paper's printed A, for ITS state order (x, y, vx, vy, ax, ay, a, b, theta).
Covariance paper_printed_A(double T) {
  Covariance A = Covariance::Identity();
  A(0, 2) = T;
  A(0, 4) = T * T / 2;
  A(1, 3) = T;
  A(1, 5) = T * T / 2;
  A(2, 4) = T;
  A(3, 5) = T;
  return A;
}

TEST(Filter, TransitionMatrixIsThePapersAInOurStateOrder) {
  const double T = 0.137;
  // paper index of each of our states (x, y, a, b, theta, vx, vy, ax, ay)
  const int paper_of[9] = {0, 1, 6, 7, 8, 2, 3, 4, 5};
  const Covariance ours = transition_matrix(T);
  const Covariance paper = paper_printed_A(T);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) EXPECT_DOUBLE_EQ(ours(i, j), paper(paper_of[i], paper_of[j])) << i << "," << j;
}

TEST(Filter, SparsePropagationEqualsDenseProducts) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n01;
  Eigen::Matrix<double, 9, 9> L;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) L(i, j) = n01(rng);
  Covariance P = L * L.transpose();
  State x;
  for (int i = 0; i < 9; ++i) x(i) = n01(rng);
  const double dt = 0.083;
  testing::default_params();
  FilterParams fp;
  const Covariance Q = process_noise(fp, dt, fp.jerk_psd_m2ps5);
  const Covariance A = transition_matrix(dt);
  const State x_dense = A * x;
  const Covariance P_dense = A * P * A.transpose() + Q;
  propagate(&x, &P, Q, dt);
  EXPECT_LT((x - x_dense).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((P - P_dense).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(Filter, ProcessNoiseScalesWithTheInterval) {
  FilterParams fp;
  const Covariance q1 = process_noise(fp, 0.1, 0.05), q2 = process_noise(fp, 0.2, 0.05);
  EXPECT_NEAR(q2(kVx, kVx) / q1(kVx, kVx), 8.0, 1e-12);  // dt^3 / 3
  EXPECT_NEAR(q2(kX, kX) / q1(kX, kX), 32.0, 1e-12);     // dt^5 / 20
  EXPECT_NEAR(q2(kA, kA) / q1(kA, kA), 2.0, 1e-12);      // random walk
  EXPECT_EQ(q1(kX, kY), 0.0);
}

TEST(Filter, WrapHalfPi) {
  EXPECT_NEAR(wrap_half_pi(0.3), 0.3, 1e-15);
  EXPECT_NEAR(wrap_half_pi(0.3 + kPi), 0.3, 1e-12);
  EXPECT_NEAR(wrap_half_pi(0.3 - 3 * kPi), 0.3, 1e-12);
  EXPECT_NEAR(wrap_half_pi(kPi / 2 + 0.1), -kPi / 2 + 0.1, 1e-12);
  EXPECT_NEAR(wrap_half_pi(-kPi / 2), -kPi / 2, 1e-15);
  EXPECT_NEAR(wrap_half_pi(kPi / 2), -kPi / 2, 1e-15);
}

TEST(Filter, AdaptivePositionVarianceFollowsThePaper) {
  AdaptiveNoiseParams p;
  p.kappa = 5.5;
  p.gamma = 1.3;
  p.xi_min_m2 = 0.001;
  p.xi_max_m2 = 0.1;
  p.r_pos_min_m2 = 0.002;
  p.r_pos_max_m2 = 0.5;
  double k = -1;
  EXPECT_DOUBLE_EQ(adaptive_position_variance(0.0, p, &k), p.r_pos_min_m2);
  EXPECT_EQ(k, 0.0);
  EXPECT_NEAR(adaptive_position_variance(1e-6, p, &k), p.r_pos_min_m2, 1e-15);
  EXPECT_EQ(k, 0.0);
  EXPECT_NEAR(adaptive_position_variance(10.0, p, &k), p.r_pos_max_m2, 1e-15);
  EXPECT_EQ(k, 1.0);
  // Xi_p = kappa Xi_eta^gamma = sqrt(Xi_min Xi_max) = 0.01 gives k = 1/2, R_p = sqrt(R_min R_max).
  const double xi_eta = std::pow(0.01 / 5.5, 1.0 / 1.3);
  EXPECT_NEAR(adaptive_position_variance(xi_eta, p, &k), std::sqrt(0.002 * 0.5), 1e-12);
  EXPECT_NEAR(k, 0.5, 1e-12);
  // monotone in Xi_eta
  double prev = 0;
  for (int i = 1; i < 200; ++i) {
    const double r = adaptive_position_variance(1e-4 * i, p, nullptr);
    EXPECT_GE(r, prev);
    prev = r;
  }
}

Measurement mbe(double x, double y, double a, double b, double theta) {
  Measurement z;
  z.x = x;
  z.y = y;
  z.a = a;
  z.b = b;
  z.theta = theta;
  return z;
}

// An elongated ellipse lying along +-pi/2 whose measured orientation jitters
// across the wrap: the estimate must stay near +-pi/2, never drift towards 0.
TEST(Filter, OrientationIsPiPeriodicAcrossTheWrap) {
  const PredictorParams params = testing::default_params();
  std::mt19937 rng(11);
  std::normal_distribution<double> jitter(0.0, 0.05);
  TrackFilter f(params, mbe(0, 0, 0.8, 0.2, kPi / 2 - 0.01));
  for (int i = 0; i < 60; ++i) {
    const double measured = wrap_half_pi(kPi / 2 + jitter(rng));
    f.predict(0.1);
    f.update(mbe(0, 0, 0.8, 0.2, measured));
    const double err = wrap_half_pi(f.state()(kTheta) - kPi / 2);
    EXPECT_LT(std::fabs(err), 0.1) << "frame " << i << " theta " << f.state()(kTheta);
    EXPECT_GE(f.state()(kTheta), -kPi / 2);
    EXPECT_LT(f.state()(kTheta), kPi / 2);
  }
}

// A near-circle whose MBE flips between (a, b, theta) and (b, a, theta + pi/2):
// the same ellipse, so the shape estimate must not jump and Xi_eta stays small.
TEST(Filter, AxisSwapOfTheSameEllipseIsNotAShapeChange) {
  const PredictorParams params = testing::default_params();
  TrackFilter f(params, mbe(1, 2, 0.41, 0.39, 0.2));
  for (int i = 0; i < 30; ++i) {
    f.predict(0.1);
    const UpdateInfo info =
        (i % 2) ? f.update(mbe(1, 2, 0.41, 0.39, 0.2)) : f.update(mbe(1, 2, 0.39, 0.41, 0.2 - kPi / 2));
    EXPECT_EQ(info.swapped_axes, i % 2 == 0);
    EXPECT_LT(info.xi_eta, 1e-6);
    EXPECT_NEAR(f.state()(kA), 0.41, 1e-3);
    EXPECT_NEAR(f.state()(kB), 0.39, 1e-3);
  }
}

// Own Xi_eta is the paper's sample variance over the window: known answer.
TEST(Filter, OwnShapeVariationKnownAnswer) {
  PredictorParams params = testing::default_params();
  params.adaptive_noise.window_frames = 4;
  TrackFilter f(params, mbe(0, 0, 1.0, 0.5, 0.0));
  // window after 3 updates: a = 1.0, 1.2, 1.0, 1.2 (b, theta constant)
  for (double a : {1.2, 1.0, 1.2}) {
    f.predict(0.1);
    f.update(mbe(0, 0, a, 0.5, 0.0));
  }
  // mean 1.1, sum of squares 4 * 0.01, divided by m - 1 = 3
  EXPECT_NEAR(f.own_shape_variation(), 0.04 / 3.0, 1e-12);
  // ring buffer: two more frames at a = 1.0 replace the two oldest (1.0, 1.2)
  for (int i = 0; i < 2; ++i) {
    f.predict(0.1);
    f.update(mbe(0, 0, 1.0, 0.5, 0.0));
  }
  // window 1.0, 1.2, 1.0, 1.0 -> mean 1.05, squares 3*0.0025 + 0.0225 = 0.03
  EXPECT_NEAR(f.own_shape_variation(), 0.03 / 3.0, 1e-12);
}

TEST(Filter, NewTrackStartsAtRestWithWideVelocityCovariance) {
  const PredictorParams params = testing::default_params();
  TrackFilter f(params, mbe(3, 4, 0.5, 0.3, 0.1));
  EXPECT_EQ(f.state()(kVx), 0.0);
  EXPECT_EQ(f.state()(kVy), 0.0);
  // the moving modes start with the wide velocity covariance, the
  // stationary mode (its prior share) with none: the mix holds the rest
  ASSERT_GT(f.stationary_probability(), 0.0);
  EXPECT_NEAR(f.covariance()(kVx, kVx),
              (1.0 - f.stationary_probability()) * std::pow(params.filter.init_speed_std_mps, 2), 1e-12);
  EXPECT_NEAR(f.state()(kX), 3.0, 1e-15);
  PredictorParams moving_only = params;
  moving_only.stationary.enabled = false;
  TrackFilter g(moving_only, mbe(3, 4, 0.5, 0.3, 0.1));
  EXPECT_EQ(g.stationary_probability(), 0.0);
  EXPECT_NEAR(g.covariance()(kVx, kVx), std::pow(params.filter.init_speed_std_mps, 2), 1e-12);
}

}  // namespace
}  // namespace evade::prediction

namespace evade::prediction {
namespace {

// IMM: a steady target settles in the quiet mode; a sudden change of velocity
// moves the probability to the manoeuvring mode within a few frames.
TEST(Filter, ManeuverProbabilityRisesOnlyWhenTheMotionChanges) {
  const PredictorParams params = testing::default_params();
  ASSERT_TRUE(params.maneuver.enabled);
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.03);
  Measurement z;
  z.a = 0.4;
  z.b = 0.3;
  z.theta = 0.1;
  TrackFilter f(params, z);
  double x = 0, y = 0;
  for (int i = 1; i <= 40; ++i) {  // 4 s straight at 1 m/s
    x += 0.1;
    z.x = x + noise(rng);
    z.y = y + noise(rng);
    f.predict(0.1);
    f.update(z);
  }
  EXPECT_LT(f.maneuver_probability(), 0.1);
  double peak = 0;
  for (int i = 1; i <= 5; ++i) {  // abrupt turn to +y at 1 m/s
    y += 0.1;
    z.x = x + noise(rng);
    z.y = y + noise(rng);
    f.predict(0.1);
    peak = std::max(peak, f.update(z).maneuver_probability);
  }
  EXPECT_GT(peak, 0.5);
  // the prediction's Q is the probability-weighted mix of the models the
  // modes run: its velocity noise lies between the quiet (white jerk) and
  // the manoeuvring (cv: white acceleration) mode's
  const double q_vel = f.prediction_noise(0.1)(kVx, kVx);
  EXPECT_GT(q_vel, process_noise(params.filter, 0.1, params.filter.jerk_psd_m2ps5)(kVx, kVx));
  EXPECT_LT(q_vel, process_noise_cv(params.filter, 0.1, params.maneuver.accel_psd_m2ps3)(kVx, kVx));
  EXPECT_GT(q_vel, 0.2 * process_noise_cv(params.filter, 0.1, params.maneuver.accel_psd_m2ps3)(kVx, kVx));
}

TEST(Filter, SingleFilterWhenTheImmIsOff) {
  PredictorParams params = testing::default_params();
  params.maneuver.enabled = false;
  Measurement z;
  z.a = 0.4;
  z.b = 0.3;
  TrackFilter f(params, z);
  for (int i = 1; i <= 10; ++i) {
    z.x = 0.2 * i;
    f.predict(0.1);
    EXPECT_EQ(f.update(z).maneuver_probability, 0.0);
  }
  EXPECT_TRUE(f.prediction_noise(0.1).isApprox(process_noise(params.filter, 0.1, params.filter.jerk_psd_m2ps5)));
}

}  // namespace
}  // namespace evade::prediction

namespace evade::prediction {
namespace {

// Feeds a filter one MBE per 0.1 s frame with centre noise of 3 cm.
struct Feed {
  explicit Feed(const PredictorParams& params, double x, double y) : rng(11), f(params, at(x, y)) {}
  Measurement at(double x, double y) {
    Measurement z;
    z.x = x + noise(rng);
    z.y = y + noise(rng);
    z.a = 0.4;
    z.b = 0.3;
    return z;
  }
  void step(double x, double y) {
    f.predict(0.1);
    f.update(at(x, y));
  }
  double speed() const { return std::hypot(f.state()(kVx), f.state()(kVy)); }
  std::mt19937 rng;
  std::normal_distribution<double> noise{0.0, 0.03};
  TrackFilter f;
};

// A bin seen while the robot drives past: its MBE centre jumps 0.15 m when
// another face comes into view, then stays. The moving modes read the jump
// as motion and the quiet one holds on to it; the stationary mode predicts
// the frames after it and takes the probability back, so the bin is not
// predicted to roll away.
TEST(Filter, StandingObjectWhoseCentreJumpsIsPredictedStanding) {
  PredictorParams with = testing::default_params();
  ASSERT_TRUE(with.stationary.enabled);
  PredictorParams without = with;
  without.stationary.enabled = false;
  double speed_after[2], stationary_after = 0;
  int i = 0;
  for (const PredictorParams* p : {&with, &without}) {
    Feed s(*p, 2.0, 1.0);
    for (int k = 0; k < 30; ++k) s.step(2.0, 1.0);
    for (int k = 0; k < 10; ++k) s.step(2.15, 1.0);  // the jump, then 1 s standing there
    speed_after[i++] = s.speed();
    if (p == &with) stationary_after = s.f.stationary_probability();
  }
  EXPECT_GT(stationary_after, 0.5);
  EXPECT_LT(speed_after[0], 0.05);
  EXPECT_GT(speed_after[1], 2 * speed_after[0]);  // what the mode changes
}

// A pedestrian waiting at a kerb for 3 s, then walking at 1.2 m/s: within
// 0.5 s the stationary mode has let go and within 1 s the velocity is known.
TEST(Filter, AStartFromRestIsFollowed) {
  const PredictorParams params = testing::default_params();
  Feed s(params, 0.0, 0.0);
  for (int k = 0; k < 30; ++k) s.step(0.0, 0.0);
  EXPECT_GT(s.f.stationary_probability(), 0.9);
  double y = 0;
  for (int k = 0; k < 5; ++k) s.step(0.0, y += 0.12);
  EXPECT_LT(s.f.stationary_probability(), 0.1);
  for (int k = 0; k < 5; ++k) s.step(0.0, y += 0.12);
  EXPECT_NEAR(s.f.state()(kVy), 1.2, 0.3);
  EXPECT_NEAR(s.f.state()(kVx), 0.0, 0.2);
}

// Walking at 1 m/s, then stopping: one second later the track stands.
TEST(Filter, AStopIsTakenForStanding) {
  const PredictorParams params = testing::default_params();
  Feed s(params, 0.0, 0.0);
  double x = 0;
  for (int k = 0; k < 40; ++k) s.step(x += 0.1, 0.0);
  EXPECT_LT(s.f.stationary_probability(), 0.01);
  EXPECT_NEAR(s.f.state()(kVx), 1.0, 0.15);
  for (int k = 0; k < 10; ++k) s.step(x, 0.0);
  EXPECT_GT(s.f.stationary_probability(), 0.5);
  EXPECT_LT(s.speed(), 0.2);
}

// An e-bike first seen at 1.8 m/s: the stationary prior of a new track is
// gone within three frames and the speed is learnt as fast as without it.
TEST(Filter, AFastMoverFirstSeenIsNotHeldStill) {
  PredictorParams with = testing::default_params();
  PredictorParams without = with;
  without.stationary.enabled = false;
  double vx[2];
  int i = 0;
  for (const PredictorParams* p : {&with, &without}) {
    Feed s(*p, 5.0, 0.4);
    double x = 5.0;
    for (int k = 0; k < 3; ++k) s.step(x -= 0.18, 0.4);
    if (p == &with) {
      EXPECT_LT(s.f.stationary_probability(), 0.05);
    }
    for (int k = 0; k < 2; ++k) s.step(x -= 0.18, 0.4);
    vx[i++] = s.f.state()(kVx);
  }
  EXPECT_NEAR(vx[0], -1.8, 0.4);
  EXPECT_NEAR(vx[0], vx[1], 0.1);
}

// The ends of an elongated MBE: what they share is motion, the rest is a
// change of what is seen.
TEST(Aperture, ShiftIsWhatTheEndsDoNotShare) {
  const Measurement before = mbe(0.0, 0.0, 1.0, 0.1, 0.0);
  // one end stays at x = -1, the other retreats from 1 to 0.6
  Eigen::Vector2d s = aperture_shift(before, mbe(-0.2, 0.0, 0.8, 0.1, 0.0), 2.0, 0.0);
  EXPECT_NEAR(s.x(), -0.2, 1e-12);
  EXPECT_NEAR(s.y(), 0.0, 1e-12);
  // the same, reported as (b, a, theta + pi/2)
  s = aperture_shift(before, mbe(-0.2, 0.0, 0.1, 0.8, 0.5 * kPi), 2.0, 0.0);
  EXPECT_NEAR(s.x(), -0.2, 1e-12);
  EXPECT_NEAR(s.y(), 0.0, 1e-12);
  // a rigid move of 0.3 along the axis, and one across it: all motion
  EXPECT_NEAR(aperture_shift(before, mbe(0.3, 0.0, 1.0, 0.1, 0.0), 2.0, 0.0).norm(), 0.0, 1e-12);
  EXPECT_NEAR(aperture_shift(before, mbe(0.0, 0.3, 1.0, 0.1, 0.0), 2.0, 0.0).norm(), 0.0, 1e-12);
  // moved 0.3 while 0.1 more came into view at the front: of the centre's
  // 0.35, 0.3 is motion
  EXPECT_NEAR(aperture_shift(before, mbe(0.35, 0.0, 1.05, 0.1, 0.0), 2.0, 0.0).x(), 0.05, 1e-12);
  // a round MBE, or the rule off: nothing
  EXPECT_EQ(aperture_shift(mbe(0, 0, 0.3, 0.25, 0), mbe(0.2, 0, 0.3, 0.2, 0), 2.0, 0.0).norm(), 0.0);
  EXPECT_EQ(aperture_shift(before, mbe(-0.2, 0.0, 0.8, 0.1, 0.0), 0.0, 0.0).norm(), 0.0);
  // a change of the half-extent within the jitter is no change: of 0.2 less
  // 0.05, 0.15 is a change of what is seen, 0.05 motion
  EXPECT_NEAR(aperture_shift(before, mbe(-0.2, 0.0, 0.8, 0.1, 0.0), 2.0, 0.05).x(), -0.15, 1e-12);
}

// A 1.5 m piece of wall (as the tracker tiles one) whose far end a passer-by's
// shadow sweeps over and back within 1.7 s: the seen part shrinks to 0.3 m
// and grows again, its centre sliding 0.6 m along the wall and back. Without
// the rule it is published as a mover; with it it stands.
TEST(Filter, AWallSeenInPartIsNotAMover) {
  PredictorParams with = testing::default_params();
  with.filter.aperture_min_elongation = 2.0;
  with.filter.aperture_axis_noise_m = 0.05;
  PredictorParams without = with;
  without.filter.aperture_min_elongation = 0.0;
  std::vector<double> seen;  // length of the seen part, frame by frame
  for (int k = 0; k < 20; ++k) seen.push_back(1.5);
  for (int k = 1; k <= 6; ++k) seen.push_back(1.5 - 0.2 * k);
  for (int k = 0; k < 5; ++k) seen.push_back(0.3);
  for (int k = 1; k <= 6; ++k) seen.push_back(0.3 + 0.2 * k);
  for (int k = 0; k < 10; ++k) seen.push_back(1.5);
  double top[2] = {0.0, 0.0};
  int i = 0;
  for (const PredictorParams* p : {&with, &without}) {
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, 0.02);
    auto wall = [&](double length) {
      return mbe(0.5 * length + noise(rng), 1.0 + noise(rng), 0.5 * length + 0.05, 0.1, 0.0);
    };
    TrackFilter f(*p, wall(seen[0]));
    for (size_t k = 1; k < seen.size(); ++k) {
      f.predict(0.1);
      f.update(wall(seen[k]));
      top[i] = std::max(top[i], std::hypot(f.state()(kVx), f.state()(kVy)));
    }
    ++i;
  }
  EXPECT_LT(top[0], 0.15);
  EXPECT_GT(top[1], 0.3);
}

// A bike (1.8 x 0.6 m) riding along its own axis at 3 m/s, its MBE jittering
// by 3 cm: both ends move together, so the rule leaves its speed alone.
TEST(Filter, ABikeAlongItsAxisKeepsItsSpeed) {
  PredictorParams with = testing::default_params();
  with.filter.aperture_min_elongation = 2.0;
  with.filter.aperture_axis_noise_m = 0.05;
  PredictorParams without = with;
  without.filter.aperture_min_elongation = 0.0;
  double vx[2];
  int i = 0;
  for (const PredictorParams* p : {&with, &without}) {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.03);
    auto bike = [&](double x) { return mbe(x + noise(rng), 2.0 + noise(rng), 0.9 + noise(rng), 0.3, 0.0); };
    double x = 0.0;
    TrackFilter f(*p, bike(x));
    for (int k = 0; k < 20; ++k) {
      f.predict(0.1);
      f.update(bike(x += 0.3));
    }
    vx[i++] = f.state()(kVx);
  }
  EXPECT_NEAR(vx[0], 3.0, 0.3);
  EXPECT_NEAR(vx[0], vx[1], 0.2);
}

// A bike riding past at 3 m/s whose seen length grows from 0.4 to 1.6 m as
// its side comes into view (its far end lags): a mover's ends do not move
// together either, and the rule, which only the stationary mode applies,
// leaves the published velocity as it was without it.
TEST(Filter, ABikeSeenGrowingKeepsItsVelocity) {
  PredictorParams with = testing::default_params();
  with.filter.aperture_min_elongation = 2.0;
  with.filter.aperture_axis_noise_m = 0.05;
  PredictorParams without = with;
  without.filter.aperture_min_elongation = 0.0;
  double vx[2];
  int i = 0;
  for (const PredictorParams* p : {&with, &without}) {
    std::mt19937 rng(9);
    std::normal_distribution<double> noise(0.0, 0.02);
    auto seen = [&](double front, double length) {
      return mbe(front + 0.5 * length + noise(rng), 1.5 + noise(rng), 0.5 * length, 0.15, 0.0);
    };
    double front = 8.0, length = 0.4;
    TrackFilter f(*p, seen(front, length));
    for (int k = 0; k < 12; ++k) {
      f.predict(0.1);
      front -= 0.3;
      length = std::min(1.6, length + 0.2);
      f.update(seen(front, length));
    }
    vx[i++] = f.state()(kVx);
  }
  EXPECT_LT(vx[1], -1.5);
  EXPECT_NEAR(vx[0], vx[1], 0.05);
}

}  // namespace
}  // namespace evade::prediction
