// Mode evade: a speed bound near the regions hidden behind large obstacles
// (OCCLUSIONS, lib/mapping/hidden_regions.h), as a careful driver passing a
// parked van keeps. A person hidden in a region comes into view across one
// of its side edges; walking from there at walking_speed_mps, they need
//   T = (d - clearance_m) / walking_speed_mps
// to reach the robot's footprint, d the distance from the footprint to the
// nearest point of a side edge ahead of the robot. The robot, reacting after
// reaction_s and braking at its deceleration limit, stops in time when
//   v <= decel (T - reaction_s),
// which is the bound on v at each step of the plan, never below
// min_speed_mps (a crawl: without it the robot would stand at every corner).
// The plan's positions are those of the reference path travelled at the
// bounded speed, so the bound is fixed before the solve: an upper bound on
// v_k in the problem (Problem::v_cap), not a constraint on the state.
#pragma once

#include <vector>

#include "config/fields.h"
#include "evade/hidden_region_list_t.hpp"
#include "planning/problem.h"

namespace evade::planning {

struct OcclusionSpeedParams {
  bool enabled = true;             // mode evade bounds its speed near OCCLUSIONS' regions
  double walking_speed_mps = 1.6;  // a person stepping out of a hidden region
  double reaction_s = 0.3;         // from stepping into view to braking: a revolution, perception, a cycle
  double clearance_m = 0.3;        // the person's radius: their edge reaches the footprint this much sooner
  double min_speed_mps = 0.25;     // the bound never goes below this crawl
  double max_age_s = 0.5;          // OCCLUSIONS older than this (bus time) are not used

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("walking_speed_mps", walking_speed_mps, config::between(0.1, 10.0));
    v.field("reaction_s", reaction_s, config::between(0.0, 5.0));
    v.field("clearance_m", clearance_m, config::between(0.0, 5.0));
    v.field("min_speed_mps", min_speed_mps, config::between(0.0, 10.0));
    v.field("max_age_s", max_age_s, config::positive());
  }
};

// The stopping-safe speed at distance d (m) from the footprint's edge to
// where a person could step out: decel (T - reaction_s), at least 0.
double stopping_safe_speed(const OcclusionSpeedParams& p, double decel_mps2, double d);

// Distance from (x, y) to the nearest point of the region's side edges
// that lies ahead of a robot at heading yaw (positive along it); infinity
// when none does.
double distance_to_exit_ahead(const evade::hidden_region_t& r, double x, double y, double yaw);

// Upper bounds on v_k, k = 0..N-1, for pb (its reference path, footprint,
// limits and start speed): each the stopping-safe speed at the step's
// position (at least min_speed_mps, at most v_max), raised where braking
// from pb.v_prev at the deceleration limit cannot get below it yet. Empty
// when no bound is below v_max.
std::vector<double> occlusion_speed_caps(const OcclusionSpeedParams& p, const evade::hidden_region_list_t& regions,
                                         const Problem& pb);

}  // namespace evade::planning
