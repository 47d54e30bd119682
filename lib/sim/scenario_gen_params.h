// Parameters of the scenario families (config/scenario_families.yaml) and
// the facts of the robot they are drawn for (config/robot.yaml). Both are
// read strictly: an unknown, missing or out-of-range key is a
// config::ConfigError naming file, line and key.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "config/config.h"
#include "config/fields.h"

namespace evade::sim::gen {

struct Range {
  double lo = 0.0;
  double hi = 0.0;
};
struct Count {
  int lo = 0;
  int hi = 0;
};

// What the families need to know about the robot and its stack.
struct RobotFacts {
  double footprint_length_m = 0.42;
  double footprint_width_m = 0.31;
  double reference_speed_mps = 0.8;  // planner.reference_speed_mps
  double lidar_height_m = 0.5;       // lidar.mount.z_m
  // Highest step the map lets pass (elevation_map.step_max_m and
  // blind_ground_step_max_m, the larger): lower obstacles are not seen.
  double step_max_m = 0.15;
  // The robot profile the configuration was merged with (config/
  // robot_profile.h; "" none): generated scenarios name it (robot.profile)
  // so that runs of them use the same robot.
  std::string profile;
  std::string lidar_model = "vlp16";  // lidar.model

  // Reads robot and lidar (config/robot_params.h), planner
  // (planning/params.h) and elevation_map (mapping/elevation_map.h), each
  // through its owner's field list, and the profile of the merge.
  static RobotFacts from_config(const config::Node& root);
};

// Defaults: config/scenario_families.yaml's values (test_scenario_gen
// checks that a default-constructed FamilyParams equals the file).
struct CommonParams {
  Range route_length_m{16.0, 24.0};
  double goal_tolerance_m = 0.3;
  double lidar_rate_hz = 10.0;
  double range_noise_std_m = 0.01;
  double duration_factor = 2.5;
  double duration_slack_s = 20.0;
  double arrival_lag_s = 0.4;
  double meet_from_start_m = 4.0;
  double meet_before_goal_m = 2.0;
  double start_margin_m = 0.3;
  double start_clear_time_s = 2.0;
  double goal_margin_m = 0.3;
  double passage_margin_m = 0.3;
  double min_visible_height_m = 0.05;
  int max_attempts = 200;
};

struct CylinderKind {  // walkers, joggers, balls, dogs, bins, posts
  Range radius_m, height_m, speed_mps;
};
struct BoxKind {  // bikes, vehicles, benches, planters
  Range length_m, width_m, height_m, speed_mps;
};
struct WallKind {  // the doorway's wall (its length is the family's)
  Range thickness_m, height_m;
};

struct Shapes {
  CylinderKind walker{{0.2, 0.3}, {1.5, 1.9}, {0.8, 1.6}};
  CylinderKind jogger{{0.2, 0.3}, {1.5, 1.9}, {2.0, 3.2}};
  CylinderKind ball{{0.11, 0.11}, {0.22, 0.22}, {1.0, 3.0}};  // as high as it is wide
  CylinderKind dog{{0.15, 0.3}, {0.3, 0.6}, {1.0, 3.0}};
  BoxKind bike{{1.6, 1.9}, {0.5, 0.7}, {1.4, 1.8}, {2.5, 5.0}};
  BoxKind parked_vehicle{{3.8, 5.0}, {1.7, 2.0}, {1.45, 2.2}, {}};
  WallKind wall{{0.15, 0.3}, {1.0, 2.5}};
};

struct CrossingParams {
  Count movers{1, 4};
  double bike_share = 0.2;
  Range crossing_angle_deg{60.0, 120.0}, lead_s{-2.0, 2.0}, approach_m{3.0, 8.0}, exit_m{3.0, 6.0};
};
struct HeadonParams {
  Count movers{1, 3};
  double bike_share = 0.35;
  double group_share = 0.3;  // of the walkers: a group abreast
  Count group_size{2, 3};
  Range group_spacing_m{0.7, 1.0};
  Range lateral_offset_m{-0.8, 0.8}, start_past_goal_m{-4.0, 6.0}, start_delay_s{0.0, 8.0};
};
struct OvertakingParams {
  Count movers{1, 3};
  double jogger_share = 0.3, bike_share = 0.4;
  Range walker_speed_mps{1.3, 1.8}, lateral_offset_m{0.7, 1.6}, start_behind_m{3.0, 12.0}, start_delay_s{0.0, 10.0};
};
struct CrowdParams {
  Count walkers{5, 15};
  Range street_width_m{4.0, 8.0}, crossing_angle_deg{70.0, 110.0}, crossing_share{0.3, 0.7}, along_length_m{4.0, 12.0},
      along_lateral_m{0.3, 2.0};
  double min_separation_m = 0.2;
};
struct DoorwayParams {
  Range gap_m{0.61, 2.0}, gap_offset_m{-1.0, 1.0}, wall_at{0.35, 0.65}, wall_half_length_m{4.0, 8.0};
  double straight_m = 2.0;
  double through_share = 0.7, same_way_share = 0.3;
  Range lead_s{-3.0, 3.0}, approach_m{3.0, 6.0}, exit_m{4.0, 8.0}, exit_aside_m{1.0, 4.0};
};
struct OcclusionParams {
  Count vehicles{1, 3};
  Range kerb_offset_m{0.6, 1.2}, vehicle_gap_m{1.0, 3.0}, hidden_from_front_m{0.5, 1.5};
  double behind_m = 0.15;
  double jogger_share = 0.3;
  Range lead_s{0.0, 2.0}, exit_m{2.0, 4.0};
};
struct FastSmallParams {
  Count movers{1, 4};
  double ball_share = 0.5;
  Range crossing_angle_deg{45.0, 135.0}, lead_s{-1.5, 1.5}, approach_m{3.0, 8.0}, exit_m{2.0, 6.0},
      zigzag_leg_m{1.0, 2.5}, zigzag_turn_deg{30.0, 70.0};
};
struct ClutterParams {
  Count items{4, 12};
  Range lateral_m{-2.5, 2.5}, vehicle_lateral_m{1.6, 3.0};
  double bin_share = 0.3, post_share = 0.25, bench_share = 0.15, planter_share = 0.2;
  CylinderKind bin{{0.2, 0.4}, {0.8, 1.1}, {}};
  CylinderKind post{{0.06, 0.1}, {0.9, 1.3}, {}};
  BoxKind bench{{1.4, 2.0}, {0.4, 0.6}, {0.45, 0.55}, {}};
  BoxKind planter{{0.6, 1.2}, {0.6, 1.2}, {0.4, 0.8}, {}};
};
struct MixedParams {
  Count families{2, 3};
  // Weight of each family it may draw from (family_names() order, 0 = never;
  // mixed and doorway, whose route bends, are never drawn; a family the
  // file does not list is left out).
  std::vector<std::pair<std::string, double>> weights{{"crossing", 1.0},  {"headon", 1.0},     {"overtaking", 1.0},
                                                      {"occlusion", 1.0}, {"fast_small", 1.0}, {"static_clutter", 1.0}};
};

struct FamilyParams {
  CommonParams common;
  Shapes shapes;
  CrossingParams crossing;
  HeadonParams headon;
  OvertakingParams overtaking;
  CrowdParams crowd;
  DoorwayParams doorway;
  OcclusionParams occlusion;
  FastSmallParams fast_small;
  ClutterParams static_clutter;
  MixedParams mixed;
  // Not in the file: the robot the families are checked against (the
  // doorway's narrowest gap, the lowest visible obstacle).
  RobotFacts robot;

  // The whole file, every key once (config/fields.h; scenario_gen_params.cpp
  // instantiates it for config::Loader and config::Writer).
  template <class V>
  void fields(V& v);

  // Reads the whole file (every section closed). `robot` is checked
  // against it: the doorway's gaps are drawn from what lets the robot
  // through (footprint width + passage margin) up (a range wholly below it
  // is an error), and no obstacle kind may be lower
  // than the map's step threshold + min_visible_height_m.
  static FamilyParams from_config(const config::Node& root, const RobotFacts& robot);
};

// The family names, in the order of the file.
const std::vector<std::string>& family_names();

// scenario_families.yaml found as the robot configuration is (config.h:
// config_file_candidates): ./config, the source tree, the installed sysconfdir.
std::string default_families_path();

}  // namespace evade::sim::gen
