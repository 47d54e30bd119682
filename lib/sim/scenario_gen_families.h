// Internal to the scenario generator (scenario_gen.cpp): the scene being
// drawn, the helpers the families share, and one builder per family.
// Each builder adds its obstacles to the draft and returns false when it
// could not place them (the scene is then redrawn).
#pragma once

#include <string>
#include <vector>

#include "sim/scenario.h"
#include "sim/scenario_check.h"
#include "sim/scenario_gen_params.h"
#include "sim/scenario_gen_random.h"

namespace evade::sim::gen::detail {

struct Ctx {
  const FamilyParams& p;
  const RobotFacts& robot;
  const ScenarioCheckParams& check;
  Rng& rng;
};

struct Draft {
  Scenario sc;
  std::vector<std::string> notes;    // one per obstacle
  std::vector<std::string> summary;  // one line per family that added obstacles
};

// v rounded to a multiple of `step` (values are rounded as they are drawn,
// so the file holds exactly what the checks saw).
double q(double v, double step = 1e-3);

// The robot's nominal arrival time (s after the obstacles start) at route
// position x: route arc length to x / reference speed + arrival_lag_s.
double arrival_s(const Ctx& c, const Draft& d, double x);

// Adds `o` if it keeps the start margin, starts apart from every other
// obstacle and, resting for good, keeps the goal margin; false otherwise.
bool add_if_clear(const Ctx& c, Draft& d, const ObstacleSpec& o, const std::string& note);
// All of them, or none if one of them breaks a margin (a group).
bool add_all_if_clear(const Ctx& c, Draft& d, const std::vector<ObstacleSpec>& os,
                      const std::vector<std::string>& notes);

// A straight route from (-L/2, 0) to (L/2, 0), L drawn from route_length_m.
Draft straight_draft(Ctx& c);

// Where along a straight route a mover meets it: uniform over
// [start + meet_from_start_m, goal - meet_before_goal_m].
double meet_x(Ctx& c, const Draft& d);
// Unit vector at `angle_rad` from +x.
Vec2 heading(double angle_rad);
Vec2 along(const Vec2& from, const Vec2& dir, double distance);
// Bodies with sizes drawn from their kind (speeds are drawn by the caller).
ObstacleSpec cylinder_body(Ctx& c, const CylinderKind& k);
ObstacleSpec box_body(Ctx& c, const BoxKind& k, double yaw);
// `o` follows `path` once at `speed` and is at arc length s_meet at time
// t_meet: it waits there (start_delay_s) or, when it could not make it in
// time, starts further along the path. Points are rounded.
void follow_timed(ObstacleSpec& o, std::vector<Vec2> path, double speed, double s_meet, double t_meet);
double path_length(const std::vector<Vec2>& path);
// A number for the notes ("1.25").
std::string num(double v);
// "1.25 s before the robot" (lead > 0) or "0.50 s after the robot".
std::string timing(double lead_s);
// "1 mover", "3 movers" (plural: singular + "s" unless given).
std::string count(int n, const std::string& singular, const std::string& plural = "");

bool crossing(Ctx& c, Draft& d);
bool headon(Ctx& c, Draft& d);
bool overtaking(Ctx& c, Draft& d);
bool crowd(Ctx& c, Draft& d);
bool doorway(Ctx& c, Draft& d);  // bends the draft's route through the gap
bool occlusion(Ctx& c, Draft& d);
bool fast_small(Ctx& c, Draft& d);
bool static_clutter(Ctx& c, Draft& d);

}  // namespace evade::sim::gen::detail
