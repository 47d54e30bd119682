// Parameters of the scenario families (config/scenario_families.yaml) and
// the facts of the robot they are drawn for (config/robot.yaml). Both are
// read strictly: an unknown, missing or out-of-range key is a
// config::ConfigError naming file, line and key.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "config/config.h"

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
  // so that runs of them use the same robot. Set by the caller.
  std::string profile;
  std::string lidar_model = "vlp16";  // lidar.model, set by the caller likewise

  // Reads robot, planner, lidar.mount and elevation_map (shared sections,
  // not closed).
  static RobotFacts from_config(const config::Node& root);
};

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
struct BoxKind {  // bikes, vehicles, benches, planters, walls
  Range length_m, width_m, height_m, speed_mps;
};

struct Shapes {
  CylinderKind walker, jogger, ball, dog;
  BoxKind bike, parked_vehicle;
  Range wall_thickness_m, wall_height_m;
};

struct CrossingParams {
  Count movers;
  double bike_share = 0.0;
  Range crossing_angle_deg, lead_s, approach_m, exit_m;
};
struct HeadonParams {
  Count movers;
  double bike_share = 0.0;
  double group_share = 0.0;  // of the walkers: a group abreast
  Count group_size;
  Range group_spacing_m;
  Range lateral_offset_m, start_past_goal_m, start_delay_s;
};
struct OvertakingParams {
  Count movers;
  double jogger_share = 0.0, bike_share = 0.0;
  Range walker_speed_mps, lateral_offset_m, start_behind_m, start_delay_s;
};
struct CrowdParams {
  Count walkers;
  Range street_width_m, crossing_angle_deg, crossing_share, along_length_m, along_lateral_m;
  double min_separation_m = 0.2;
};
struct DoorwayParams {
  Range gap_m, gap_offset_m, wall_at, wall_half_length_m;
  double straight_m = 2.0;
  double through_share = 0.0, same_way_share = 0.0;
  Range lead_s, approach_m, exit_m, exit_aside_m;
};
struct OcclusionParams {
  Count vehicles;
  Range kerb_offset_m, vehicle_gap_m, hidden_from_front_m;
  double behind_m = 0.15;
  double jogger_share = 0.0;
  Range lead_s, exit_m;
};
struct FastSmallParams {
  Count movers;
  double ball_share = 0.0;
  Range crossing_angle_deg, lead_s, approach_m, exit_m, zigzag_leg_m, zigzag_turn_deg;
};
struct ClutterParams {
  Count items;
  Range lateral_m, vehicle_lateral_m;
  double bin_share = 0.0, post_share = 0.0, bench_share = 0.0, planter_share = 0.0;
  CylinderKind bin, post;
  BoxKind bench, planter;
};
struct MixedParams {
  Count families;
  // Weight of each family it may draw from (family_names() order, 0 = never;
  // mixed and doorway, whose route bends, are never drawn).
  std::vector<std::pair<std::string, double>> weights;
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

  // Reads the whole file (every section closed). `robot` is checked
  // against it: the doorway's gaps start at what lets the robot through
  // (footprint width + passage margin; the range's lower end is raised to
  // it, and a range wholly below it is an error), and no obstacle kind may be lower
  // than the map's step threshold + min_visible_height_m.
  static FamilyParams from_config(const config::Node& root, const RobotFacts& robot);
};

// The family names, in the order of the file.
const std::vector<std::string>& family_names();

// scenario_families.yaml found as the robot configuration is (config.h:
// config_file_candidates): ./config, the source tree, the installed sysconfdir.
std::string default_families_path();

}  // namespace evade::sim::gen
