// Synthetic MBE observations of a moving obstacle, with the noise a LiDAR
// minimum bounding ellipse really has: white centre noise, shape jitter, and
// the centre shift that shape jitter causes (an MBE grows on the side where
// new returns appear, so its centre moves by half the axis change).
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "evade/obstacle_list_t.hpp"
#include "prediction/params.h"

namespace evade::prediction::testing {

struct Truth {
  double x0 = 0, y0 = 0, vx = 0, vy = 0, ax = 0, ay = 0;
  double a = 0.4, b = 0.25, theta = 0.3;
  double x(double t) const { return x0 + vx * t + 0.5 * ax * t * t; }
  double y(double t) const { return y0 + vy * t + 0.5 * ay * t * t; }
  double speed(double t) const { return std::hypot(vx + ax * t, vy + ay * t); }
};

struct Noise {
  double centre_std_m = 0.04;   // white centre noise
  double axis_std_m = 0.03;     // shape jitter of each semi-axis
  double theta_std_rad = 0.05;  // orientation jitter
  double coupled_shift = 0.0;   // centre shift per metre of major-axis change (0.5 = one side fixed)
  double min_interval_s = 0.1;  // frame interval drawn uniformly in [min, max]
  double max_interval_s = 0.1;
};

struct Frame {
  double t;
  evade::obstacle_list_t msg;
};

inline std::vector<Frame> make_frames(const Truth& truth, const Noise& noise, double duration_s, uint32_t seed,
                                      int64_t id = 7, int64_t t0_us = 1'000'000'000) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> interval(noise.min_interval_s, noise.max_interval_s);
  std::vector<Frame> frames;
  int64_t utime = t0_us;
  double t = 0.0;
  while (t <= duration_s + 1e-9) {
    const double da = noise.axis_std_m * n01(rng);
    const double db = noise.axis_std_m * n01(rng);
    const double dth = noise.theta_std_rad * n01(rng);
    const double side = (rng() & 1u) ? 1.0 : -1.0;         // which end of the major axis moved
    const double shift = noise.coupled_shift * da * side;  // one end fixed: the centre moves by da / 2
    evade::obstacle_t o{};
    o.id = id;
    o.x = truth.x(t) + noise.centre_std_m * n01(rng) + shift * std::cos(truth.theta);
    o.y = truth.y(t) + noise.centre_std_m * n01(rng) + shift * std::sin(truth.theta);
    o.a = std::max(0.05, truth.a + da);
    o.b = std::max(0.05, truth.b + db);
    o.theta = truth.theta + dth;
    o.shape_variation = 0.0;
    o.num_cells = 20;
    o.age = static_cast<int32_t>(frames.size());
    Frame f;
    f.t = t;
    f.msg.utime = utime;
    f.msg.obstacles.push_back(o);
    f.msg.num_obstacles = 1;
    frames.push_back(f);
    const double step = interval(rng);
    utime += static_cast<int64_t>(std::llround(step * 1e6));
    t = 1e-6 * static_cast<double>(utime - t0_us);
  }
  return frames;
}

// The defaults of config/robot.yaml, read through the real loader.
PredictorParams default_params();

}  // namespace evade::prediction::testing
