#include "soak/soak_episode.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bus/log.h"
#include "closedloop/closed_loop.h"
#include "closedloop/run_monitor.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "sim/scenario_gen.h"

namespace evade::soak {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw config::ConfigError(path + ":0: key '': cannot open file");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The run configuration of a scenario, as `scenario-info --write-config`
// writes it: the base with the scenario's LiDAR model and mount height.
config::Node run_config(const EpisodeInputs& in, const sim::Scenario& sc) {
  YAML::Node root = YAML::Load(in.robot_text);
  root["lidar"]["model"] = sc.lidar.model;
  root["lidar"]["mount"]["z_m"] = sc.lidar.height;
  YAML::Emitter out;
  out << root;
  return config::load_string(out.c_str(), in.robot_path + " (for " + sc.name + ")");
}

const char* outcome_name(int outcome) {
  if (outcome == closedloop::RunMonitor::kGoal) return "goal";
  if (outcome == closedloop::RunMonitor::kDuration) return "duration";
  return "cap";
}

}  // namespace

EpisodeInputs EpisodeInputs::load(const std::string& robot_path, const std::string& families_path,
                                  const std::string& mode, const std::string& profile) {
  EpisodeInputs in;
  in.robot_path = robot_path;
  const config::Node root = config::load_robot_config(robot_path, {profile, ""});
  if (profile.empty()) {
    in.robot_text = read_text(robot_path);
  } else {
    YAML::Emitter merged;
    merged << root.yaml();
    in.robot_text = merged.c_str();
  }
  in.robot = sim::gen::RobotFacts::from_config(root);
  in.families = sim::gen::FamilyParams::from_config(config::load_file(families_path), in.robot);
  in.metrics = metrics::MetricsParams::from_config(root.section("metrics"));
  in.mode = mode;
  return in;
}

EpisodeResult run_episode(const EpisodeInputs& in, const std::string& family, uint64_t seed,
                          const std::string& log_path) {
  EpisodeResult r;
  r.family = family;
  r.seed = seed;
  const sim::gen::Generated g = sim::gen::generate(family, seed, in.families, in.robot);
  r.scenario_yaml = g.yaml;
  const config::Node root = run_config(in, g.scenario);
  closedloop::LockstepRun run;
  run.seed = seed;
  run.planner_mode = in.mode;
  run.unlogged = {"LIDAR_POINTS", "LIDAR_SCAN", "ELEVATION_MAP"};
  std::filesystem::remove(log_path);
  closedloop::LockstepResult lr;
  {
    closedloop::ClosedLoop loop(root, g.scenario, run);
    bus::LogWriter log(log_path);
    lr = loop.run(&log);
  }
  r.outcome = outcome_name(lr.outcome);
  r.sim_s = lr.sim_s;
  r.events = lr.events;
  const metrics::RunMetrics m = metrics::compute_metrics(bus::read_log(log_path), in.metrics);
  r.reached_goal = m.reached_goal;
  r.timed_out = m.timed_out;
  r.success = m.success;
  r.collisions_at_fault = m.collisions_at_fault;
  r.collisions_not_at_fault = m.collisions_not_at_fault;
  r.min_dist_m = m.min_dist_m;
  return r;
}

}  // namespace evade::soak
