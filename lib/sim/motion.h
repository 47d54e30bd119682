// Obstacle motion models. Each is a pure function of the time since the
// obstacles started moving, so a run is reproducible and a test can check
// any instant against the definition.
#pragma once

#include "sim/scenario.h"

namespace evade::sim {

struct ObstacleState {
  double x = 0.0;  // m, centre, world frame
  double y = 0.0;
  double vx = 0.0;  // m/s
  double vy = 0.0;
};

// State of obstacle `s` at `t_s` seconds after the motion started. Its own
// motion begins s.start_delay_s later: for t_s <= s.start_delay_s (not
// started yet) it is at its initial position, at rest; after that the
// models below run on t = t_s - s.start_delay_s.
//  - static: always at (x, y);
//  - constant velocity: (x, y) + (vx, vy) t;
//  - waypoints: arc length speed*t along the path (x, y) -> waypoints...,
//    pingpong: back and forth (period 2 L / speed); loop: the closed
//    polygon (period L / speed); once: stops at the last waypoint.
ObstacleState obstacle_state(const ObstacleSpec& s, double t_s);

}  // namespace evade::sim
