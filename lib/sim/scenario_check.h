// Validity of a scenario for an unattended benchmark episode: what the
// scenario generator guarantees for every scene it writes (and what its
// tests check over many seeds). Each rule is stated on the scenario as the
// simulator runs it (obstacle_state(), motion.h).
#pragma once

#include <string>
#include <vector>

#include "sim/scenario.h"

namespace evade::sim {

struct ScenarioCheckParams {
  // 1. No obstacle within start_margin_m of the robot's footprint at its
  //    start pose, at any time in [0, start_clear_time_s] of obstacle
  //    motion (sampled every time_step_s).
  double start_margin_m = 0.3;
  double start_clear_time_s = 2.0;
  double time_step_s = 0.02;
  // 2. Every obstacle at rest for good (static, or a `once` mover at its
  //    last waypoint) keeps goal_margin_m off the robot standing at the
  //    goal with any heading (a disc of the footprint's half-diagonal).
  double goal_margin_m = 0.3;
  // 3. Past the obstacles at rest for good, a way from start to goal at
  //    least footprint width + passage_margin_m wide (to the resolution of
  //    a grid of grid_m cells, 8-connected), within route_pad_m of the
  //    route's bounding box (a wall reaching farther than that from the
  //    route cannot be walked round).
  double passage_margin_m = 0.3;
  double grid_m = 0.1;
  double route_pad_m = 3.0;
  // 4. Every obstacle at least min_height_m high (visible to the map).
  double min_height_m = 0.2;
  // 5. No two obstacles closer than apart_m where they start (they may
  //    pass through each other later: movers follow their scripts).
  double apart_m = 0.05;
};

// Every broken rule, one line each ("obstacles[3]: ..."); empty = valid.
// Also (6): the route starts at the start pose and ends at the goal.
std::vector<std::string> check_scenario(const Scenario& sc, const ScenarioCheckParams& p);

// Rule 1 for one obstacle: its smallest clearance to the start footprint
// over the checked interval (m, negative when it overlaps).
double start_clearance(const Scenario& sc, const ObstacleSpec& o, const ScenarioCheckParams& p);

// Rule 5: the gap between two obstacles where they start (m, negative
// when they overlap).
double start_gap(const ObstacleSpec& a, const ObstacleSpec& b);

// Where obstacle `o` rests for good, if it does (static: its position; a
// `once` mover: its last waypoint); false for anything that keeps moving.
bool final_rest(const ObstacleSpec& o, Vec2* at);

}  // namespace evade::sim
