#include "sim/scenario_gen_params.h"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace evade::sim::gen {
namespace {

// Bounds every length, speed, time and share in the file must respect
// (anything outside is a typo, not a scene).
constexpr double kMaxLengthM = 100.0;
constexpr double kMaxSpeedMps = 10.0;
constexpr double kMaxTimeS = 600.0;

std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

Range read_range(const config::Node& n, const std::string& key, double min, double max) {
  std::vector<double> v = n.get_doubles(key, 2);
  if (v[0] > v[1]) n.fail(key, "expected [lo, hi] with lo <= hi");
  if (v[0] < min || v[1] > max) n.fail(key, "range outside [" + num(min) + ", " + num(max) + "]");
  return Range{v[0], v[1]};
}

Range length(const config::Node& n, const std::string& key) { return read_range(n, key, 0.0, kMaxLengthM); }
Range signed_length(const config::Node& n, const std::string& key) {
  return read_range(n, key, -kMaxLengthM, kMaxLengthM);
}
Range positive_length(const config::Node& n, const std::string& key) {
  Range r = length(n, key);
  if (!(r.lo > 0.0)) n.fail(key, "sizes must be greater than 0");
  return r;
}
Range time_range(const config::Node& n, const std::string& key) { return read_range(n, key, -kMaxTimeS, kMaxTimeS); }
double share(const config::Node& n, const std::string& key) { return n.get_double(key, 0.0, 1.0); }

Count read_count(const config::Node& n, const std::string& key, int max) {
  std::vector<double> v = n.get_doubles(key, 2);
  for (double d : v)
    if (d != static_cast<int>(d) || d < 0 || d > max)
      n.fail(key, "expected two whole numbers in [0, " + num(max) + "]");
  if (v[0] > v[1]) n.fail(key, "expected [lo, hi] with lo <= hi");
  return Count{static_cast<int>(v[0]), static_cast<int>(v[1])};
}

// An obstacle kind lower than min_h (RobotFacts::step_max_m +
// common.min_visible_height_m) would be invisible to the LiDAR map.
void check_visible(const config::Node& n, const std::string& key, double lowest, double min_h) {
  if (lowest < min_h)
    n.fail(key, "lowest height " + num(lowest) + " m is not above the map's step threshold + min_visible_height_m (" +
                    num(min_h) + " m): the LiDAR map would not see it");
}

CylinderKind cylinder(const config::Node& parent, const std::string& key, bool moves, bool has_height, double min_h) {
  config::Node n = parent.section(key);
  CylinderKind k;
  k.radius_m = positive_length(n, "radius_m");
  if (has_height) {
    k.height_m = positive_length(n, "height_m");
    check_visible(n, "height_m", k.height_m.lo, min_h);
  } else {
    k.height_m = Range{2.0 * k.radius_m.lo, 2.0 * k.radius_m.hi};  // a ball: as high as it is wide
    check_visible(n, "radius_m", k.height_m.lo, min_h);
  }
  if (moves) k.speed_mps = read_range(n, "speed_mps", 0.01, kMaxSpeedMps);
  n.close();
  return k;
}

BoxKind box(const config::Node& parent, const std::string& key, bool moves, double min_h) {
  config::Node n = parent.section(key);
  BoxKind k;
  k.length_m = positive_length(n, "length_m");
  k.width_m = positive_length(n, "width_m");
  k.height_m = positive_length(n, "height_m");
  check_visible(n, "height_m", k.height_m.lo, min_h);
  if (moves) k.speed_mps = read_range(n, "speed_mps", 0.01, kMaxSpeedMps);
  n.close();
  return k;
}

CommonParams read_common(const config::Node& root) {
  config::Node n = root.section("common");
  CommonParams c;
  c.route_length_m = read_range(n, "route_length_m", 5.0, kMaxLengthM);
  c.goal_tolerance_m = n.get_double("goal_tolerance_m", 0.05, 2.0);
  c.lidar_rate_hz = n.get_double("lidar_rate_hz", 5.0, 20.0);
  c.range_noise_std_m = n.get_double("range_noise_std_m", 0.0, 1.0);
  c.duration_factor = n.get_double("duration_factor", 1.0, 20.0);
  c.duration_slack_s = n.get_double("duration_slack_s", 0.0, kMaxTimeS);
  c.arrival_lag_s = n.get_double("arrival_lag_s", 0.0, 10.0);
  c.meet_from_start_m = n.get_double("meet_from_start_m", 0.0, kMaxLengthM);
  c.meet_before_goal_m = n.get_double("meet_before_goal_m", 0.0, kMaxLengthM);
  if (c.meet_from_start_m + c.meet_before_goal_m >= c.route_length_m.lo)
    n.fail("meet_before_goal_m", "meet_from_start_m + meet_before_goal_m leave no room on the shortest route");
  c.start_margin_m = n.get_double("start_margin_m", 0.0, 10.0);
  c.start_clear_time_s = n.get_double("start_clear_time_s", 0.0, 60.0);
  c.goal_margin_m = n.get_double("goal_margin_m", 0.0, 10.0);
  c.passage_margin_m = n.get_double("passage_margin_m", 0.0, 10.0);
  c.min_visible_height_m = n.get_double("min_visible_height_m", 0.0, 1.0);
  c.max_attempts = n.get_int("max_attempts", 1, 100000);
  n.close();
  return c;
}

Shapes read_shapes(const config::Node& root, double min_h) {
  config::Node n = root.section("shapes");
  Shapes s;
  s.walker = cylinder(n, "walker", true, true, min_h);
  s.jogger = cylinder(n, "jogger", true, true, min_h);
  s.bike = box(n, "bike", true, min_h);
  s.ball = cylinder(n, "ball", true, false, min_h);
  s.dog = cylinder(n, "dog", true, true, min_h);
  s.parked_vehicle = box(n, "parked_vehicle", false, min_h);
  config::Node w = n.section("wall");
  s.wall_thickness_m = positive_length(w, "thickness_m");
  s.wall_height_m = positive_length(w, "height_m");
  check_visible(w, "height_m", s.wall_height_m.lo, min_h);
  w.close();
  n.close();
  return s;
}

}  // namespace

const std::vector<std::string>& family_names() {
  static const std::vector<std::string> names = {"crossing",  "headon",     "overtaking",     "crowd", "doorway",
                                                 "occlusion", "fast_small", "static_clutter", "mixed"};
  return names;
}

RobotFacts RobotFacts::from_config(const config::Node& root) {
  RobotFacts f;
  config::Node robot = root.section("robot");
  f.footprint_length_m = robot.get_positive("footprint_length_m");
  f.footprint_width_m = robot.get_positive("footprint_width_m");
  f.reference_speed_mps = root.section("planner").get_positive("reference_speed_mps");
  f.lidar_height_m = root.section("lidar").section("mount").get<double>("z_m");
  config::Node map = root.section("elevation_map");
  f.step_max_m = std::max(map.get_positive("step_max_m"), map.get_positive("blind_ground_step_max_m"));
  return f;
}

namespace {

CrossingParams read_crossing(const config::Node& f) {
  config::Node n = f.section("crossing");
  CrossingParams p;
  p.movers = read_count(n, "movers", 100);
  p.bike_share = share(n, "bike_share");
  p.crossing_angle_deg = read_range(n, "crossing_angle_deg", 10.0, 170.0);
  p.lead_s = time_range(n, "lead_s");
  // The walker is on the gap's line 0.6 m either side of the wall (scenario_gen_places.cpp).
  p.approach_m = read_range(n, "approach_m", 1.0, kMaxLengthM);
  p.exit_m = read_range(n, "exit_m", 1.0, kMaxLengthM);
  n.close();
  return p;
}

HeadonParams read_headon(const config::Node& f) {
  config::Node n = f.section("headon");
  HeadonParams p;
  p.movers = read_count(n, "movers", 100);
  p.bike_share = share(n, "bike_share");
  p.group_share = share(n, "group_share");
  p.group_size = read_count(n, "group_size", 10);
  if (p.group_size.lo < 2) n.fail("group_size", "a group is at least 2");
  p.group_spacing_m = positive_length(n, "group_spacing_m");
  p.lateral_offset_m = signed_length(n, "lateral_offset_m");
  p.start_past_goal_m = signed_length(n, "start_past_goal_m");
  p.start_delay_s = read_range(n, "start_delay_s", 0.0, kMaxTimeS);
  n.close();
  return p;
}

OvertakingParams read_overtaking(const config::Node& f) {
  config::Node n = f.section("overtaking");
  OvertakingParams p;
  p.movers = read_count(n, "movers", 100);
  p.jogger_share = share(n, "jogger_share");
  p.bike_share = share(n, "bike_share");
  if (p.jogger_share + p.bike_share > 1.0) n.fail("bike_share", "jogger_share + bike_share exceed 1");
  p.walker_speed_mps = read_range(n, "walker_speed_mps", 0.01, kMaxSpeedMps);
  p.lateral_offset_m = length(n, "lateral_offset_m");
  p.start_behind_m = length(n, "start_behind_m");
  p.start_delay_s = read_range(n, "start_delay_s", 0.0, kMaxTimeS);
  n.close();
  return p;
}

CrowdParams read_crowd(const config::Node& f) {
  config::Node n = f.section("crowd");
  CrowdParams p;
  p.walkers = read_count(n, "walkers", 200);
  p.street_width_m = positive_length(n, "street_width_m");
  p.crossing_angle_deg = read_range(n, "crossing_angle_deg", 10.0, 170.0);
  p.crossing_share = read_range(n, "crossing_share", 0.0, 1.0);
  p.along_length_m = positive_length(n, "along_length_m");
  p.along_lateral_m = length(n, "along_lateral_m");
  p.min_separation_m = n.get_double("min_separation_m", 0.0, 5.0);
  n.close();
  return p;
}

DoorwayParams read_doorway(const config::Node& f, const CommonParams& c, const RobotFacts& robot) {
  config::Node n = f.section("doorway");
  DoorwayParams p;
  p.gap_m = positive_length(n, "gap_m");
  // Gaps the robot cannot pass are left out: a wider robot (a profile,
  // config/robots/) draws from the part of the range it fits through.
  const double passable = robot.footprint_width_m + c.passage_margin_m;
  p.gap_m.lo = std::max(p.gap_m.lo, passable);
  if (p.gap_m.hi < passable)
    n.fail("gap_m", "the widest gap must be at least footprint width + passage_margin_m (" + num(passable) + " m)");
  p.gap_offset_m = signed_length(n, "gap_offset_m");
  p.wall_at = read_range(n, "wall_at", 0.1, 0.9);
  p.wall_half_length_m = positive_length(n, "wall_half_length_m");
  p.straight_m = n.get_double("straight_m", 0.5, 10.0);
  p.through_share = share(n, "through_share");
  p.same_way_share = share(n, "same_way_share");
  p.lead_s = time_range(n, "lead_s");
  // The walker is on the gap's line 0.6 m either side of the wall (scenario_gen_places.cpp).
  p.approach_m = read_range(n, "approach_m", 1.0, kMaxLengthM);
  p.exit_m = read_range(n, "exit_m", 1.0, kMaxLengthM);
  p.exit_aside_m = length(n, "exit_aside_m");
  n.close();
  return p;
}

OcclusionParams read_occlusion(const config::Node& f) {
  config::Node n = f.section("occlusion");
  OcclusionParams p;
  p.vehicles = read_count(n, "vehicles", 20);
  if (p.vehicles.lo < 1) n.fail("vehicles", "at least one vehicle hides the person");
  p.kerb_offset_m = positive_length(n, "kerb_offset_m");
  p.vehicle_gap_m = positive_length(n, "vehicle_gap_m");
  p.hidden_from_front_m = positive_length(n, "hidden_from_front_m");
  p.behind_m = n.get_double("behind_m", 0.0, 5.0);
  p.jogger_share = share(n, "jogger_share");
  p.lead_s = time_range(n, "lead_s");
  p.exit_m = positive_length(n, "exit_m");
  n.close();
  return p;
}

FastSmallParams read_fast_small(const config::Node& f) {
  config::Node n = f.section("fast_small");
  FastSmallParams p;
  p.movers = read_count(n, "movers", 100);
  p.ball_share = share(n, "ball_share");
  p.crossing_angle_deg = read_range(n, "crossing_angle_deg", 10.0, 170.0);
  p.lead_s = time_range(n, "lead_s");
  // The walker is on the gap's line 0.6 m either side of the wall (scenario_gen_places.cpp).
  p.approach_m = read_range(n, "approach_m", 1.0, kMaxLengthM);
  p.exit_m = read_range(n, "exit_m", 1.0, kMaxLengthM);
  p.zigzag_leg_m = positive_length(n, "zigzag_leg_m");
  p.zigzag_turn_deg = read_range(n, "zigzag_turn_deg", 0.0, 85.0);
  n.close();
  return p;
}

ClutterParams read_clutter(const config::Node& f, double min_h) {
  config::Node n = f.section("static_clutter");
  ClutterParams p;
  p.items = read_count(n, "items", 200);
  p.lateral_m = signed_length(n, "lateral_m");
  p.vehicle_lateral_m = length(n, "vehicle_lateral_m");
  p.bin_share = share(n, "bin_share");
  p.post_share = share(n, "post_share");
  p.bench_share = share(n, "bench_share");
  p.planter_share = share(n, "planter_share");
  if (p.bin_share + p.post_share + p.bench_share + p.planter_share > 1.0)
    n.fail("planter_share", "bin, post, bench and planter shares exceed 1");
  p.bin = cylinder(n, "bin", false, true, min_h);
  p.post = cylinder(n, "post", false, true, min_h);
  p.bench = box(n, "bench", false, min_h);
  p.planter = box(n, "planter", false, min_h);
  n.close();
  return p;
}

MixedParams read_mixed(const config::Node& f) {
  config::Node n = f.section("mixed");
  MixedParams p;
  p.families = read_count(n, "families", 8);
  config::Node w = n.section("weights");
  double total = 0.0;
  for (const std::string& name : family_names()) {
    if (name == "mixed" || name == "doorway" || !w.has(name)) continue;
    double weight = w.get_double(name, 0.0, 1000.0);
    p.weights.emplace_back(name, weight);
    total += weight > 0.0 ? 1.0 : 0.0;
  }
  w.close();
  if (total < p.families.hi) n.fail("families", "more families than weights above 0 in mixed.weights");
  n.close();
  return p;
}

}  // namespace

FamilyParams FamilyParams::from_config(const config::Node& root, const RobotFacts& robot) {
  FamilyParams p;
  p.common = read_common(root);
  const double min_h = robot.step_max_m + p.common.min_visible_height_m;
  p.shapes = read_shapes(root, min_h);
  config::Node f = root.section("families");
  p.crossing = read_crossing(f);
  p.headon = read_headon(f);
  p.overtaking = read_overtaking(f);
  p.crowd = read_crowd(f);
  p.doorway = read_doorway(f, p.common, robot);
  p.occlusion = read_occlusion(f);
  p.fast_small = read_fast_small(f);
  p.static_clutter = read_clutter(f, min_h);
  p.mixed = read_mixed(f);
  f.close();
  root.close();
  return p;
}

std::string default_families_path() { return config::find_config_file("scenario_families.yaml"); }

}  // namespace evade::sim::gen
