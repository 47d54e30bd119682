#include "metrics/contacts.h"

#include <cmath>

namespace evade::metrics {
namespace {

OrientedRect box_of(const evade::sim_obstacle_t& o) { return {{o.x, o.y}, o.yaw, o.length, o.width}; }

Vec2 unit(Vec2 from, Vec2 to) {
  const double dx = to.x - from.x, dy = to.y - from.y, n = std::hypot(dx, dy);
  return n > 1e-12 ? Vec2{dx / n, dy / n} : Vec2{0, 0};
}

}  // namespace

OrientedRect footprint(const evade::sim_truth_t& t) {
  return {{t.x, t.y}, t.yaw, t.footprint_length, t.footprint_width};
}

double obstacle_clearance(const OrientedRect& robot, const evade::sim_obstacle_t& o) {
  if (o.shape == "box") return clearance(robot, box_of(o));
  return clearance(robot, Vec2{o.x, o.y}, o.radius);
}

void obstacle_closest_points(const OrientedRect& robot, const evade::sim_obstacle_t& o, Vec2* on_robot,
                             Vec2* on_obstacle) {
  if (o.shape == "box")
    closest_points(robot, box_of(o), on_robot, on_obstacle);
  else
    closest_points(robot, Vec2{o.x, o.y}, o.radius, on_robot, on_obstacle);
}

double point_velocity_along(const evade::sim_truth_t& t, Vec2 p, Vec2 n) {
  const double vx = t.v * std::cos(t.yaw) - t.omega * (p.y - t.y);
  const double vy = t.v * std::sin(t.yaw) + t.omega * (p.x - t.x);
  return vx * n.x + vy * n.y;
}

Contact ContactTracker::start(const evade::sim_truth_t& t, const evade::sim_obstacle_t& o, double t_s) const {
  Contact c;
  c.obstacle_id = o.id;
  c.t_start_s = t_s;
  c.robot_speed_mps = std::fabs(t.v);
  // The direction of the contact: from the robot's closest point to the
  // obstacle's in the sample before, when they were still apart; at a
  // first sample that already overlaps, from the robot's closest point
  // to the obstacle's centre.
  Vec2 on_robot, on_obstacle;
  Vec2 n;
  const evade::sim_obstacle_t* before = nullptr;
  if (previous_)
    for (const auto& p : previous_->obstacles)
      if (p.id == o.id) before = &p;
  if (before) {
    obstacle_closest_points(footprint(*previous_), *before, &on_robot, &on_obstacle);
    n = unit(on_robot, on_obstacle);
  } else {
    obstacle_closest_points(footprint(t), o, &on_robot, &on_obstacle);
    n = unit(on_robot, Vec2{o.x, o.y});
  }
  c.approach_speed_mps = point_velocity_along(t, on_robot, n);
  c.at_fault = c.approach_speed_mps > fault_mps_;
  return c;
}

void ContactTracker::add(const evade::sim_truth_t& t, double t_s) {
  const OrientedRect robot = footprint(t);
  std::map<int, size_t> still_open;
  for (const auto& o : t.obstacles) {
    const double c = obstacle_clearance(robot, o);
    if (c > 0) continue;
    auto it = open_.find(o.id);
    size_t i;
    if (it == open_.end()) {
      i = contacts_.size();
      contacts_.push_back(start(t, o, t_s));
    } else {
      i = it->second;
    }
    contacts_[i].t_end_s = t_s;
    contacts_[i].max_penetration_m = std::max(contacts_[i].max_penetration_m, -c);
    still_open[o.id] = i;
  }
  open_.swap(still_open);
  previous_ = t;
}

}  // namespace evade::metrics
