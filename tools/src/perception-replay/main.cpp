// perception-replay LOG [--config robot.yaml] [--robot NAME] [--out FILE] [--log-out OUT.lcmlog]
// Open-loop perception yardstick: the tracker and predictor cores of this
// build and configuration run over a simulated run's logged ELEVATION_MAP
// and OCCLUSIONS (in process, on the log's time), their OBSTACLES and
// OBSTACLE_PREDICTIONS take the logged ones' place, and the result is
// scored against SIM_TRUTH exactly as perception-metrics scores a run (same
// JSON). The robot's path is the logged one, so two trackers are compared
// on the same views. With the configuration and code of the run it prints
// the run's own perception-metrics JSON.
// Exit 0 with the JSON, 2 on a usage or configuration error, 1 when the log
// cannot be scored.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "bus/log.h"
#include "bus/log_replay.h"
#include "bus/process_main.h"
#include "config/robot_profile.h"
#include "metrics/perception_metrics.h"
#include "prediction/predictor_core.h"
#include "tracking/tracker_core.h"

namespace {

// The log with its OBSTACLES and OBSTACLE_PREDICTIONS replaced by what the
// configured cores publish from its maps.
std::vector<evade::bus::LogEvent> retracked(const std::vector<evade::bus::LogEvent>& run,
                                            const evade::config::Node& root) {
  auto tracker = evade::tracking::TrackerCore::from_config(root);
  auto predictor = evade::prediction::PredictorCore::from_config(root);
  evade::bus::ReplayOptions opt;
  opt.channels = {"ELEVATION_MAP", "OCCLUSIONS"};
  opt.keep_health = false;
  std::vector<evade::bus::LogEvent> out = evade::bus::replay({tracker.get(), predictor.get()}, run, opt);
  for (const auto& e : run)
    if (e.channel != "OBSTACLES" && e.channel != "OBSTACLE_PREDICTIONS") out.push_back(e);
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
  return out;
}

bool write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  return bool(f);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade perception-replay: this build's tracker and predictor over a run's maps, scored"};
  std::string log, out, log_out;
  evade::bus::CommonOptions opts;
  app.add_option("log", log, "run log with ELEVATION_MAP and SIM_TRUTH")->required()->check(CLI::ExistingFile);
  app.add_option("--out", out, "also write the JSON here");
  app.add_option("--log-out", log_out, "also write the replaced log here");
  evade::bus::add_robot_options(app, opts, false);  // --config (default: the repository's), --robot
  CLI11_PARSE(app, argc, argv);
  const std::string config_path = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
  try {
    const auto root = evade::config::load_robot_config(config_path, {opts.robot, ""});
    const auto params = evade::metrics::PerceptionParams::from_config(root.section("perception_metrics"));
    const auto events = retracked(evade::bus::read_log(log), root);
    if (!log_out.empty()) evade::bus::write_log(log_out, events);
    const std::string json =
        evade::metrics::perception_json(evade::metrics::compute_perception(events, params), params);
    std::fputs(json.c_str(), stdout);
    if (!out.empty() && !write_text(out, json)) {
      std::fprintf(stderr, "perception-replay: cannot write %s\n", out.c_str());
      return 2;
    }
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "perception-replay: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "perception-replay: %s: %s\n", log.c_str(), e.what());
    return 1;
  }
  return 0;
}
