// Mode evade: a speed bound near the route's end, so that the robot can
// still turn onto its goal instead of circling it.
//
// A unicycle at speed v turning at most omega_max follows circles no
// tighter than R = v / omega_max. The goal at distance d, at bearing phi off
// the heading, lies on the circle through it tangent to the heading, of
// radius d / (2 |sin phi|); a tighter turn followed by a straight line also
// reaches it. So from any speed with
//   v <= omega_max d / (2 |sin phi|)   (|phi| <= 90 deg)
//   v <= omega_max d / 2               (the goal behind the robot's beam)
// the goal can be driven onto; faster, the robot passes it on an arc and
// comes round again (at 0.8 m/s and 0.5 rad/s, a 1.6 m circle against a
// 0.3 m goal). The bound is fixed before the solve from the robot's state
// now, the same at every step (Problem::v_cap): as the robot turns onto the
// goal, the next cycle's bound is looser. It applies only while the route
// left is about straight to the end (at most max_route_ratio times the
// straight distance): a route that loops back past its own end keeps its
// speed. Never below min_speed_mps, never below what braking from the
// measured speed can reach yet.
#pragma once

#include <vector>

#include "config/fields.h"
#include "planning/problem.h"

namespace evade::planning {

struct GoalApproachParams {
  bool enabled = true;
  double min_speed_mps = 0.1;    // the bound never goes below this crawl
  double max_route_ratio = 2.0;  // applies while the route left <= this x the straight distance to its end

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("min_speed_mps", min_speed_mps, config::between(0.0, 10.0));
    v.field("max_route_ratio", max_route_ratio, config::between(1.0, 100.0));
  }
};

// The speed from which a robot at (x, y, yaw) turning at most omega_max
// can drive onto (gx, gy): infinity when the goal lies straight ahead.
double goal_capture_speed(double x, double y, double yaw, double gx, double gy, double omega_max);

// Upper bounds on v_k, k = 0..N-1, for pb (its start state, limits and
// measured speed) with the goal at (gx, gy) and route_left_m of the route
// still to go; empty when the bound does not apply or is not below v_max.
std::vector<double> goal_approach_caps(const GoalApproachParams& p, const Problem& pb, double gx, double gy,
                                       double route_left_m);

// *caps = the stepwise minimum of *caps and more (either may be empty:
// no bound).
void tighten_caps(const std::vector<double>& more, std::vector<double>* caps);

}  // namespace evade::planning
