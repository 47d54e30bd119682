// Guidance (mode evade, planner.guidance): topologically distinct ways
// through the predicted obstacles over the horizon, each as a coarse
// space-time path the local solves start from (README "Guidance").
//
// Homotopy invariant. In the frame of the route ahead (origin the robot,
// axis e towards the reference's last point, e_perp to its left), the
// vector from obstacle i to the robot at step k is (ds_k, rho_k) =
// (e . (p_k - o_k), e_perp . (p_k - o_k)). Its label is the signed number
// of times ds crosses zero: +1 for each crossing forwards (ds from < 0 to
// >= 0) with rho >= 0 (passing level with the obstacle on its left), -1 on
// its right, the opposite sign for a crossing backwards. This counts the
// half-turns of that vector's winding round the obstacle's world line,
// taken where it crosses the line ds = 0: two paths with the same end
// points avoiding the world line have the same count exactly when they are
// homotopic round it (the H-signature of the world line with ds = 0 as its
// cut). The path is continued from its end along e, the obstacle held
// where it is at the horizon's end: an obstacle still ahead then adds the
// side the continuation passes it on, nothing when it runs into the
// ellipse. A label 0 means the robot does not get past the obstacle (it
// waits or follows behind it, or gets level and falls back). Two paths are the same class when every obstacle has the
// same label in both (same_class): waiting short of an obstacle is a way of
// its own, besides passing it on the left or on the right. A plan keeps
// the way of an earlier one when no obstacle has two different nonzero
// labels (compatible): an obstacle not reached then may be passed now.
//
// Search: a lattice in the route frame, one layer every `layer_steps` MPC
// steps, nodes every `longitudinal_step_m` along e and `lateral_step_m`
// across it (within +-lateral_max_m), edges no longer than v_max times the
// layer's time (plus half a cell's diagonal), a node or edge step inside
// an obstacle's ellipse grown by the footprint's reach and d_safe blocked
// (checked at every MPC step, the obstacle as the solver sees it). An edge costs the MPC's stage cost (q_xy, terminal
// p_xy) of its steps against the reference. Forward and backward dynamic programming give, for every node, the cheapest
// path through it; those paths in order of cost are kept when their class is new, up to max_classes. Deterministic: no
// sampling, ties broken by node order.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "config/fields.h"
#include "planning/problem.h"

namespace evade::planning {

// `planner.guidance`; the defaults are config/robot.yaml's.
struct GuidanceParams {
  bool enabled = false;               // off until it wins the benchmark (config/robot.yaml)
  int max_classes = 4;                // guidance classes solved per cycle (besides the previous plan)
  int threads = 2;                    // local solves run on this many threads
  int layer_steps = 5;                // MPC steps per lattice layer
  double lateral_step_m = 0.25;       // lattice spacing across the route
  double lateral_max_m = 2.5;         // lattice half-width
  double longitudinal_step_m = 0.25;  // lattice spacing along the route
  double switch_cost_factor = 1.3;    // a plan of another class than last cycle's counts its cost times this
  // When no local solve meets every constraint: the least violating plan
  // (braking among the candidates), or evade's recovery chain (restarts,
  // relaxed problem, escape turn, most clearance; planner_core.h recover).
  enum class Fallback { kLeastViolating, kRecovery };
  Fallback fallback = Fallback::kRecovery;

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("max_classes", max_classes, config::between(0, 16));
    v.field("threads", threads, config::between(1, 64));
    v.field("layer_steps", layer_steps, config::between(1, 64));
    v.field("lateral_step_m", lateral_step_m, config::between(0.05, 2.0));
    v.field("lateral_max_m", lateral_max_m, config::between(0.0, 10.0));
    v.field("longitudinal_step_m", longitudinal_step_m, config::between(0.05, 2.0));
    v.field("switch_cost_factor", switch_cost_factor, config::between(1.0, 100.0));
    v.choice(
        "fallback", fallback,
        config::Choices<Fallback>{{"least_violating", Fallback::kLeastViolating}, {"recovery", Fallback::kRecovery}});
  }
};

// Labels by obstacle id (sorted by id), see the header comment.
struct Signature {
  std::vector<std::pair<int64_t, int>> labels;
};

// True when every obstacle in both has the same label.
bool same_class(const Signature& a, const Signature& b);
// True when no obstacle in both has two different nonzero labels.
bool compatible(const Signature& a, const Signature& b);

// The route frame of a problem: origin the robot, axis towards the
// reference's last point (its heading at step 1 when that is nearer than
// 0.1 m).
struct RouteFrame {
  double ox = 0, oy = 0, ex = 1, ey = 0;
};
RouteFrame route_frame(const Problem& pb);

// The signature of positions xs, ys (N + 1, steps 0..N) against every
// obstacle of pb.
Signature path_signature(const Problem& pb, const RouteFrame& f, const std::vector<double>& xs,
                         const std::vector<double>& ys);
// The same for a rollout's states (3 (N + 1): x, y, yaw).
Signature states_signature(const Problem& pb, const RouteFrame& f, const std::vector<double>& states);

struct GuidancePath {
  Signature signature;
  std::vector<double> x, y;  // N + 1 positions, steps 0..N
  double cost = 0;           // the lattice cost
};

// Up to g.max_classes paths of distinct classes, cheapest first; none when
// every lattice node next to the start is blocked.
std::vector<GuidancePath> find_guidance(const Problem& pb, const GuidanceParams& g);

// pb with the guidance path as its reference (positions, and headings
// along the path): a local solve of this problem stays in the path's class.
Problem along_guidance(const Problem& pb, const GuidancePath& path);

// Controls (2N) that follow a guidance path with the unicycle within the
// limits of pb (a warm start for the local solve).
std::vector<double> controls_along(const Problem& pb, const GuidancePath& path);

}  // namespace evade::planning
