// Contacts between the robot's true footprint and the true obstacle shapes
// (SIM_TRUTH), one per episode of continuous overlap with one obstacle, and
// whether the robot was at fault (metrics_rules()).
#pragma once

#include <map>
#include <optional>
#include <vector>

#include "evade/sim_truth_t.hpp"
#include "metrics/geometry.h"

namespace evade::metrics {

struct Contact {
  int obstacle_id = 0;
  double t_start_s = 0;           // first overlapping sample, since the first SIM_TRUTH
  double t_end_s = 0;             // last overlapping sample
  double max_penetration_m = 0;   // largest overlap depth (-clearance) during the episode
  double robot_speed_mps = 0;     // |v| of the robot at t_start_s
  double approach_speed_mps = 0;  // its velocity at the contact point towards the obstacle
  bool at_fault = false;          // approach_speed_mps > fault threshold
};

// The footprint rectangle of a SIM_TRUTH sample.
OrientedRect footprint(const evade::sim_truth_t& t);
// The clearance between a footprint and an obstacle (<= 0: overlap), and
// optionally the closest points of the two.
double obstacle_clearance(const OrientedRect& robot, const evade::sim_obstacle_t& o);
void obstacle_closest_points(const OrientedRect& robot, const evade::sim_obstacle_t& o, Vec2* on_robot,
                             Vec2* on_obstacle);

// The velocity (m/s) of the footprint's point p of a rigid robot moving at
// (v, omega) from `t`, projected on the unit vector n.
double point_velocity_along(const evade::sim_truth_t& t, Vec2 p, Vec2 n);

class ContactTracker {
 public:
  explicit ContactTracker(double fault_approach_speed_mps) : fault_mps_(fault_approach_speed_mps) {}
  // One SIM_TRUTH sample, in time order; t_s = its time since the first.
  void add(const evade::sim_truth_t& t, double t_s);
  const std::vector<Contact>& contacts() const { return contacts_; }

 private:
  Contact start(const evade::sim_truth_t& t, const evade::sim_obstacle_t& o, double t_s) const;

  double fault_mps_;
  std::vector<Contact> contacts_;
  std::map<int, size_t> open_;                  // obstacle id -> its contact in contacts_, while overlapping
  std::optional<evade::sim_truth_t> previous_;  // the sample before
};

}  // namespace evade::metrics
