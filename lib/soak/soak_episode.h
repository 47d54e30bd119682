// One soak episode, in this process: a scenario of a family drawn with a
// seed (lib/sim/scenario_gen.h), the whole stack run over it in lockstep
// (lib/closedloop), and its outcome and contacts from the run's log
// (lib/metrics, without the reaction replays), as
// `tools/scenario-gen --family F --seed K` + `tools/run_scenario --lockstep
// --seed K --no-reaction` would give. Everything is built afresh per
// episode and destroyed after it, so what an episode leaks stays in the
// process and shows in its memory (tools/soak).
#pragma once

#include <cstdint>
#include <string>

#include "metrics/run_metrics.h"
#include "sim/scenario_gen_params.h"

namespace evade::soak {

// What every episode shares, loaded once. Throws config::ConfigError.
struct EpisodeInputs {
  std::string robot_path;  // the robot configuration (checked as a process would)
  std::string robot_text;  // its text merged with the profile, the base of each episode's run configuration
  sim::gen::RobotFacts robot;
  sim::gen::FamilyParams families;
  metrics::MetricsParams metrics;
  std::string mode;  // planner mode; empty: the configuration's
  // `profile`: a robot profile merged onto robot_path (config/robot_profile.h; "" none).
  static EpisodeInputs load(const std::string& robot_path, const std::string& families_path, const std::string& mode,
                            const std::string& profile = "");
};

struct EpisodeResult {
  std::string family;
  uint64_t seed = 0;
  std::string scenario_yaml;  // the generated scenario file
  std::string outcome;        // "goal", "duration" or "cap" (the lockstep safety cap)
  double sim_s = 0.0;
  int64_t events = 0;
  bool reached_goal = false;
  bool timed_out = false;
  bool success = false;
  int collisions_at_fault = 0;
  int collisions_not_at_fault = 0;
  double min_dist_m = 0.0;
};

// Runs one episode; the run's log (without LIDAR_POINTS, LIDAR_SCAN and
// ELEVATION_MAP, which the metrics do not read) goes to `log_path`,
// replacing any file there. Throws what the generator, the stack or the
// metrics throw.
EpisodeResult run_episode(const EpisodeInputs& in, const std::string& family, uint64_t seed,
                          const std::string& log_path);

}  // namespace evade::soak
