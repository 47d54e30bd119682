// Mode evade: passive motion safety (Fraichard's "passive safety": if a
// collision happens, the robot is at rest). The defaults (config/robot.yaml)
// put it into every plan (every_plan) in its braking-point form
// (braking_point, below); the first form, described first, bounds the
// recovery's plans when no plan meets every D-CBF constraint.
// Whatever the recovery sends is bounded to a speed from which the
// robot, still going for reaction_s and then braking at its deceleration
// limit, is at rest before any nearby mover, going at its own speed in ANY
// direction, could reach the front of its body, whatever the prediction says
// about where it goes. The recovery's plans are judged against predictions
// that can be metres wrong (a walker that turns round, a bike first tracked
// late); this bound does not rely on them.
//
// A mover at body gap g (m) from the front of the robot, going at s (m/s),
// reaches it no sooner than (g - d_robot) / s, d_robot the robot's way until
// it stands; the robot at v stands after reaction_s + v / decel, having gone
// v reaction_s + v^2 / (2 decel). It stands first when
//   v reaction_s + v^2 / (2 decel) + s (reaction_s + v / decel) <= g,
// so v <= decel (-p + sqrt(p^2 + 2 (g - s reaction_s) / decel)),
// p = reaction_s + s / decel (0 when g <= s reaction_s).
// The front of the body is the footprint's front disc: the robot never
// reverses (PlannerParams::from_config), and a contact on its sides or rear
// while it goes forward is no approach of its own (the metrics' fault rule,
// docs/SPEC.md). The gap is the paper's line-ellipse distance from that
// disc to the mover's step-0 ellipse less its inflation sigma (its own body).
// A mover is any ellipse obstacle of the problem whose fastest predicted
// step is at least min_mover_speed_mps; a track younger than
// min_track_age_s (its speed not known yet) is one going at least
// unknown_speed_mps. Older slower tracks (bins, posts, walls) are left to
// the constraints. With speed_memory_s, a track's speed is at least the
// fastest its tracker reported over that long (ObstacleTrack::
// recent_speed_mps, recent_max.h): a walker turning round goes on at its
// walking speed while the estimate passes through zero, and the bound
// must not lapse just as it comes back. With measured_position, the mover
// is also where its tracker last measured it (ObstacleTrack::measured) when
// that is nearer the front disc than the prediction's step 0: a filter that
// trusts its motion model lags a walker turning round by half a metre for
// a few tenths of a second, the measurement far less.
//
// With every_plan the bound is in every cycle's problem, certified plans
// included (the invariant passive safety needs: a robot that enters the
// recovery faster than the bound cannot always brake to it in time).
//
// The bound is one speed for every step of the plan (Problem::v_cap, below
// what braking from the measured speed reaches only where braking cannot
// get there yet): the plan is sent for one cycle, and the next cycle bounds
// again from where the robot and the movers are then.
//
// With braking_point, each mover bounds where braking ends instead
// (Problem::reach, problem.h): at every step of the plan, the point where
// the front disc stands if the robot goes on for reaction_s and then
// brakes stays out of the mover's reach by then, the mover going at its
// speed in any direction from where it is now. Driving straight at a mover
// this is the speed bound; across its way the braking point moves aside,
// so a robot at rest in a bike's path may turn and drive out of it, which
// the speed bound forbids (it would stand, passive and in the way). Where
// braking from the measured controls misses a step's bound, that step asks
// no more than braking gives.
//
// With turn_bound, the turn is bounded too: a robot turning on the spot is
// not at rest. A point of the footprint rectangle at lever arm r from the
// base centre moves at omega x r, so a long body's ends swing sideways and
// its front edge's sides move forwards (the Scout's 0.93 x 0.70 m body at
// 0.5 rad/s: up to 0.29 m/s at a corner), and a walker beside or ahead of
// it is met, as the metrics count it, at fault (docs/SPEC.md: omega x
// lever arm). For every mover, every point c of the rectangle's edge
// (checked: the point nearest the body's centre, the corners and three
// points between the corners on each edge) and every direction n a
// contact at c can have (an edge's outward normal; at a corner, seven
// between its edges' normals), the turn that moves c along n (omega q >
// 0, q = (z x r_c) . n) is bounded to the rate w from which it slows
// (going on for reaction_s, then slowing at the turn-rate limit alpha) to
// w_r = turn_residual_mps / q, where c comes at no more than
// turn_residual_mps, before the mover, at its speed s in any direction,
// could touch c from n, c's own swing included:
//   s (reaction_s + (w - w_r) / alpha)
//     + q (w reaction_s + (w^2 - w_r^2) / (2 alpha)) <= g,
// g how far the body's centre has to go to touch c from n (the gap from
// c to the body when n points at it, farther round a corner; the same
// bodies, speeds and measured positions as above); w_r is never bound.
// Not the nearest point alone: a dog running past the robot's side
// reaches the far corner before the turn stops, and a turn that swings
// that corner out towards it is one the nearest point calls free. And a
// point that barely swings (q near 0) bounds nothing: without the
// residual it would bound the turn to the rate that stops before the
// mover arrives however little it moves. A turn that moves every checked
// point away from every contact it could have is free. One
// exception: where the mover's predicted body (inflation removed) meets
// the robot standing where it is within the horizon, and a turn that way
// at the limits gets the body out of its way in time (turned by at most a
// quarter turn, the robot standing would not meet it, and the turn there
// keeps clear of it at every step), that turn is not bound: standing is
// no refuge, and the turn is what gets the body out of the mover's way
// (the Scout straightening up in a lane as a walker comes
// past it). The bound is on the plan's first step (Problem::omega_lo,
// omega_hi), the command sent before the next cycle bounds again; a turn
// that cannot slow to it in one step slows as fast as it can.
#pragma once

#include <vector>

#include "config/fields.h"
#include "planning/problem.h"
#include "planning/recovery_rank.h"

namespace evade::planning {

struct PassiveSafetyParams {
  bool enabled = true;               // mode evade: the bound (off: unbounded)
  double reaction_s = 0.15;          // the robot goes on this long before it brakes: perception's age and a cycle
  double unknown_speed_mps = 1.6;    // a track younger than min_track_age_s moves at least this fast
  double min_track_age_s = 0.5;      // tracked this long, a track's speed is its prediction's
  double min_mover_speed_mps = 0.2;  // older tracks predicted slower than this are not movers
  bool every_plan = true;            // the hard problem too: certified plans keep the bound (off: only the recovery's)
  bool braking_point = true;         // bound where braking from each step ends (off: one speed in every direction)
  bool slow_chosen = true;  // the recovery's chosen plan slowed onto the reach bounds where it comes to no worse
  SlowedRefusal slowed_refused_if = SlowedRefusal::kStructure;  // slow_chosen: what "worse" is (recovery_rank.h)
  double speed_memory_s = 2.0;      // s: a mover is as fast as its tracker said lately (0: the prediction)
  bool measured_position = true;    // a mover is also where its tracker last measured it, if nearer
  bool turn_bound = false;          // the first step's turn moves no footprint point into a mover's reach (above)
  double turn_residual_mps = 0.05;  // turn_bound: a point may still come this fast where a mover could reach it

  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("reaction_s", reaction_s, config::between(0.0, 5.0));
    v.field("unknown_speed_mps", unknown_speed_mps, config::between(0.0, 20.0));
    v.field("min_track_age_s", min_track_age_s, config::between(0.0, 10.0));
    v.field("min_mover_speed_mps", min_mover_speed_mps, config::between(0.0, 20.0));
    v.field("every_plan", every_plan);
    v.field("braking_point", braking_point);
    v.field("slow_chosen", slow_chosen);
    v.choice("slowed_refused_if", slowed_refused_if,
             config::Choices<SlowedRefusal>{{"worse_outcome", SlowedRefusal::kWorseOutcome},
                                            {"drives_into", SlowedRefusal::kDrivesInto},
                                            {"structure", SlowedRefusal::kStructure}});
    v.field("speed_memory_s", speed_memory_s, config::between(0.0, 30.0));
    v.field("measured_position", measured_position);
    v.field("turn_bound", turn_bound);
    v.field("turn_residual_mps", turn_residual_mps, config::between(0.0, 1.0));
  }
};

// The largest speed (m/s, at least 0) from which the robot stands before a
// mover at body gap gap_m going at mover_speed_mps could reach it (above).
double passive_safe_speed(double gap_m, double mover_speed_mps, double reaction_s, double decel_mps2);

// The largest turn rate w (rad/s, at least 0) from which a footprint point
// whose swing towards a mover is lever_m w slows to a swing of
// residual_mps before the mover at gap gap_m going at mover_speed_mps
// could reach it (turn_bound, above); infinity for a point that does not
// swing (lever_m 0).
double passive_safe_turn_rate(double gap_m, double mover_speed_mps, double lever_m, double reaction_s,
                              double alpha_radps2, double residual_mps);

// The first step's turn-rate bounds of turn_bound for pb: lo <= 0 <= hi,
// -omega_max and omega_max where no mover binds.
struct TurnBounds {
  double lo = 0.0, hi = 0.0;
};
TurnBounds passive_turn_bounds(const PassiveSafetyParams& p, const Problem& pb);

// One mover of pb: its body now (inflation removed) and its
// passive_safe_speed (m/s, at most pb.lim.v_max).
struct MoverBound {
  ObstacleTrack body;
  double speed_mps = 0.0;        // the robot's
  double mover_speed_mps = 0.0;  // the mover's, as the bound takes it
};
std::vector<MoverBound> mover_bounds(const PassiveSafetyParams& p, const Problem& pb);

// The bound for pb: the least passive_safe_speed over pb's movers, at most
// pb.lim.v_max (v_max: no mover).
double passive_speed_bound(const PassiveSafetyParams& p, const Problem& pb);

// One reach bound (Problem::reach) per mover whose speed is below v_max,
// for pb's footprint, reaction_s and decel.
std::vector<ReachBound> passive_reach_bounds(const PassiveSafetyParams& p, const Problem& pb);

// u (controls of pb, within its limits: project_controls) with each speed
// lowered, step by step and no lower than braking from the step before
// allows, until every reach bound of pb holds at its step (the turn rates
// kept). A step where even braking misses keeps braking's speed (its
// allowance covers braking from the measured controls, not from
// elsewhere). Returns whether it lowered any speed.
bool project_onto_reach(const Problem& pb, std::vector<double>* u);

// pb bounded (braking_point: reach bounds appended; else every v_cap at
// most passive_speed_bound, v_cap filled with v_max first where empty);
// pb unchanged when no mover binds. Returns whether it bound.
bool bound_passively(const PassiveSafetyParams& p, Problem* pb);

// pb's first step's turn within passive_turn_bounds (omega_lo, omega_hi
// sized N, unbounded past step 0, and any earlier bound kept), whatever
// p.turn_bound says; pb unchanged when no mover binds. Returns whether it
// bound.
bool bound_turn_passively(const PassiveSafetyParams& p, Problem* pb);

}  // namespace evade::planning
