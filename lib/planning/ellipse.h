// An obstacle's ellipse at one moment, in the odometry frame: what the
// planner's layers keep clear of besides the MPC's constraints (the detour
// grid's settled and swept obstacles, the static field's movers and kept
// tracks). A track's step k of OBSTACLE_PREDICTIONS, inflated as published.
//
// The tracker's tracking::Ellipse (lib/tracking/geometry.h) stays a type of
// its own: it is the minimum bounding ellipse fitted to a cluster's cells,
// kept in a canonical form (b <= a, theta in [-pi/2, pi/2): an axis is a
// line) on which its shape variation (Xi_eta) relies; and lib/tracking and
// lib/planning depend neither on one another nor on a common library of
// shapes. Here a and b are in any order and theta is any angle (a mover
// swept along its velocity).
#pragma once

namespace evade::planning {

struct Ellipse {
  double x = 0, y = 0;  // centre, m
  double a = 0, b = 0;  // semi-axes, m; a along theta
  double theta = 0;     // rad
  // (px, py) inside the ellipse with both semi-axes grown by `grow` (m).
  bool contains(double px, double py, double grow) const;
};

}  // namespace evade::planning
