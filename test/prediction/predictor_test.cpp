// The predictor end to end on synthetic MBE streams with realistic noise:
// velocity accuracy, interval jitter, 2.5 s prediction error, the adaptive
// position noise, track life cycle, output format, caps, and the bus core.
#include "prediction/predictor.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>

#include "bus/memory_bus.h"
#include "config/config.h"
#include "prediction/predictor_core.h"
#include "scenario.h"

namespace evade::prediction {
namespace {

using testing::default_params;
using testing::Frame;
using testing::make_frames;
using testing::Noise;
using testing::Truth;

struct RunStats {
  double rms_rel_speed_err = 0;  // RMS over frames with t >= t_from of |v_est - v_true| / |v_true|
  double max_rel_speed_err = 0;
  double mean_speed_err = 0;        // signed mean of |v_est| - |v_true| (bias), m/s
  double rms_pred_err_2_5s = 0;     // RMS centre error of the 2.5 s-ahead prediction, m
  double rms_pos_err = 0;           // RMS error of the index-0 centre, m
  double rms_step_jitter = 0;       // RMS of (estimated - true) centre change between frames, m
  double ls_rms_rel_speed_err = 0;  // same metric for a growing-window least-squares quadratic fit
  int samples = 0;
  int pred_samples = 0;
};

// Velocity at the last sample of an unweighted least-squares fit p(t) = c0 + c1 t + c2 t^2
// over all samples so far: the efficient estimator of the constant-acceleration model
// with no process noise and no prior, i.e. the best the paper's model can do.
double ls_quadratic_velocity(const std::vector<double>& t, const std::vector<double>& p) {
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  const double t_now = t.back();
  for (size_t i = 0; i < t.size(); ++i) {
    const double u = t[i] - t_now;  // centred on now for conditioning
    const Eigen::Vector3d phi(1.0, u, u * u);
    N += phi * phi.transpose();
    rhs += phi * p[i];
  }
  return N.ldlt().solve(rhs)(1);
}

// Runs a set of seeds through a fresh Predictor each and pools the errors over t >= t_from.
RunStats run(const PredictorParams& params, const Truth& truth, const Noise& noise, double duration_s, double t_from,
             int seeds) {
  RunStats st;
  double sum_rel2 = 0, sum_bias = 0, sum_pred2 = 0, sum_pos2 = 0, sum_ls2 = 0, sum_step2 = 0;
  const double horizon_s = params.prediction_steps * params.prediction_dt_s;
  for (int seed = 1; seed <= seeds; ++seed) {
    Predictor p(params);
    const auto frames = make_frames(truth, noise, duration_s, static_cast<uint32_t>(seed));
    std::vector<double> ts, xs, ys;
    double prev_ex = 0, prev_ey = 0;
    bool have_prev = false;
    for (const Frame& f : frames) {
      ts.push_back(f.t);
      xs.push_back(f.msg.obstacles[0].x);
      ys.push_back(f.msg.obstacles[0].y);
      evade::prediction_list_t out;
      FrameStats fs;
      EXPECT_TRUE(p.process(f.msg, &out, &fs));
      EXPECT_EQ(out.num_tracks, 1);
      if (f.t < t_from || out.num_tracks != 1) continue;
      const auto& tr = out.tracks[0];
      const double tvx = truth.vx + truth.ax * f.t, tvy = truth.vy + truth.ay * f.t;
      const double rel = std::hypot(tr.vx - tvx, tr.vy - tvy) / std::hypot(tvx, tvy);
      sum_rel2 += rel * rel;
      const double ls_rel =
          std::hypot(ls_quadratic_velocity(ts, xs) - tvx, ls_quadratic_velocity(ts, ys) - tvy) / std::hypot(tvx, tvy);
      sum_ls2 += ls_rel * ls_rel;
      st.max_rel_speed_err = std::max(st.max_rel_speed_err, rel);
      sum_bias += std::hypot(tr.vx, tr.vy) - std::hypot(tvx, tvy);
      sum_pos2 += std::pow(tr.x[0] - truth.x(f.t), 2) + std::pow(tr.y[0] - truth.y(f.t), 2);
      const double ex = tr.x[0] - truth.x(f.t), ey = tr.y[0] - truth.y(f.t);
      if (have_prev) sum_step2 += std::pow(ex - prev_ex, 2) + std::pow(ey - prev_ey, 2);
      prev_ex = ex;
      prev_ey = ey;
      have_prev = true;
      ++st.samples;
      if (f.t + horizon_s <= duration_s) {
        const int last = tr.horizon - 1;
        sum_pred2 +=
            std::pow(tr.x[last] - truth.x(f.t + horizon_s), 2) + std::pow(tr.y[last] - truth.y(f.t + horizon_s), 2);
        ++st.pred_samples;
      }
    }
  }
  st.rms_rel_speed_err = std::sqrt(sum_rel2 / st.samples);
  st.ls_rms_rel_speed_err = std::sqrt(sum_ls2 / st.samples);
  st.mean_speed_err = sum_bias / st.samples;
  st.rms_pos_err = std::sqrt(sum_pos2 / st.samples);
  st.rms_step_jitter = std::sqrt(sum_step2 / (st.samples - seeds));
  st.rms_pred_err_2_5s = st.pred_samples ? std::sqrt(sum_pred2 / st.pred_samples) : 0.0;
  return st;
}

void report(const char* name, const RunStats& s) {
  std::printf(
      "[figures] %-34s velocity err RMS %.2f%% max %.2f%% (LS quadratic bound %.2f%%) speed bias %+.4f m/s | "
      "centre RMS %.3f m | 2.5 s prediction RMS %.3f m (%d samples)\n",
      name, 100 * s.rms_rel_speed_err, 100 * s.max_rel_speed_err, 100 * s.ls_rms_rel_speed_err, s.mean_speed_err,
      s.rms_pos_err, s.rms_pred_err_2_5s, s.pred_samples);
}

constexpr int kSeeds = 30;

Noise mbe_noise() {
  Noise n;
  n.centre_std_m = 0.04;  // 4 cm white centre noise
  n.axis_std_m = 0.03;    // 3 cm semi-axis jitter
  n.theta_std_rad = 0.05;
  n.coupled_shift = 0.5;  // and the centre shift that jitter causes
  return n;
}

// With the MBE noise (4 cm centre + 3 cm axis jitter dragging the
// centre) the paper's constant-acceleration model cannot reach 2 % at 1.2 m/s:
// even the least-squares quadratic fit over every frame (its information
// limit) is at ~2.5 %. The filter must come close to that limit (within 35 %:
// the manoeuvring IMM mode costs some steady-state accuracy, see the turn
// test for what it buys), be unbiased, and predict 2.5 s ahead within a quarter metre.
TEST(Predictor, ConstantVelocityTargetNearTheModelsInformationLimit) {
  Truth truth;
  truth.vx = 1.2 * std::cos(0.5);
  truth.vy = 1.2 * std::sin(0.5);
  const RunStats s = run(default_params(), truth, mbe_noise(), 10.0, 2.0, kSeeds);
  report("CV 1.2 m/s, 4 cm noise", s);
  EXPECT_LT(s.rms_rel_speed_err, 1.35 * s.ls_rms_rel_speed_err);
  EXPECT_LT(std::fabs(s.mean_speed_err), 0.005 * 1.2);
  EXPECT_LT(s.rms_pred_err_2_5s, 0.25);
}

TEST(Predictor, ConstantAccelerationTargetNearTheModelsInformationLimit) {
  Truth truth;
  truth.vx = 0.6;
  truth.vy = -0.3;
  truth.ax = 0.25;
  truth.ay = 0.1;
  const RunStats s = run(default_params(), truth, mbe_noise(), 8.0, 2.0, kSeeds);
  report("CA 0.27 m/s^2 from 0.67 m/s, 4 cm", s);
  EXPECT_LT(s.rms_rel_speed_err, 1.35 * s.ls_rms_rel_speed_err);
  EXPECT_LT(std::fabs(s.mean_speed_err), 0.01);
  EXPECT_LT(s.rms_pred_err_2_5s, 0.3);
}

// The criterion, velocity error under 2 % after 2 s, at the low end of
// the realistic noise range (3 cm centre, 2 cm axis jitter) for a pedestrian
// at 1.5 m/s and an accelerating cyclist.
Noise low_mbe_noise() {
  Noise n = mbe_noise();
  n.centre_std_m = 0.03;
  n.axis_std_m = 0.02;
  return n;
}

TEST(Predictor, VelocityErrorUnder2PercentAfter2sAt3cmNoise) {
  Truth walker;
  walker.vx = 1.5 * std::cos(2.0);
  walker.vy = 1.5 * std::sin(2.0);
  const RunStats cv = run(default_params(), walker, low_mbe_noise(), 10.0, 2.0, kSeeds);
  report("CV 1.5 m/s, 3 cm noise", cv);
  EXPECT_LT(cv.rms_rel_speed_err, 0.02);
  Truth cyclist;
  cyclist.vx = 1.2;
  cyclist.vy = 0.4;
  cyclist.ax = 0.2;
  const RunStats ca = run(default_params(), cyclist, low_mbe_noise(), 8.0, 2.0, kSeeds);
  report("CA 0.2 m/s^2 from 1.26 m/s, 3 cm", ca);
  EXPECT_LT(ca.rms_rel_speed_err, 0.02);
}

TEST(Predictor, JitteredFrameIntervalsDoNotBiasSpeed) {
  Truth truth;
  truth.vx = 1.5;
  Noise jittered = mbe_noise();
  jittered.min_interval_s = 0.05;
  jittered.max_interval_s = 0.15;
  const PredictorParams params = default_params();
  const RunStats regular = run(params, truth, mbe_noise(), 10.0, 2.0, kSeeds);
  const RunStats irregular = run(params, truth, jittered, 10.0, 2.0, kSeeds);
  report("1.5 m/s, 0.1 s frames", regular);
  report("1.5 m/s, 0.05-0.15 s frames", irregular);
  // Bias well under 1 % of the speed, and no worse accuracy than with regular frames.
  EXPECT_LT(std::fabs(irregular.mean_speed_err), 0.005 * 1.5);
  EXPECT_LT(irregular.rms_rel_speed_err, 1.2 * regular.rms_rel_speed_err);
  EXPECT_LT(std::fabs(irregular.rms_pred_err_2_5s - regular.rms_pred_err_2_5s), 0.1 * regular.rms_pred_err_2_5s);
}

// The paper's point: a jittering MBE shape shifts the MBE centre; raising R_p
// with the shape variation damps that position jitter. Same frames, adaptive
// R_p versus R_p pinned at R_p,min.
TEST(Predictor, JitteringShapeDampsPositionJitter) {
  Truth truth;
  truth.vx = 0.8;
  Noise noise;
  noise.centre_std_m = 0.02;
  noise.axis_std_m = 0.15;    // a badly jittering major axis ...
  noise.coupled_shift = 0.5;  // ... that drags the centre by half of it
  const PredictorParams adaptive = default_params();
  PredictorParams fixed = adaptive;
  fixed.adaptive_noise.r_pos_max_m2 = fixed.adaptive_noise.r_pos_min_m2;
  const RunStats a = run(adaptive, truth, noise, 8.0, 2.0, kSeeds);
  const RunStats f = run(fixed, truth, noise, 8.0, 2.0, kSeeds);
  report("shape jitter, adaptive R_p", a);
  report("shape jitter, fixed R_p", f);
  std::printf("[figures] shape jitter: frame-to-frame centre jitter adaptive %.4f m, fixed %.4f m\n", a.rms_step_jitter,
              f.rms_step_jitter);
  EXPECT_LT(a.rms_step_jitter, 0.75 * f.rms_step_jitter);
  EXPECT_LT(a.rms_pos_err, f.rms_pos_err);
  EXPECT_LT(a.rms_rel_speed_err, 0.8 * f.rms_rel_speed_err);

  // And the mechanism: R_p rises with the shape variation.
  Predictor p(adaptive);
  const auto frames = make_frames(truth, noise, 3.0, 5);
  for (const auto& fr : frames) {
    evade::prediction_list_t out;
    p.process(fr.msg, &out, nullptr);
  }
  const TrackFilter* tf = p.track(7);
  ASSERT_NE(tf, nullptr);
  double k = 0;
  adaptive_position_variance(tf->own_shape_variation(), adaptive.adaptive_noise, &k);
  EXPECT_GT(k, 0.3);
}

// A new track starts at rest with a wide velocity covariance: its early
// speed is well below the spike a two-point initialisation would produce.
TEST(Predictor, StationaryNewTrackHasNoVelocitySpike) {
  Truth truth;  // at rest
  const PredictorParams params = default_params();
  double filter2 = 0, naive2 = 0, filter_max = 0, naive_max = 0;
  int n = 0;
  for (uint32_t seed = 1; seed <= 30; ++seed) {
    Predictor p(params);
    const auto frames = make_frames(truth, mbe_noise(), 1.0, seed);
    for (size_t i = 0; i < frames.size(); ++i) {
      evade::prediction_list_t out;
      ASSERT_TRUE(p.process(frames[i].msg, &out, nullptr));
      const double v = std::hypot(out.tracks[0].vx, out.tracks[0].vy);
      if (i == 0) {
        EXPECT_EQ(v, 0.0);
        continue;
      }
      const auto& o0 = frames[i - 1].msg.obstacles[0];
      const auto& o1 = frames[i].msg.obstacles[0];
      const double naive = std::hypot(o1.x - o0.x, o1.y - o0.y) / (frames[i].t - frames[i - 1].t);
      filter2 += v * v;
      naive2 += naive * naive;
      filter_max = std::max(filter_max, v);
      naive_max = std::max(naive_max, naive);
      ++n;
    }
  }
  std::printf(
      "[figures] stationary new track, first 1 s: speed RMS %.3f m/s (max %.3f), two-point differences RMS %.3f m/s "
      "(max %.3f)\n",
      std::sqrt(filter2 / n), filter_max, std::sqrt(naive2 / n), naive_max);
  EXPECT_LT(std::sqrt(filter2 / n), 0.4 * std::sqrt(naive2 / n));
  EXPECT_LT(filter_max, 0.6 * naive_max);
}

evade::obstacle_t ob(int64_t id, double x, double y) {
  evade::obstacle_t o{};
  o.id = id;
  o.x = x;
  o.y = y;
  o.a = 0.4;
  o.b = 0.3;
  o.theta = 0.1;
  return o;
}

evade::obstacle_list_t list(int64_t utime, std::vector<evade::obstacle_t> obs) {
  evade::obstacle_list_t l;
  l.utime = utime;
  l.obstacles = std::move(obs);
  l.num_obstacles = static_cast<int32_t>(l.obstacles.size());
  return l;
}

// A pedestrian walking at 1.2 m/s turns by 90 degrees in 1 s (4 s to 5 s).
// The low jerk noise that gives accurate steady velocities makes the paper's
// single filter slow to follow a turn; the two-mode IMM follows it.
struct TurnErrors {
  double during, after1, after2;  // velocity error RMS, m/s: turn + 1 s, 1-3 s after, 3-5 s after
};

TurnErrors turn_errors(const PredictorParams& params) {
  const double kPi = 3.14159265358979323846;
  const double v = 1.2, t_turn = 4.0, turn_s = 1.0, radius = v * turn_s / (kPi / 2);
  auto truth = [&](double t, double* x, double* y, double* vx, double* vy) {
    if (t < t_turn) {
      *x = v * t;
      *y = 0;
      *vx = v;
      *vy = 0;
    } else if (t < t_turn + turn_s) {
      const double ph = (t - t_turn) / turn_s * (kPi / 2);
      *x = v * t_turn + radius * std::sin(ph);
      *y = radius * (1 - std::cos(ph));
      *vx = v * std::cos(ph);
      *vy = v * std::sin(ph);
    } else {
      *x = v * t_turn + radius;
      *y = radius + v * (t - t_turn - turn_s);
      *vx = 0;
      *vy = v;
    }
  };
  double e[3] = {0, 0, 0};
  int n[3] = {0, 0, 0};
  for (uint32_t seed = 1; seed <= kSeeds; ++seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01;
    Predictor p(params);
    for (int i = 0; i <= 100; ++i) {
      const double t = 0.1 * i;
      double x, y, vx, vy;
      truth(t, &x, &y, &vx, &vy);
      const evade::obstacle_t o = ob(1, x + 0.04 * n01(rng), y + 0.04 * n01(rng));
      evade::prediction_list_t out;
      EXPECT_TRUE(p.process(list(1'000'000 + i * 100'000, {o}), &out, nullptr));
      const double e2 = std::pow(out.tracks[0].vx - vx, 2) + std::pow(out.tracks[0].vy - vy, 2);
      const int bin = t < t_turn ? -1 : t < t_turn + turn_s + 1.0 ? 0 : t < t_turn + turn_s + 3.0 ? 1 : 2;
      if (bin >= 0) {
        e[bin] += e2;
        ++n[bin];
      }
    }
  }
  return {std::sqrt(e[0] / n[0]), std::sqrt(e[1] / n[1]), std::sqrt(e[2] / n[2])};
}

TEST(Predictor, TurnIsFollowedWithinAFewSeconds) {
  PredictorParams single = default_params();
  single.maneuver.enabled = false;
  const TurnErrors imm = turn_errors(default_params());
  const TurnErrors one = turn_errors(single);
  std::printf(
      "[figures] 90 deg turn at 1.2 m/s, velocity error RMS (turn + 1 s | 1-3 s after | 3-5 s after): "
      "IMM %.3f | %.3f | %.3f m/s, single filter %.3f | %.3f | %.3f m/s\n",
      imm.during, imm.after1, imm.after2, one.during, one.after1, one.after2);
  EXPECT_LT(imm.after1, 0.5 * one.after1);
  EXPECT_LT(imm.after1, 0.25);
  EXPECT_LT(imm.after2, 0.1);
}

// A walker at 1 m/s turns a corner at once (-x, then +y; mixed_street's
// loop walker). With a constant-acceleration manoeuvring mode the
// acceleration learnt in the turn outlived it: 1 s after the corner the
// estimate was about (0.44, 1.44) m/s, its predicted path cutting across
// the corner, towards a robot waiting beside it. The constant-velocity
// manoeuvring mode follows the new heading without that overshoot.
TEST(Predictor, ACornerTurnedAtOnceIsNotOvershot) {
  auto error_after_corner = [](const std::string& model) {
    PredictorParams params = default_params();
    params.maneuver.model = model;
    double worst = 0;  // largest mean velocity error from 0.5 s to 2 s after the corner
    const int seeds = 20;
    std::vector<double> ex(16, 0.0), ey(16, 0.0);
    for (int seed = 0; seed < seeds; ++seed) {
      Predictor p(params);
      std::mt19937 rng(static_cast<uint32_t>(seed));
      std::normal_distribution<double> noise(0.0, 0.03);
      evade::prediction_list_t out;
      FrameStats st;
      for (int i = 0; i <= 70; ++i) {
        const double t = 0.1 * i;
        const bool turned = t > 5.0 + 1e-9;
        evade::obstacle_t o = ob(1, (turned ? -5.0 : -t) + noise(rng), (turned ? -2.0 + (t - 5.0) : -2.0) + noise(rng));
        EXPECT_TRUE(p.process(list(1'000'000 + i * 100'000, {o}), &out, &st));
        const int after = i - 50;  // frames after the corner
        if (after >= 5 && after <= 20) {
          ex[static_cast<size_t>(after - 5)] += out.tracks[0].vx / seeds;
          ey[static_cast<size_t>(after - 5)] += (out.tracks[0].vy - 1.0) / seeds;
        }
      }
    }
    for (size_t k = 0; k < ex.size(); ++k) worst = std::max(worst, std::hypot(ex[k], ey[k]));
    return worst;
  };
  const double cv = error_after_corner("cv"), ca = error_after_corner("ca");
  std::printf(
      "[figures] 1 m/s walker turning a corner at once: largest mean velocity error 0.5-2 s after it, "
      "manoeuvring mode cv %.3f m/s, ca %.3f m/s\n",
      cv, ca);
  EXPECT_LT(cv, 0.15);
  EXPECT_GT(ca, 0.4);  // the overshoot this is about
}

TEST(Predictor, MissingTracksCoastThenAreDropped) {
  PredictorParams params = default_params();
  params.coast_max_s = 0.25;
  params.coast_min_frames = 3;
  Predictor p(params);
  evade::prediction_list_t out;
  FrameStats st;
  ASSERT_TRUE(p.process(list(800'000, {ob(1, 0, 0), ob(2, 5, 5)}), &out, &st));
  EXPECT_EQ(st.created, 2);
  ASSERT_TRUE(p.process(list(900'000, {ob(1, 0, 0), ob(2, 5, 5)}), &out, &st));
  ASSERT_TRUE(p.process(list(1'000'000, {ob(1, 0, 0), ob(2, 5, 5)}), &out, &st));
  EXPECT_EQ(p.num_tracks(), 2u);
  // id 1 missing: still predicted and published, after the measured ones
  ASSERT_TRUE(p.process(list(1'100'000, {ob(2, 5.1, 5)}), &out, &st));
  EXPECT_EQ(st.updated, 1);
  EXPECT_EQ(st.coasting, 1);
  EXPECT_EQ(st.dropped, 0);
  ASSERT_EQ(out.num_tracks, 2);
  EXPECT_EQ(out.tracks[0].id, 2);
  EXPECT_EQ(out.tracks[1].id, 1);
  // both missing; id 1 unseen 0.3 s > coast_max_s: dropped; id 2 unseen 0.2 s: coasts
  ASSERT_TRUE(p.process(list(1'300'000, {}), &out, &st));
  EXPECT_EQ(st.dropped, 1);
  EXPECT_EQ(st.coasting, 1);
  EXPECT_EQ(p.track(1), nullptr);
  ASSERT_EQ(out.num_tracks, 1);
  EXPECT_EQ(out.tracks[0].id, 2);
  ASSERT_TRUE(p.process(list(1'400'000, {}), &out, &st));
  EXPECT_EQ(p.num_tracks(), 0u);
  EXPECT_EQ(out.num_tracks, 0);
}

// A cluster split off a mover for one frame gets a new id and vanishes
// again. Coasted, it would be a static ellipse inflated to the cap (its
// velocity unknown) sitting in the robot's way for coast_max_s; seen in
// fewer than coast_min_frames frames, it is dropped at its first miss.
TEST(Predictor, AShortLivedTrackIsNotCoasted) {
  PredictorParams params = default_params();
  params.coast_max_s = 0.5;
  params.coast_min_frames = 3;
  Predictor p(params);
  evade::prediction_list_t out;
  FrameStats st;
  ASSERT_TRUE(p.process(list(1'000'000, {ob(1, 0, 0)}), &out, &st));
  ASSERT_TRUE(p.process(list(1'100'000, {ob(1, 0, 0), ob(9, 2, 2)}), &out, &st));
  EXPECT_EQ(out.num_tracks, 2);
  ASSERT_TRUE(p.process(list(1'200'000, {ob(1, 0, 0)}), &out, &st));
  EXPECT_EQ(st.coasting, 0);
  EXPECT_EQ(st.dropped, 1);
  EXPECT_EQ(p.track(9), nullptr);
  ASSERT_EQ(out.num_tracks, 1);
  EXPECT_EQ(out.tracks[0].id, 1);
  // with coast_min_frames 1 the same track coasts
  params.coast_min_frames = 1;
  Predictor q(params);
  ASSERT_TRUE(q.process(list(1'100'000, {ob(1, 0, 0), ob(9, 2, 2)}), &out, &st));
  ASSERT_TRUE(q.process(list(1'200'000, {ob(1, 0, 0)}), &out, &st));
  EXPECT_EQ(st.coasting, 1);
  EXPECT_EQ(out.num_tracks, 2);
}

TEST(Predictor, CoastMaxZeroDropsAtTheFirstMiss) {
  PredictorParams params = default_params();
  params.coast_max_s = 0.0;
  Predictor p(params);
  evade::prediction_list_t out;
  FrameStats st;
  ASSERT_TRUE(p.process(list(1'000'000, {ob(1, 0, 0), ob(2, 5, 5)}), &out, &st));
  ASSERT_TRUE(p.process(list(1'100'000, {ob(2, 5.1, 5)}), &out, &st));
  EXPECT_EQ(st.dropped, 1);
  EXPECT_EQ(p.track(1), nullptr);
  EXPECT_EQ(out.num_tracks, 1);
}

// A walker unseen for three frames (occluded; the tracker keeps its id) and
// then seen again keeps its velocity: restarting its filter would present it
// to the planner as standing still.
TEST(Predictor, AMoverMissedForAFewFramesKeepsItsVelocity) {
  auto walk = [](double coast_max_s) {
    PredictorParams params = default_params();
    params.coast_max_s = coast_max_s;
    Predictor p(params);
    evade::prediction_list_t out;
    FrameStats st;
    const double speed = 1.2;
    double vx_while_missing = -1.0, vx_back = -1.0;
    for (int i = 0; i <= 33; ++i) {
      const int64_t t = 1'000'000 + i * 100'000;
      const bool missing = i >= 30 && i < 33;
      std::vector<evade::obstacle_t> obs;
      if (!missing) obs.push_back(ob(7, speed * 0.1 * i, 2.0));
      EXPECT_TRUE(p.process(list(t, obs), &out, &st));
      const double vx = out.num_tracks == 1 ? out.tracks[0].vx : 0.0;
      if (i == 32) vx_while_missing = vx;
      if (i == 33) vx_back = vx;
    }
    EXPECT_EQ(out.num_tracks, 1);
    return std::make_pair(vx_while_missing, vx_back);
  };
  const auto [coasting_vx, coasting_after] = walk(0.5);
  const auto [dropping_vx, dropping_after] = walk(0.0);
  std::printf(
      "[figures] walker at 1.2 m/s, 3 frames unseen: vx while unseen %.3f, when seen again %.3f m/s "
      "(dropped at the first miss: %.3f, %.3f)\n",
      coasting_vx, coasting_after, dropping_vx, dropping_after);
  EXPECT_NEAR(coasting_vx, 1.2, 0.1);
  EXPECT_NEAR(coasting_after, 1.2, 0.1);
  EXPECT_EQ(dropping_vx, 0.0);     // not published while unseen
  EXPECT_LT(dropping_after, 0.3);  // restarted at rest
}

TEST(Predictor, StaleAndMalformedInputIsSkipped) {
  Predictor p(default_params());
  evade::prediction_list_t out;
  FrameStats st;
  ASSERT_TRUE(p.process(list(1'000'000, {ob(1, 0, 0)}), &out, &st));
  EXPECT_FALSE(p.process(list(1'000'000, {ob(1, 0, 0)}), &out, &st));  // same utime
  EXPECT_FALSE(p.process(list(900'000, {ob(1, 0, 0)}), &out, &st));    // older
  auto bad = ob(3, std::numeric_limits<double>::quiet_NaN(), 0);
  auto flat = ob(4, 1, 1);
  flat.a = 0.0;
  ASSERT_TRUE(p.process(list(1'100'000, {ob(1, 0, 0), bad, flat, ob(1, 9, 9)}), &out, &st));
  EXPECT_EQ(st.malformed, 3);  // NaN, zero axis, duplicate id
  EXPECT_EQ(out.num_tracks, 1);
  EXPECT_NEAR(out.tracks[0].x[0], 0.0, 1e-9);  // the duplicate did not update the track
}

TEST(Predictor, OutOfRangeObstaclesAreMalformed) {
  const PredictorParams params = default_params();
  Predictor p(params);
  evade::prediction_list_t out;
  FrameStats st;
  auto far = ob(1, params.max_abs_coordinate_m * 2, 0);
  auto huge = ob(2, 0, 0);
  huge.a = params.max_axis_m * 2;
  ASSERT_TRUE(p.process(list(1'000'000, {far, huge, ob(3, 1, 1)}), &out, &st));
  EXPECT_EQ(st.malformed, 2);
  EXPECT_EQ(out.num_tracks, 1);
}

// Random, extreme but valid obstacle lists (jumps, flips, tiny and large
// ellipses, irregular stamps): every published number stays finite.
TEST(Predictor, RandomInputNeverPublishesNonFinite) {
  const PredictorParams params = default_params();
  Predictor p(params);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> coord(-params.max_abs_coordinate_m, params.max_abs_coordinate_m);
  std::uniform_real_distribution<double> axis(1e-6, params.max_axis_m);
  std::uniform_real_distribution<double> angle(-100, 100);
  std::uniform_int_distribution<int> ids(1, 8), count(0, 8), step_us(1, 2'000'000);
  int64_t utime = 1;
  for (int f = 0; f < 3000; ++f) {
    utime += step_us(rng);
    std::vector<evade::obstacle_t> obs;
    const int n = count(rng);
    for (int i = 0; i < n; ++i) {
      auto o = ob(ids(rng), coord(rng), coord(rng));
      if (rng() % 2) {
        o.x = 0.01 * (rng() % 100);
        o.y = 0.0;
      }  // mostly near: tracks live on
      o.a = axis(rng);
      o.b = (rng() % 3 == 0) ? 0.0 : axis(rng);
      o.theta = angle(rng);
      o.shape_variation = axis(rng);
      obs.push_back(o);
    }
    evade::prediction_list_t out;
    ASSERT_TRUE(p.process(list(utime, obs), &out, nullptr));
    for (const auto& t : out.tracks) {
      ASSERT_TRUE(std::isfinite(t.vx) && std::isfinite(t.vy) && std::isfinite(t.ax) && std::isfinite(t.ay));
      for (int k = 0; k < t.horizon; ++k) {
        ASSERT_TRUE(std::isfinite(t.x[k]) && std::isfinite(t.y[k]) && std::isfinite(t.a[k]) && std::isfinite(t.b[k]) &&
                    std::isfinite(t.theta[k]) && std::isfinite(t.sigma[k]))
            << "frame " << f << " track " << t.id << " step " << k;
        ASSERT_GE(t.b[k], 0.0);
      }
    }
  }
}

// shape_variation_source: tracker uses the message's Xi_eta instead of our own window.
TEST(Predictor, TrackerShapeVariationSource) {
  PredictorParams params = default_params();
  params.adaptive_noise.shape_variation_source = "tracker";
  TrackFilter f(params, Measurement{});
  Measurement z;
  z.a = 0.4;
  z.b = 0.3;
  z.tracker_shape_variation = 0.0123;
  f.predict(0.1);
  const UpdateInfo info = f.update(z);
  EXPECT_DOUBLE_EQ(info.xi_eta, 0.0123);
  double k = 0;
  EXPECT_DOUBLE_EQ(info.r_position, adaptive_position_variance(0.0123, params.adaptive_noise, &k));
}

TEST(Predictor, LongFrameGapRestartsTracks) {
  PredictorParams params = default_params();
  Predictor p(params);
  evade::prediction_list_t out;
  FrameStats st;
  for (int i = 0; i < 20; ++i) p.process(list(1'000'000 + i * 100'000, {ob(1, 0.1 * i, 0)}), &out, &st);
  EXPECT_GT(out.tracks[0].vx, 0.5);
  const int64_t later = 1'000'000 + 19 * 100'000 + static_cast<int64_t>((params.max_frame_gap_s + 0.5) * 1e6);
  ASSERT_TRUE(p.process(list(later, {ob(1, 5, 0)}), &out, &st));
  EXPECT_TRUE(st.gap_reset);
  EXPECT_EQ(st.created, 1);
  EXPECT_EQ(out.tracks[0].vx, 0.0);
}

// A static target (4 cm centre noise, 10 s): what its predicted ellipse
// swells by over the 2.5 s horizon is what the planner has to keep clear of
// beside a bin. The moving modes carry a velocity and acceleration
// uncertainty that the stationary mode does not, and a speed read off the
// noise.
TEST(Predictor, AStaticTargetsPredictionSwellsLessWithTheStationaryMode) {
  Truth truth;  // at rest
  PredictorParams with = default_params();
  ASSERT_TRUE(with.stationary.enabled);
  PredictorParams without = with;
  without.stationary.enabled = false;
  double growth[2] = {0, 0}, speed[2] = {0, 0};
  const int seeds = 20;
  for (int i = 0; i < 2; ++i) {
    for (uint32_t seed = 1; seed <= seeds; ++seed) {
      Predictor p(i == 0 ? with : without);
      const auto frames = make_frames(truth, mbe_noise(), 10.0, seed);
      evade::prediction_list_t out;
      for (const auto& f : frames) ASSERT_TRUE(p.process(f.msg, &out, nullptr));
      ASSERT_EQ(out.num_tracks, 1);
      growth[i] += (out.tracks[0].a.back() - out.tracks[0].a.front()) / seeds;
      speed[i] += std::hypot(out.tracks[0].vx, out.tracks[0].vy) / seeds;
    }
  }
  std::printf(
      "[figures] static target, 4 cm noise, 10 s: semi-axis growth over 2.5 s %.3f m (without the stationary "
      "mode %.3f m), speed %.4f m/s (%.4f)\n",
      growth[0], growth[1], speed[0], speed[1]);
  // The swelling is the shape random walk (r_eta) and the probability the
  // IMM keeps on a manoeuvre starting, whose white acceleration (the cv
  // mode's model, weighted by that probability) dominates either way; the
  // stationary mode removes the velocity noise of the estimate.
  EXPECT_LT(growth[0], growth[1]);
  EXPECT_GT(growth[0], 0.2);
  EXPECT_LT(speed[0], 0.2 * speed[1]);
}

TEST(Predictor, OutputFormatIndexZeroIsNowAndEllipsesGrow) {
  const PredictorParams params = default_params();
  Predictor p(params);
  Truth truth;
  truth.vx = 1.0;
  const auto frames = make_frames(truth, mbe_noise(), 3.0, 9);
  evade::prediction_list_t out;
  for (const auto& f : frames) ASSERT_TRUE(p.process(f.msg, &out, nullptr));
  EXPECT_EQ(out.utime, frames.back().msg.utime);
  EXPECT_EQ(out.horizon, params.prediction_steps + 1);
  EXPECT_DOUBLE_EQ(out.dt, params.prediction_dt_s);
  ASSERT_EQ(out.num_tracks, 1);
  const auto& tr = out.tracks[0];
  ASSERT_EQ(tr.horizon, out.horizon);
  ASSERT_EQ(static_cast<int>(tr.sigma.size()), tr.horizon);
  const TrackFilter* f = p.track(7);
  EXPECT_DOUBLE_EQ(tr.x[0], f->state()(kX));  // index 0 = the current estimate
  EXPECT_DOUBLE_EQ(tr.vx, f->state()(kVx));
  for (int k = 0; k < tr.horizon; ++k) {
    EXPECT_GE(tr.a[k], tr.b[k]);
    EXPECT_GT(tr.sigma[k], 0.0);
    EXPECT_NEAR(tr.a[k] - tr.sigma[k], std::max(f->state()(kA), params.uncertainty.min_axis_m), 1e-12);
    if (k > 0) {
      // uncertainty grows with k until the configured cap, then holds there
      if (tr.sigma[k - 1] < params.uncertainty.max_inflation_m)
        EXPECT_GT(tr.sigma[k], tr.sigma[k - 1]) << k;
      else
        EXPECT_EQ(tr.sigma[k], params.uncertainty.max_inflation_m) << k;
      EXPECT_LE(tr.sigma[k], params.uncertainty.max_inflation_m) << k;
      EXPECT_NEAR(tr.x[k] - tr.x[k - 1], params.prediction_dt_s * 1.0, 0.03);  // moving at ~1 m/s
    }
  }
  EXPECT_GT(tr.sigma.back(), 2.0 * tr.sigma.front());
}

// uncertainty.combine: the same track's published inflation is r_p + r_eta
// (sum), sqrt(r_p^2 + r_eta^2) (rss) or r_p (position), at every step below
// the cap (a walker: a circle, so sigma_min = 0 and sigma is that radius).
TEST(Predictor, InflationCombinesPositionAndShapeRadiiAsConfigured) {
  Truth truth;
  truth.vx = 1.0;
  const auto frames = make_frames(truth, mbe_noise(), 3.0, 9);
  std::map<std::string, evade::track_prediction_t> out;
  for (const std::string combine : {"sum", "rss", "position"}) {
    PredictorParams params = default_params();
    params.uncertainty.combine = combine;
    params.uncertainty.max_inflation_m = 100.0;
    Predictor p(params);
    evade::prediction_list_t list;
    for (const auto& f : frames) ASSERT_TRUE(p.process(f.msg, &list, nullptr));
    ASSERT_EQ(list.num_tracks, 1);
    out[combine] = list.tracks[0];
  }
  for (int k = 0; k < out["sum"].horizon; ++k) {
    const double sum = out["sum"].sigma[k], rss = out["rss"].sigma[k], pos = out["position"].sigma[k];
    EXPECT_LT(pos, rss) << k;
    EXPECT_LT(rss, sum) << k;
    // r_eta = sum - pos; rss^2 = pos^2 + r_eta^2 (sigma_min is 0 for a circle, within the
    // root finder's tolerance for this near-circle)
    EXPECT_NEAR(rss * rss, pos * pos + (sum - pos) * (sum - pos), 1e-3) << k;
    EXPECT_DOUBLE_EQ(out["rss"].x[k], out["sum"].x[k]);  // only the size changes
  }
}

TEST(Predictor, AccelerationAndSpeedCapsHoldInPrediction) {
  PredictorParams params = default_params();
  Predictor p(params);
  Truth truth;
  truth.ax = 3.0;  // well beyond the caps: reaches 9 m/s
  Noise quiet;
  quiet.centre_std_m = 0.01;
  const auto frames = make_frames(truth, quiet, 3.0, 2);
  evade::prediction_list_t out;
  for (const auto& f : frames) ASSERT_TRUE(p.process(f.msg, &out, nullptr));
  const auto& tr = out.tracks[0];
  EXPECT_GT(std::hypot(p.track(7)->state()(kVx), p.track(7)->state()(kVy)), params.limits.max_speed_mps);
  EXPECT_LE(std::hypot(tr.vx, tr.vy), params.limits.max_speed_mps + 1e-9);
  EXPECT_LE(std::hypot(tr.ax, tr.ay), params.limits.max_accel_mps2 + 1e-9);
  for (int k = 1; k < tr.horizon; ++k)
    EXPECT_LE(std::hypot(tr.x[k] - tr.x[k - 1], tr.y[k] - tr.y[k - 1]),
              params.limits.max_speed_mps * params.prediction_dt_s + 1e-9);
}

// Past max_accel_time_s the predicted velocity is held: a steady
// acceleration estimate bends the first part of the prediction only.
TEST(Predictor, AccelerationActsOnlyUpToItsTimeLimit) {
  PredictorParams params = default_params();
  params.limits.max_accel_time_s = 0.5;
  Predictor p(params);
  Truth truth;
  truth.ax = 1.0;
  Noise quiet;
  quiet.centre_std_m = 0.005;
  quiet.axis_std_m = 0.0;
  quiet.theta_std_rad = 0.0;
  const auto frames = make_frames(truth, quiet, 3.0, 4);
  evade::prediction_list_t out;
  for (const auto& f : frames) ASSERT_TRUE(p.process(f.msg, &out, nullptr));
  const auto& tr = out.tracks[0];
  ASSERT_GT(tr.ax, 0.5);
  const int hold = static_cast<int>(std::lround(0.5 / params.prediction_dt_s));
  const double step_before = tr.x[hold] - tr.x[hold - 1];
  const double step_after = tr.x[hold + 1] - tr.x[hold];
  const double step_last = tr.x[tr.horizon - 1] - tr.x[tr.horizon - 2];
  EXPECT_GT(step_before, tr.x[1] - tr.x[0]);  // accelerating up to the limit
  EXPECT_NEAR(step_last, step_after, 1e-9);   // constant velocity after it
  EXPECT_NEAR(step_after, step_before + 0.5 * tr.ax * params.prediction_dt_s * params.prediction_dt_s, 1e-6);
}

TEST(PredictorCore, PublishesStampedPredictionsAndCountsBadInput) {
  bus::MemoryBus bus;
  PredictorCore core(default_params());
  bus.add(core);
  bus.inject(kObstaclesChannel, list(5'000'000, {ob(1, 0, 0), ob(2, 3, 1)}), 5'010'000);
  bus.inject(kObstaclesChannel, list(5'100'000, {ob(1, 0.1, 0), ob(2, 3, 1)}), 5'110'000);
  bus.inject(kObstaclesChannel, list(5'050'000, {ob(1, 0.1, 0)}), 5'120'000);  // out of order
  bus.inject(kObstaclesChannel, list(5'150'000, {ob(1, 0.15, 0), ob(2, 3, 1)}), 5'160'000);
  auto nan = ob(2, 3, 1);
  nan.theta = std::numeric_limits<double>::infinity();
  bus.inject(kObstaclesChannel, list(5'200'000, {ob(1, 0.2, 0), nan}), 5'210'000);
  const std::vector<uint8_t> garbage = {1, 2, 3, 4, 5};
  bus.inject(kObstaclesChannel, garbage, 5'220'000);
  const auto out = bus.decoded<evade::prediction_list_t>(kPredictionsChannel);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].utime, 5'000'000);
  EXPECT_EQ(out[1].utime, 5'100'000);
  EXPECT_EQ(out[2].utime, 5'150'000);
  EXPECT_EQ(out[3].utime, 5'200'000);
  EXPECT_EQ(out[3].num_tracks, 2);  // id 2's malformed obstacle is skipped; its track (3 frames old) coasts
  EXPECT_EQ(core.counter("frames"), 4);
  EXPECT_EQ(core.counter("stale_frames"), 1);
  EXPECT_EQ(core.counter("malformed_obstacles"), 1);
  EXPECT_EQ(core.counter("tracks_created"), 2);
  EXPECT_EQ(core.counter("tracks_dropped"), 0);
  EXPECT_EQ(core.counter("track_frames_coasted"), 1);
}

TEST(PredictorConfig, DefaultsLoadAndTyposAreRejected) {
  const PredictorParams p = default_params();
  EXPECT_EQ(p.prediction_steps, 25);
  EXPECT_DOUBLE_EQ(p.prediction_dt_s, 0.1);
  EXPECT_DOUBLE_EQ(p.adaptive_noise.kappa, 5.5);
  EXPECT_DOUBLE_EQ(p.adaptive_noise.gamma, 1.3);
  const auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::string text;
  {
    YAML::Emitter e;
    e << root.section("predictor").yaml();
    text = e.c_str();
  }
  const auto good = config::load_string(text, "t.yaml");
  EXPECT_NO_THROW(PredictorParams::from_config(good));
  const auto typo = config::load_string(text + "\nprediction_stepz: 3\n", "t.yaml");
  EXPECT_THROW(PredictorParams::from_config(typo), config::ConfigError);
  auto bad_range = YAML::Clone(root.section("predictor").yaml());
  bad_range["adaptive_noise"]["xi_max_m2"] = 0.0001;
  YAML::Emitter e2;
  e2 << bad_range;
  EXPECT_THROW(PredictorParams::from_config(config::load_string(e2.c_str(), "t.yaml")), config::ConfigError);
  // the stationary mode is left through the manoeuvring one: alone it is an error, named
  auto alone = YAML::Clone(root.section("predictor").yaml());
  alone["maneuver"]["enabled"] = false;
  YAML::Emitter e3;
  e3 << alone;
  try {
    PredictorParams::from_config(config::load_string(e3.c_str(), "t.yaml"));
    ADD_FAILURE() << "stationary without maneuver accepted";
  } catch (const config::ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find("stationary"), std::string::npos) << err.what();
  }
  alone["stationary"]["enabled"] = false;
  YAML::Emitter e4;
  e4 << alone;
  EXPECT_NO_THROW(PredictorParams::from_config(config::load_string(e4.c_str(), "t.yaml")));
}

}  // namespace
}  // namespace evade::prediction
