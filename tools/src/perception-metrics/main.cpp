// perception-metrics LOG [--out FILE] [--config robot.yaml]
//                    [--obstacles CH] [--predictions CH]
// Scores a simulated run's tracking and prediction against SIM_TRUTH and
// prints one JSON object (rules: --help; lib/metrics/perception_metrics.h).
// Exit 0 with the JSON, 2 on a usage or configuration error, 1 when the
// log cannot be scored (no SIM_TRUTH).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bus/log.h"
#include "bus/process_main.h"
#include "config/robot_profile.h"
#include "metrics/perception_metrics.h"

int main(int argc, char** argv) {
  namespace metrics = evade::metrics;
  CLI::App app{"evade perception-metrics: tracking and prediction scored against SIM_TRUTH"};
  app.footer(metrics::perception_rules());
  std::string log, out, obstacles = "OBSTACLES", predictions = "OBSTACLE_PREDICTIONS";
  evade::bus::CommonOptions opts;
  app.add_option("log", log, "run log with SIM_TRUTH")->required()->check(CLI::ExistingFile);
  app.add_option("--out", out, "also write the JSON here");
  // --config: its perception_metrics section (default: robot.yaml beside LOG, else config/); --robot
  evade::bus::add_robot_options(app, opts, false);
  app.add_option("--obstacles", obstacles, "the tracker's channel");
  app.add_option("--predictions", predictions, "the predictor's channel");
  CLI11_PARSE(app, argc, argv);
  std::string config_path = opts.config_path;
  if (config_path.empty()) {
    const auto beside = std::filesystem::path(log).parent_path() / "robot.yaml";
    config_path = std::filesystem::exists(beside) ? beside.string() : evade::config::default_config_path();
  }
  metrics::PerceptionParams params;
  try {
    params = metrics::PerceptionParams::from_config(
        evade::config::load_robot_config(config_path, {opts.robot, ""}).section("perception_metrics"));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "perception-metrics: %s\n", e.what());
    return 2;
  }
  std::string json;
  try {
    json = metrics::perception_json(
        metrics::compute_perception(evade::bus::read_log(log), params, obstacles, predictions), params);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "perception-metrics: %s: %s\n", log.c_str(), e.what());
    return 1;
  }
  std::fputs(json.c_str(), stdout);
  if (!out.empty()) {
    std::ofstream f(out + ".tmp");
    f << json;
    f.close();
    if (!f) {
      std::fprintf(stderr, "perception-metrics: cannot write %s\n", out.c_str());
      return 2;
    }
    std::filesystem::rename(out + ".tmp", out);
  }
  return 0;
}
