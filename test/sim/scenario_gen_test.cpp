// The scenario families generator: the same family and seed give the same
// bytes; every scene of every family over many seeds reads back, passes
// the validity rules and keeps each family's promises (doorway gap, hidden
// person, speeds, counts); the families file is read strictly; the random
// transforms and the geometry and checks behave as documented.
#include "sim/scenario_gen.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "config/robot_profile.h"
#include "sim/motion.h"
#include "sim/scenario_check.h"
#include "sim/scenario_gen_random.h"
#include "sim/scenario_geometry.h"
#include "sim/scenario_writer.h"

namespace evade::sim::gen {
namespace {

const std::string kRobotYaml = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";
const std::string kFamiliesYaml = std::string(EVADE_SOURCE_DIR) + "/config/scenario_families.yaml";
constexpr int kSeedsPerFamily = 200;

const RobotFacts& robot() {
  static const RobotFacts r = RobotFacts::from_config(config::load_robot_config(kRobotYaml));
  return r;
}
const FamilyParams& params() {
  static const FamilyParams p = FamilyParams::from_config(config::load_file(kFamiliesYaml), robot());
  return p;
}

// The file at `path` (called `name`) with `from` replaced by `to`, read by `load`: the
// ConfigError it gives ("" none); *line (if given) the line of `from`.
std::string error_with(const std::string& path, const std::string& name, const std::string& from, const std::string& to,
                       const std::function<void(const config::Node&)>& load, int* line = nullptr) {
  std::ifstream f(path);
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at == std::string::npos) return "";
  if (line)
    *line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  text.replace(at, from.size(), to);
  try {
    load(config::load_string(text, name));
  } catch (const config::ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string families_error(const std::string& from, const std::string& to) {
  return error_with(kFamiliesYaml, "families.yaml", from, to,
                    [](const config::Node& n) { FamilyParams::from_config(n, robot()); });
}

std::string robot_facts_error(const std::string& from, const std::string& to, int* line) {
  return error_with(
      kRobotYaml, "robot.yaml", from, to, [](const config::Node& n) { RobotFacts::from_config(n); }, line);
}

std::string lines(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& l : v) s += "  " + l + "\n";
  return s;
}

// Through FamilyParams' field list: the file loaded and written back is
// the file key by key (every key a field, every field a key), and a
// default-constructed FamilyParams is the file (its defaults cannot drift).
TEST(ScenarioGenConfig, TheFileWrittenBackAndTheCppDefaultsAreTheFile) {
  const config::Node root = config::load_file(kFamiliesYaml);
  const YAML::Node written = config::to_yaml(FamilyParams::from_config(root, robot()));
  const auto d = config::yaml_differences(written, root.yaml());
  EXPECT_TRUE(d.empty()) << "written (first) vs the file (second):\n" << lines(d);
  const auto drift = config::yaml_differences(config::to_yaml(FamilyParams{}), written);
  EXPECT_TRUE(drift.empty()) << "C++ default (first) vs the file (second):\n" << lines(drift);
}

// The facts come through the field lists of the sections' owners: the
// planner's range for reference_speed_mps (at most robot.max_v_mps) and
// lidar.mount.z_m's range apply, with file, line and key.
TEST(ScenarioGenConfig, RobotFactsAreReadThroughTheOwnersFieldLists) {
  EXPECT_DOUBLE_EQ(robot().reference_speed_mps, 0.8);
  EXPECT_DOUBLE_EQ(robot().step_max_m, 0.15);  // the larger of the map's two step thresholds
  EXPECT_DOUBLE_EQ(robot().lidar_height_m, 0.5);
  EXPECT_EQ(robot().lidar_model, "vlp16");
  EXPECT_EQ(robot().profile, "");
  const RobotFacts scout = RobotFacts::from_config(config::load_robot_config(kRobotYaml, {"scout2", ""}));
  EXPECT_EQ(scout.profile, "scout2");
  EXPECT_EQ(scout.lidar_model, "rs_helios");
  EXPECT_DOUBLE_EQ(scout.footprint_length_m, 0.93);
  int line = 0;
  std::string error = robot_facts_error("reference_speed_mps: 0.8 ", "reference_speed_mps: 1.5 ", &line);
  EXPECT_EQ(error,
            "robot.yaml:" + std::to_string(line) + ": key 'planner.reference_speed_mps': value 1.5 outside [0, 1]");
  error = robot_facts_error("z_m: 0.5 ", "z_m: 12 ", &line);
  EXPECT_EQ(error, "robot.yaml:" + std::to_string(line) + ": key 'lidar.mount.z_m': value 12 outside [0, 10]");
}

TEST(ScenarioGen, SameFamilyAndSeedGiveTheSameBytes) {
  for (const std::string& family : family_names()) {
    SCOPED_TRACE(family);
    std::set<std::string> texts;
    for (uint64_t seed : {1u, 2u, 3u, 1234567u}) {
      FamilyParams fresh = FamilyParams::from_config(config::load_file(kFamiliesYaml), robot());
      std::string a = generate(family, seed, params(), robot()).yaml;
      EXPECT_EQ(generate(family, seed, fresh, robot()).yaml, a);
      texts.insert(a);
    }
    EXPECT_EQ(texts.size(), 4u);  // different seeds, different scenes
  }
}

TEST(ScenarioGen, WritesTheSeedAndNameIntoTheFile) {
  Generated g = generate("crossing", 42, params(), robot());
  EXPECT_EQ(g.scenario.seed, 42u);
  EXPECT_EQ(g.scenario.name, "crossing_42");
  EXPECT_NE(g.yaml.find("\nseed: 42\n"), std::string::npos);
}

TEST(ScenarioGen, ImpossibleRulesEndInAnErrorNotAnEndlessLoop) {
  FamilyParams p = params();
  p.common.start_margin_m = 30.0;  // longer than any route: nothing may be placed anywhere
  p.common.max_attempts = 3;
  try {
    generate("crossing", 1, p, robot());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("family crossing, seed 1: no valid scene in 3 attempts"), std::string::npos)
        << e.what();
  }
}

TEST(ScenarioGen, UnknownFamilyAndHugeSeedAreErrors) {
  EXPECT_THROW(generate("stampede", 1, params(), robot()), std::invalid_argument);
  EXPECT_THROW(generate("crossing", uint64_t{1} << 63, params(), robot()), std::invalid_argument);
}

// What every family promises, checked on the scenario read back.
void expect_common(const Scenario& sc, const ScenarioCheckParams& check) {
  std::vector<std::string> problems = check_scenario(sc, check);
  EXPECT_TRUE(problems.empty()) << problems.front();
  EXPECT_DOUBLE_EQ(sc.footprint_length, robot().footprint_length_m);
  EXPECT_DOUBLE_EQ(sc.footprint_width, robot().footprint_width_m);
  double route = 0.0;
  for (size_t i = 1; i < sc.route.size(); ++i) route += geom::distance(sc.route[i - 1], sc.route[i]);
  EXPECT_GE(sc.duration_s, 2.0 * route / robot().reference_speed_mps + 10.0);  // a timeout is a stuck robot
  EXPECT_GE(route, params().common.route_length_m.lo - 1e-9);
  EXPECT_FALSE(sc.obstacles.empty());
  const geom::Outline start = geom::footprint(sc.start, sc.footprint_length, sc.footprint_width);
  for (const ObstacleSpec& o : sc.obstacles) {
    ObstacleState st = obstacle_state(o, 0.0);
    EXPECT_GE(geom::clearance(start, geom::obstacle_outline(o, st.x, st.y)), check.start_margin_m);
    EXPECT_GE(o.height, robot().step_max_m + params().common.min_visible_height_m);
  }
}

double fastest(const Scenario& sc) {
  double v = 0.0;
  for (const ObstacleSpec& o : sc.obstacles) v = std::max({v, o.speed, std::hypot(o.vx, o.vy)});
  return v;
}

int moving(const Scenario& sc) {
  int n = 0;
  for (const ObstacleSpec& o : sc.obstacles) n += o.motion != MotionKind::kStatic;
  return n;
}

// Doorway: two wall pieces across the way whose gap lets the robot through.
void expect_doorway(const Scenario& sc) {
  ASSERT_GE(sc.obstacles.size(), 2u);
  const ObstacleSpec &a = sc.obstacles[0], &b = sc.obstacles[1];
  ASSERT_EQ(a.shape, Shape::kBox);
  ASSERT_EQ(b.shape, Shape::kBox);
  double gap = (a.y - a.width / 2.0) - (b.y + b.width / 2.0);
  EXPECT_GE(gap, robot().footprint_width_m + params().common.passage_margin_m - 1e-9);
  EXPECT_LE(gap, params().doorway.gap_m.hi + 1e-9);
  // The route goes through the gap.
  double gap_y = (a.y - a.width / 2.0 + b.y + b.width / 2.0) / 2.0;
  bool through = false;
  for (size_t i = 1; i < sc.route.size(); ++i)
    through |= sc.route[i - 1].x < a.x && a.x < sc.route[i].x && std::fabs(sc.route[i].y - gap_y) < 1e-3;
  EXPECT_TRUE(through);
}

// Occlusion: the person waits where the vehicle hides it from the route
// 2 m before the vehicle's rear end, then crosses the route.
void expect_occlusion(const Scenario& sc) {
  const ObstacleSpec* person = nullptr;
  for (const ObstacleSpec& o : sc.obstacles)
    if (o.motion != MotionKind::kStatic) person = &o;
  ASSERT_NE(person, nullptr);
  const ObstacleSpec* car = nullptr;
  for (const ObstacleSpec& o : sc.obstacles)
    if (o.motion == MotionKind::kStatic &&
        (!car || std::hypot(o.x - person->x, o.y - person->y) < std::hypot(car->x - person->x, car->y - person->y)))
      car = &o;
  ASSERT_NE(car, nullptr);
  if (person->start_delay_s > 0.0) {
    geom::Outline body = geom::obstacle_outline(*car, car->x, car->y);
    Vec2 seen_from{car->x - car->length / 2.0 - 2.0, 0.0};
    EXPECT_TRUE(geom::segment_hits(seen_from, Vec2{person->x, person->y}, body));
  }
  EXPECT_LT(person->waypoints.back().y * person->y, 0.0);  // ends on the other side of the route
}

// When and where a `once` mover first reaches the route (y = 0), from its
// path: false if it never does.
bool reaches_route(const ObstacleSpec& o, double* t, double* x) {
  std::vector<Vec2> path{Vec2{o.x, o.y}};
  path.insert(path.end(), o.waypoints.begin(), o.waypoints.end());
  double s = 0.0;
  for (size_t i = 1; i < path.size(); ++i) {
    const Vec2 &a = path[i - 1], &b = path[i];
    double seg = geom::distance(a, b);
    if (a.y == 0.0 || (a.y > 0.0) != (b.y > 0.0)) {
      double f = a.y == 0.0 ? 0.0 : a.y / (a.y - b.y);
      *x = a.x + f * (b.x - a.x);
      *t = o.start_delay_s + (s + f * seg) / o.speed;
      return true;
    }
    s += seg;
  }
  return false;
}

// Crossing, fast_small and occlusion movers meet the route `lead_s`
// before the robot's nominal arrival there (reference speed from the
// start, plus the arrival lag), to the files' rounding.
void expect_timed(const Scenario& sc, const Range& lead) {
  for (const ObstacleSpec& o : sc.obstacles) {
    if (o.motion == MotionKind::kStatic) continue;
    double t = 0.0, x = 0.0;
    ASSERT_TRUE(reaches_route(o, &t, &x)) << o.id;
    double arrival = (x - sc.start.x) / robot().reference_speed_mps + params().common.arrival_lag_s;
    EXPECT_GE(arrival - t, lead.lo - 0.02) << o.id;
    EXPECT_LE(arrival - t, lead.hi + 0.02) << o.id;
    EXPECT_GE(x, sc.start.x + params().common.meet_from_start_m - 0.01) << o.id;
    EXPECT_LE(x, sc.goal.x - params().common.meet_before_goal_m + 0.01) << o.id;
  }
}

// Head-on walkers side by side (same start x and speed): the groups.
int walkers_abreast(const Scenario& sc) {
  int n = 0;
  for (size_t i = 0; i < sc.obstacles.size(); ++i)
    for (size_t j = i + 1; j < sc.obstacles.size(); ++j) {
      const ObstacleSpec &a = sc.obstacles[i], &b = sc.obstacles[j];
      if (a.shape == Shape::kCylinder && a.x == b.x && a.vx == b.vx && a.start_delay_s == b.start_delay_s) {
        EXPECT_GE(std::fabs(a.y - b.y), params().headon.group_spacing_m.lo - 1e-3);
        ++n;
      }
    }
  return n;
}

TEST(ScenarioGen, EverySceneOfEveryFamilyIsValid) {
  const ScenarioCheckParams check = check_params(params(), robot());
  for (const std::string& family : family_names()) {
    SCOPED_TRACE(family);
    std::map<int, int> attempts;
    int groups = 0;
    for (uint64_t seed = 1; seed <= kSeedsPerFamily; ++seed) {
      SCOPED_TRACE(seed);
      Generated g = generate(family, seed, params(), robot());
      Scenario sc = parse_scenario(g.yaml, "again.yaml");
      ASSERT_NO_FATAL_FAILURE(expect_common(sc, check));
      ++attempts[g.attempts];
      if (family == "doorway") {
        ASSERT_NO_FATAL_FAILURE(expect_doorway(sc));
      }
      if (family == "occlusion") {
        ASSERT_NO_FATAL_FAILURE(expect_occlusion(sc));
        ASSERT_NO_FATAL_FAILURE(expect_timed(sc, params().occlusion.lead_s));
      }
      if (family == "crossing") {
        ASSERT_NO_FATAL_FAILURE(expect_timed(sc, params().crossing.lead_s));
      }
      if (family == "fast_small") {
        ASSERT_NO_FATAL_FAILURE(expect_timed(sc, params().fast_small.lead_s));
        EXPECT_LE(fastest(sc), 3.0 + 1e-9);
        for (const ObstacleSpec& o : sc.obstacles) EXPECT_LE(o.height, params().shapes.dog.height_m.hi + 1e-9);
      }
      if (family == "headon") {
        groups += walkers_abreast(sc);
      }
      if (family == "crowd") {
        EXPECT_GE(moving(sc), params().crowd.walkers.lo);
        EXPECT_LE(moving(sc), params().crowd.walkers.hi);
      }
      if (family == "static_clutter") {
        EXPECT_EQ(moving(sc), 0);
      }
      for (const ObstacleSpec& o : sc.obstacles) {
        if (family == "overtaking") {
          EXPECT_GT(o.vx, robot().reference_speed_mps);
        }
        if (family == "headon") {
          EXPECT_LT(o.vx, 0.0);
        }
      }
    }
    if (family == "headon") {
      EXPECT_GT(groups, 10);  // groups abreast do occur
    }
    int first_try = attempts[1];
    EXPECT_GT(first_try, kSeedsPerFamily / 4) << "most scenes should not need redrawing";
  }
}

TEST(ScenarioGen, FamiliesFileIsReadStrictly) {
  // The error names the line of the misspelt key: the one after crossing's bike_share.
  std::ifstream f(kFamiliesYaml);
  int line = 0, bike_share_line = 0;
  for (std::string l; std::getline(f, l) && !bike_share_line;) {
    ++line;
    if (l == "    bike_share: 0.2") bike_share_line = line;
  }
  ASSERT_GT(bike_share_line, 0);
  EXPECT_EQ(families_error("    bike_share: 0.2\n", "    bike_share: 0.2\n    bikes: 3\n"),
            "families.yaml:" + std::to_string(bike_share_line + 1) + ": key 'families.crossing.bikes': unknown key");
  EXPECT_NE(
      families_error("gap_m: [0.61, 2.0]", "gap_m: [0.3, 0.5]").find("key 'families.doorway.gap_m': the widest gap"),
      std::string::npos);
  EXPECT_NE(families_error("ball: {radius_m: [0.11, 0.11]", "ball: {radius_m: [0.05, 0.11]")
                .find("key 'shapes.ball.radius_m': lowest height 0.1 m is not above"),
            std::string::npos);
  EXPECT_NE(families_error("lead_s: [-2.0, 2.0]", "lead_s: [2.0, -2.0]").find("lo <= hi"), std::string::npos);
  EXPECT_NE(families_error("movers: [1, 4]", "movers: [1.5, 4]").find("whole numbers"), std::string::npos);
  EXPECT_NE(families_error("crossing: 1.0, headon", "crossing: 1.0, doorway: 1.0, headon").find("unknown key"),
            std::string::npos);
}

TEST(ScenarioGenRng, TransformsAreThoseDocumented) {
  // The C++ standard fixes mt19937_64's 10000th output for the default seed.
  Rng r(std::mt19937_64::default_seed);
  double u = 0.0;
  for (int i = 0; i < 10000; ++i) u = r.unit();
  EXPECT_EQ(u, static_cast<double>(9981545732273789042ull >> 11) * 0x1.0p-53);
  Rng s(7);
  std::set<int> seen;
  double lo = 1.0, hi = 0.0, sum = 0.0;
  for (int i = 0; i < 20000; ++i) {
    double v = s.unit();
    lo = std::min(lo, v), hi = std::max(hi, v), sum += v;
    int k = s.integer(3, 6);
    ASSERT_GE(k, 3);
    ASSERT_LE(k, 6);
    seen.insert(k);
  }
  EXPECT_GE(lo, 0.0);
  EXPECT_LT(hi, 1.0);
  EXPECT_NEAR(sum / 20000, 0.5, 0.01);
  EXPECT_EQ(seen.size(), 4u);  // both ends included
}

TEST(ScenarioGeometry, ClearancesOfDiscsAndRectangles) {
  geom::Outline robot_at_origin = geom::rectangle(0, 0, 0, 0.4, 0.2);
  EXPECT_NEAR(geom::clearance(robot_at_origin, geom::disc(1.0, 0.0, 0.3)), 0.5, 1e-12);
  EXPECT_NEAR(geom::clearance(geom::disc(0.0, 1.0, 0.3), robot_at_origin), 0.6, 1e-12);
  EXPECT_LT(geom::clearance(robot_at_origin, geom::disc(0.1, 0.0, 0.3)), 0.0);
  EXPECT_NEAR(geom::clearance(robot_at_origin, geom::rectangle(1.2, 0, 0, 1.0, 1.0)), 0.5, 1e-12);
  // A square turned 45 deg: its corner points at the robot.
  EXPECT_NEAR(geom::clearance(robot_at_origin, geom::rectangle(1.2 + std::sqrt(0.5), 0, M_PI / 4, 1.0, 1.0)), 1.0,
              1e-9);
  EXPECT_LT(geom::clearance(robot_at_origin, geom::rectangle(0.3, 0.1, 0.3, 0.4, 0.4)), 0.0);
  EXPECT_TRUE(geom::segment_hits(Vec2{-3, 0.05}, Vec2{3, 0.05}, robot_at_origin));
  EXPECT_FALSE(geom::segment_hits(Vec2{-3, 0.15}, Vec2{3, 0.15}, robot_at_origin));
  EXPECT_TRUE(geom::segment_hits(Vec2{0, 0.25}, Vec2{0, 3}, geom::disc(0, 0, 0.3)));
}

const char* kBase = R"(name: t
duration_s: 60
robot:
  start: {x: -10.0, y: 0.0, yaw: 0.0}
  goal: {x: 10.0, y: 0.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
lidar: {model: vlp16, rate_hz: 10, height: 0.5, range_noise_std: 0.01}
obstacles:
)";

std::vector<std::string> problems_with(const std::string& obstacles) {
  ScenarioCheckParams p;
  p.min_height_m = 0.2;
  return check_scenario(parse_scenario(std::string(kBase) + obstacles, "t.yaml"), p);
}

TEST(ScenarioCheck, EachRuleCatchesItsCase) {
  EXPECT_TRUE(problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: 0.0, y: 3.0}\n").empty());
  // On the start footprint (which also leaves the robot no way out), or 0.2 m from it.
  std::vector<std::string> on_start =
      problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: -10.0, y: 0.0}\n");
  ASSERT_FALSE(on_start.empty());
  EXPECT_EQ(on_start[0], "obstacles[0]: comes -0.300 m from the robot's start footprint in the first 2.0 s");
  EXPECT_EQ(
      problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: -9.3, y: 0.0}\n"),
      std::vector<std::string>{"obstacles[0]: comes 0.190 m from the robot's start footprint in the first 2.0 s"});
  // Walks through the start pose 1.5 s in; 2.5 s in is allowed.
  EXPECT_EQ(problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: -10.0, y: 1.5, vx: 0, vy: -1}\n").size(),
            1u);
  EXPECT_TRUE(
      problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: -10.0, y: 3.5, vx: 0, vy: -1}\n").empty());
  EXPECT_EQ(problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: -10.0, y: 1.5, vx: 0, vy: -1, "
                          "start_delay_s: 0.5}\n")
                .size(),
            1u);
  EXPECT_TRUE(problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: -10.0, y: 1.5, vx: 0, vy: -1, "
                            "start_delay_s: 1.5}\n")
                  .empty());
  // Resting on the goal: as a static box, or at the end of a `once` walk.
  EXPECT_FALSE(problems_with("  - {shape: box, size: [1, 1, 1], x: 10.5, y: 0.0}\n").empty());
  EXPECT_FALSE(problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: 10.0, y: 5.0, "
                             "waypoints: [[10.0, 0.3]], speed: 1, mode: once}\n")
                   .empty());
  // Two obstacles starting inside each other.
  EXPECT_EQ(problems_with("  - {shape: cylinder, radius: 0.3, height: 1.7, x: 0.0, y: 3.0}\n"
                          "  - {shape: box, size: [1, 1, 1], x: 0.5, y: 3.5, vx: 1, vy: 0}\n"),
            std::vector<std::string>{"obstacles[0] and obstacles[1]: start -0.300 m apart (at least 0.050 m)"});
  // Too low to be seen.
  EXPECT_EQ(problems_with("  - {shape: cylinder, radius: 0.3, height: 0.15, x: 0.0, y: 3.0}\n").size(), 1u);
}

TEST(ScenarioCheck, ThePassageMustLetTheRobotThrough) {
  // A wall across the way (y from -20 to 20 reaches past the checked area)
  // with a gap of `gap` centred on the route.
  auto wall = [](double gap) {
    double half = 20.0, w = half - gap / 2.0;
    return "  - {shape: box, size: [0.2, " + yaml_number(w) + ", 1.5], x: 0.0, y: " + yaml_number(gap / 2.0 + w / 2.0) +
           "}\n  - {shape: box, size: [0.2, " + yaml_number(w) +
           ", 1.5], x: 0.0, y: " + yaml_number(-gap / 2.0 - w / 2.0) + "}\n";
  };
  EXPECT_TRUE(problems_with(wall(0.61)).empty());
  EXPECT_TRUE(problems_with(wall(1.5)).empty());
  std::vector<std::string> narrow = problems_with(wall(0.45));
  ASSERT_EQ(narrow.size(), 1u);
  EXPECT_EQ(narrow[0].rfind("passage:", 0), 0u) << narrow[0];
}

TEST(ScenarioWriter, ShippedScenariosReadBackTheSame) {
  std::filesystem::path dir = std::filesystem::path(EVADE_SOURCE_DIR) / "config" / "scenarios";
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".yaml") continue;
    SCOPED_TRACE(e.path().string());
    Scenario a = load_scenario(e.path().string());
    Scenario b = parse_scenario(scenario_yaml(a, {"written back"}, {}), "back.yaml");
    EXPECT_EQ(b.name, a.name);
    EXPECT_EQ(b.seed, a.seed);
    EXPECT_EQ(b.obstacles_start, a.obstacles_start);
    ASSERT_EQ(b.route.size(), a.route.size());
    ASSERT_EQ(b.obstacles.size(), a.obstacles.size());
    for (size_t i = 0; i < a.obstacles.size(); ++i) {
      const ObstacleSpec &x = a.obstacles[i], &y = b.obstacles[i];
      EXPECT_EQ(y.shape, x.shape);
      EXPECT_EQ(y.motion, x.motion);
      EXPECT_EQ(y.mode, x.mode);
      EXPECT_NEAR(y.yaw, x.yaw, 5e-5);
      for (double t : {0.0, 3.3, 17.0}) {
        ObstacleState p = obstacle_state(x, t), r = obstacle_state(y, t);
        EXPECT_NEAR(p.x, r.x, 1e-3) << i << " at " << t;
        EXPECT_NEAR(p.y, r.y, 1e-3) << i << " at " << t;
      }
    }
  }
  EXPECT_EQ(yaml_number(-0.00001), "0.0");
  EXPECT_EQ(yaml_number(-10.0), "-10.0");
  EXPECT_EQ(yaml_number(0.2635), "0.2635");
}

}  // namespace
}  // namespace evade::sim::gen
