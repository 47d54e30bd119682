#include "sim/scenario_gen_params.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "config/robot_params.h"
#include "config/robot_profile.h"
#include "mapping/elevation_map.h"
#include "planning/params.h"

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

// The file's value kinds, as converters for the field lists below: a
// range [lo, hi] within [min, max] (sizes: lo > 0 too), a count of whole
// numbers within [0, max].
config::Converter<Range> range_in(double min, double max, bool sizes = false) {
  return {[=](const config::Node& n, const std::string& key) {
            std::vector<double> v = n.get_doubles(key, 2);
            if (v[0] > v[1]) n.fail(key, "expected [lo, hi] with lo <= hi");
            if (v[0] < min || v[1] > max) n.fail(key, "range outside [" + num(min) + ", " + num(max) + "]");
            if (sizes && !(v[0] > 0.0)) n.fail(key, "sizes must be greater than 0");
            return Range{v[0], v[1]};
          },
          [](const Range& r) {
            YAML::Node list(YAML::NodeType::Sequence);
            list.push_back(config::number_node(r.lo));
            list.push_back(config::number_node(r.hi));
            return list;
          }};
}
config::Converter<Range> length() { return range_in(0.0, kMaxLengthM); }
config::Converter<Range> signed_length() { return range_in(-kMaxLengthM, kMaxLengthM); }
config::Converter<Range> positive_length() { return range_in(0.0, kMaxLengthM, true); }
config::Converter<Range> time_range() { return range_in(-kMaxTimeS, kMaxTimeS); }
config::Converter<Range> speed() { return range_in(0.01, kMaxSpeedMps); }
config::Converter<Range> angle() { return range_in(10.0, 170.0); }
config::Converter<Range> distance() { return range_in(1.0, kMaxLengthM); }
const config::Range kShare = config::between(0.0, 1.0);

config::Converter<Count> count_in(int max) {
  return {[=](const config::Node& n, const std::string& key) {
            std::vector<double> v = n.get_doubles(key, 2);
            for (double d : v)
              if (d != static_cast<int>(d) || d < 0 || d > max)
                n.fail(key, "expected two whole numbers in [0, " + num(max) + "]");
            if (v[0] > v[1]) n.fail(key, "expected [lo, hi] with lo <= hi");
            return Count{static_cast<int>(v[0]), static_cast<int>(v[1])};
          },
          [](const Count& c) {
            YAML::Node list(YAML::NodeType::Sequence);
            list.push_back(config::number_node(c.lo));
            list.push_back(config::number_node(c.hi));
            return list;
          }};
}

// An obstacle kind lower than min_h (RobotFacts::step_max_m +
// common.min_visible_height_m) would be invisible to the LiDAR map.
template <class V>
void check_visible(V& v, const std::string& key, double lowest, double min_h) {
  v.rule(lowest >= min_h, key,
         "lowest height " + num(lowest) + " m is not above the map's step threshold + min_visible_height_m (" +
             num(min_h) + " m): the LiDAR map would not see it");
}

struct CylinderKeys {
  CylinderKind& k;
  bool moves, has_height;
  double min_h;
  template <class V>
  void fields(V& v) {
    v.convert("radius_m", k.radius_m, positive_length());
    if (has_height) {
      v.convert("height_m", k.height_m, positive_length());
      check_visible(v, "height_m", k.height_m.lo, min_h);
    } else {
      k.height_m = Range{2.0 * k.radius_m.lo, 2.0 * k.radius_m.hi};  // a ball: as high as it is wide
      check_visible(v, "radius_m", k.height_m.lo, min_h);
    }
    if (moves) v.convert("speed_mps", k.speed_mps, speed());
  }
};

struct BoxKeys {
  BoxKind& k;
  bool moves;
  double min_h;
  template <class V>
  void fields(V& v) {
    v.convert("length_m", k.length_m, positive_length());
    v.convert("width_m", k.width_m, positive_length());
    v.convert("height_m", k.height_m, positive_length());
    check_visible(v, "height_m", k.height_m.lo, min_h);
    if (moves) v.convert("speed_mps", k.speed_mps, speed());
  }
};

struct CommonKeys {
  CommonParams& c;
  template <class V>
  void fields(V& v) {
    v.convert("route_length_m", c.route_length_m, range_in(5.0, kMaxLengthM));
    v.field("goal_tolerance_m", c.goal_tolerance_m, config::between(0.05, 2.0));
    v.field("lidar_rate_hz", c.lidar_rate_hz, config::between(5.0, 20.0));
    v.field("range_noise_std_m", c.range_noise_std_m, config::between(0.0, 1.0));
    v.field("duration_factor", c.duration_factor, config::between(1.0, 20.0));
    v.field("duration_slack_s", c.duration_slack_s, config::between(0.0, kMaxTimeS));
    v.field("arrival_lag_s", c.arrival_lag_s, config::between(0.0, 10.0));
    v.field("meet_from_start_m", c.meet_from_start_m, config::between(0.0, kMaxLengthM));
    v.field("meet_before_goal_m", c.meet_before_goal_m, config::between(0.0, kMaxLengthM));
    v.rule(c.meet_from_start_m + c.meet_before_goal_m < c.route_length_m.lo, "meet_before_goal_m",
           "meet_from_start_m + meet_before_goal_m leave no room on the shortest route");
    v.field("start_margin_m", c.start_margin_m, config::between(0.0, 10.0));
    v.field("start_clear_time_s", c.start_clear_time_s, config::between(0.0, 60.0));
    v.field("goal_margin_m", c.goal_margin_m, config::between(0.0, 10.0));
    v.field("passage_margin_m", c.passage_margin_m, config::between(0.0, 10.0));
    v.field("min_visible_height_m", c.min_visible_height_m, config::between(0.0, 1.0));
    v.field("max_attempts", c.max_attempts, config::between(1, 100000));
  }
};

struct WallKeys {
  WallKind& k;
  double min_h;
  template <class V>
  void fields(V& v) {
    v.convert("thickness_m", k.thickness_m, positive_length());
    v.convert("height_m", k.height_m, positive_length());
    check_visible(v, "height_m", k.height_m.lo, min_h);
  }
};

struct ShapeKeys {
  Shapes& s;
  double min_h;
  template <class V>
  void fields(V& v) {
    CylinderKeys walker{s.walker, true, true, min_h}, jogger{s.jogger, true, true, min_h};
    CylinderKeys ball{s.ball, true, false, min_h}, dog{s.dog, true, true, min_h};
    BoxKeys bike{s.bike, true, min_h}, parked{s.parked_vehicle, false, min_h};
    WallKeys wall{s.wall, min_h};
    v.section("walker", walker);
    v.section("jogger", jogger);
    v.section("bike", bike);
    v.section("ball", ball);
    v.section("dog", dog);
    v.section("parked_vehicle", parked);
    v.section("wall", wall);
  }
};

}  // namespace

const std::vector<std::string>& family_names() {
  static const std::vector<std::string> names = {"crossing",  "headon",     "overtaking",     "crowd", "doorway",
                                                 "occlusion", "fast_small", "static_clutter", "mixed"};
  return names;
}

RobotFacts RobotFacts::from_config(const config::Node& root) {
  RobotFacts f;
  const auto robot = config::load<config::RobotParams>(root.section("robot"));
  f.footprint_length_m = robot.footprint_length_m;
  f.footprint_width_m = robot.footprint_width_m;
  const auto lidar = config::load<config::LidarParams>(root.section("lidar"));
  f.lidar_height_m = lidar.mount.z_m;
  f.lidar_model = lidar.model;
  // The planner's and the map's sections through their owners' lists.
  f.reference_speed_mps = planning::PlannerParams::from_config(root).reference_speed_mps;
  const auto map = mapping::ElevationMapParams::from_config(root.section("elevation_map"));
  f.step_max_m = std::max(map.step_max_m, map.blind_ground_step_max_m);
  if (root.provenance()) f.profile = root.provenance()->profile;
  return f;
}

namespace {

struct CrossingKeys {
  CrossingParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("movers", p.movers, count_in(100));
    v.field("bike_share", p.bike_share, kShare);
    v.convert("crossing_angle_deg", p.crossing_angle_deg, angle());
    v.convert("lead_s", p.lead_s, time_range());
    v.convert("approach_m", p.approach_m, distance());
    v.convert("exit_m", p.exit_m, distance());
  }
};

struct HeadonKeys {
  HeadonParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("movers", p.movers, count_in(100));
    v.field("bike_share", p.bike_share, kShare);
    v.field("group_share", p.group_share, kShare);
    v.convert("group_size", p.group_size, count_in(10));
    v.rule(p.group_size.lo >= 2, "group_size", "a group is at least 2");
    v.convert("group_spacing_m", p.group_spacing_m, positive_length());
    v.convert("lateral_offset_m", p.lateral_offset_m, signed_length());
    v.convert("start_past_goal_m", p.start_past_goal_m, signed_length());
    v.convert("start_delay_s", p.start_delay_s, range_in(0.0, kMaxTimeS));
  }
};

struct OvertakingKeys {
  OvertakingParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("movers", p.movers, count_in(100));
    v.field("jogger_share", p.jogger_share, kShare);
    v.field("bike_share", p.bike_share, kShare);
    v.rule(p.jogger_share + p.bike_share <= 1.0, "bike_share", "jogger_share + bike_share exceed 1");
    v.convert("walker_speed_mps", p.walker_speed_mps, speed());
    v.convert("lateral_offset_m", p.lateral_offset_m, length());
    v.convert("start_behind_m", p.start_behind_m, length());
    v.convert("start_delay_s", p.start_delay_s, range_in(0.0, kMaxTimeS));
  }
};

struct CrowdKeys {
  CrowdParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("walkers", p.walkers, count_in(200));
    v.convert("street_width_m", p.street_width_m, positive_length());
    v.convert("crossing_angle_deg", p.crossing_angle_deg, angle());
    v.convert("crossing_share", p.crossing_share, range_in(0.0, 1.0));
    v.convert("along_length_m", p.along_length_m, positive_length());
    v.convert("along_lateral_m", p.along_lateral_m, length());
    v.field("min_separation_m", p.min_separation_m, config::between(0.0, 5.0));
  }
};

struct DoorwayKeys {
  DoorwayParams& p;
  const CommonParams& c;
  const RobotFacts& robot;
  template <class V>
  void fields(V& v) {
    v.convert("gap_m", p.gap_m, positive_length());
    // Gaps narrower than this are left out when drawing (scenario_gen_places.cpp).
    const double narrowest = robot.footprint_width_m + c.passage_margin_m;
    v.rule(p.gap_m.hi >= narrowest, "gap_m",
           "the widest gap must be at least footprint width + passage_margin_m (" + num(narrowest) + " m)");
    v.convert("gap_offset_m", p.gap_offset_m, signed_length());
    v.convert("wall_at", p.wall_at, range_in(0.1, 0.9));
    v.convert("wall_half_length_m", p.wall_half_length_m, positive_length());
    v.field("straight_m", p.straight_m, config::between(0.5, 10.0));
    v.field("through_share", p.through_share, kShare);
    v.field("same_way_share", p.same_way_share, kShare);
    v.convert("lead_s", p.lead_s, time_range());
    v.convert("approach_m", p.approach_m, distance());
    v.convert("exit_m", p.exit_m, distance());
    v.convert("exit_aside_m", p.exit_aside_m, length());
  }
};

struct OcclusionKeys {
  OcclusionParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("vehicles", p.vehicles, count_in(20));
    v.rule(p.vehicles.lo >= 1, "vehicles", "at least one vehicle hides the person");
    v.convert("kerb_offset_m", p.kerb_offset_m, positive_length());
    v.convert("vehicle_gap_m", p.vehicle_gap_m, positive_length());
    v.convert("hidden_from_front_m", p.hidden_from_front_m, positive_length());
    v.field("behind_m", p.behind_m, config::between(0.0, 5.0));
    v.field("jogger_share", p.jogger_share, kShare);
    v.convert("lead_s", p.lead_s, time_range());
    v.convert("exit_m", p.exit_m, positive_length());
  }
};

struct FastSmallKeys {
  FastSmallParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("movers", p.movers, count_in(100));
    v.field("ball_share", p.ball_share, kShare);
    v.convert("crossing_angle_deg", p.crossing_angle_deg, angle());
    v.convert("lead_s", p.lead_s, time_range());
    v.convert("approach_m", p.approach_m, distance());
    v.convert("exit_m", p.exit_m, distance());
    v.convert("zigzag_leg_m", p.zigzag_leg_m, positive_length());
    v.convert("zigzag_turn_deg", p.zigzag_turn_deg, range_in(0.0, 85.0));
  }
};

struct ClutterKeys {
  ClutterParams& p;
  double min_h;
  template <class V>
  void fields(V& v) {
    v.convert("items", p.items, count_in(200));
    v.convert("lateral_m", p.lateral_m, signed_length());
    v.convert("vehicle_lateral_m", p.vehicle_lateral_m, length());
    v.field("bin_share", p.bin_share, kShare);
    v.field("post_share", p.post_share, kShare);
    v.field("bench_share", p.bench_share, kShare);
    v.field("planter_share", p.planter_share, kShare);
    v.rule(p.bin_share + p.post_share + p.bench_share + p.planter_share <= 1.0, "planter_share",
           "bin, post, bench and planter shares exceed 1");
    CylinderKeys bin{p.bin, false, true, min_h}, post{p.post, false, true, min_h};
    BoxKeys bench{p.bench, false, min_h}, planter{p.planter, false, min_h};
    v.section("bin", bin);
    v.section("post", post);
    v.section("bench", bench);
    v.section("planter", planter);
  }
};

// mixed.weights: a weight per family it may draw, in family_names() order;
// a family the file does not list is left out (mixed and doorway never
// drawn, so naming them is an unknown key).
config::Converter<std::vector<std::pair<std::string, double>>> weights() {
  return {[](const config::Node& n, const std::string& key) {
            const config::Node w = n.section(key);
            std::vector<std::pair<std::string, double>> out;
            for (const std::string& name : family_names()) {
              if (name == "mixed" || name == "doorway" || !w.has(name)) continue;
              out.emplace_back(name, w.get_double(name, 0.0, 1000.0));
            }
            w.close();
            return out;
          },
          [](const std::vector<std::pair<std::string, double>>& ws) {
            YAML::Node map(YAML::NodeType::Map);
            for (const auto& [name, weight] : ws) map[name] = config::number_node(weight);
            return map;
          }};
}

struct MixedKeys {
  MixedParams& p;
  template <class V>
  void fields(V& v) {
    v.convert("families", p.families, count_in(8));
    v.convert("weights", p.weights, weights());
    int drawn = 0;
    for (const auto& w : p.weights) drawn += w.second > 0.0 ? 1 : 0;
    v.rule(drawn >= p.families.hi, "families", "more families than weights above 0 in mixed.weights");
  }
};

struct FamiliesKeys {
  FamilyParams& p;
  double min_h;
  template <class V>
  void fields(V& v) {
    CrossingKeys crossing{p.crossing};
    HeadonKeys headon{p.headon};
    OvertakingKeys overtaking{p.overtaking};
    CrowdKeys crowd{p.crowd};
    DoorwayKeys doorway{p.doorway, p.common, p.robot};
    OcclusionKeys occlusion{p.occlusion};
    FastSmallKeys fast_small{p.fast_small};
    ClutterKeys clutter{p.static_clutter, min_h};
    MixedKeys mixed{p.mixed};
    v.section("crossing", crossing);
    v.section("headon", headon);
    v.section("overtaking", overtaking);
    v.section("crowd", crowd);
    v.section("doorway", doorway);
    v.section("occlusion", occlusion);
    v.section("fast_small", fast_small);
    v.section("static_clutter", clutter);
    v.section("mixed", mixed);
  }
};

}  // namespace

template <class V>
void FamilyParams::fields(V& v) {
  CommonKeys c{common};
  v.section("common", c);
  const double min_h = robot.step_max_m + common.min_visible_height_m;
  ShapeKeys s{shapes, min_h};
  v.section("shapes", s);
  FamiliesKeys f{*this, min_h};
  v.section("families", f);
}
template void FamilyParams::fields<config::Loader>(config::Loader&);
template void FamilyParams::fields<config::Writer>(config::Writer&);

FamilyParams FamilyParams::from_config(const config::Node& root, const RobotFacts& robot) {
  FamilyParams p;
  p.robot = robot;
  config::load_into(root, p);
  return p;
}

std::string default_families_path() { return config::find_config_file("scenario_families.yaml"); }

}  // namespace evade::sim::gen
