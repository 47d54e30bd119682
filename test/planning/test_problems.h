// Hand-built planning problems shared by the planning tests and benchmark.
#pragma once

#include <cmath>
#include <vector>

#include "planning/params.h"
#include "planning/problem.h"

namespace evade::planning::testing {

inline Limits default_limits() {
  Limits l;
  l.v_min = 0.0;
  l.v_max = 1.0;
  l.omega_max = 0.5;
  l.accel = 1.0;
  l.decel = 1.5;
  l.alpha = 3.0;
  return l;
}

// Robot at (x0, y0, yaw0) moving at v0; the reference runs along the x axis
// from x0 at speed v_ref.
inline Problem straight_problem(double x0, double y0, double yaw0, double v0, double v_ref, int N = 25,
                                double dt = 0.1) {
  Problem pb;
  pb.N = N;
  pb.dt = dt;
  pb.x0 = x0;
  pb.y0 = y0;
  pb.yaw0 = yaw0;
  pb.v_prev = v0;
  pb.omega_prev = 0;
  pb.w = Weights{};  // robot.yaml's (test_config_sections pins the C++ defaults to it)
  pb.lim = default_limits();
  pb.d_safe = 0.3;
  for (int k = 0; k <= N; ++k) {
    pb.ref_x.push_back(x0 + v_ref * dt * k);
    pb.ref_y.push_back(0.0);
    pb.ref_yaw.push_back(0.0);
  }
  return pb;
}

// The controls (v, omega) at every step of pb's horizon, as given (not
// projected onto the limits).
inline std::vector<double> constant_controls(const Problem& pb, double v, double omega) {
  std::vector<double> u(pb.num_controls());
  for (int k = 0; k < pb.N; ++k) {
    u[2 * k] = v;
    u[2 * k + 1] = omega;
  }
  return u;
}

// Obstacle moving at constant velocity, fixed shape.
inline ObstacleTrack moving_obstacle(int64_t id, double x, double y, double vx, double vy, double a, double b,
                                     double theta, double decay, int N, double dt) {
  ObstacleTrack o;
  o.id = id;
  o.decay = decay;
  for (int k = 0; k <= N; ++k) {
    o.x.push_back(x + vx * dt * k);
    o.y.push_back(y + vy * dt * k);
    o.a.push_back(a);
    o.b.push_back(b);
    o.theta.push_back(theta);
  }
  return o;
}

// The fixed benchmark problem with k obstacles: the robot drives along x at
// 0.8 m/s; obstacles alternate between static ones near the path, head-on
// movers and crossing movers, laid out deterministically.
inline Problem bench_problem(int num_obstacles, double time_offset_s = 0.0) {
  const double v = 0.8;
  Problem pb = straight_problem(v * time_offset_s, 0.0, 0.0, v, v);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);  // the robot of config/robot.yaml, its planner's discs
  pb.d_safe = 0.15;
  const double decay = 1.0 - 0.1;  // gamma = 0.1
  for (int i = 0; i < num_obstacles; ++i) {
    const double t = time_offset_s;
    double x, y, vx, vy;
    const int row = i / 4;
    switch (i % 4) {
      case 0:  // static, close beside the path, alternating sides (a slalom)
        x = 1.4 + 0.5 * row;
        y = row % 2 == 0 ? 0.55 : -0.55;
        vx = vy = 0.0;
        break;
      case 1:  // oncoming, offset from the path
        x = 3.5 + 0.6 * row;
        y = row % 2 == 0 ? -0.65 : 0.65;
        vx = -0.5;
        vy = 0.0;
        break;
      case 2:  // crossing ahead from the left
        x = 2.2 + 0.4 * row;
        y = 2.0 + 0.3 * row;
        vx = 0.0;
        vy = -0.6;
        break;
      default:  // static, off to the side
        x = 1.0 + 0.5 * row;
        y = row % 2 == 0 ? -0.75 : 0.75;
        vx = vy = 0.0;
        break;
    }
    pb.obstacles.push_back(moving_obstacle(i, x + vx * t, y + vy * t, vx, vy, 0.35, 0.25, 0.3 * i, decay, pb.N, pb.dt));
  }
  return pb;
}

}  // namespace evade::planning::testing
