// scenario-info SCENARIO.yaml [--start-pose] [--duration] [--name] [--robot-profile]
//               [--write-config OUT [--config BASE] [--robot NAME]]
// Reads a scenario (strictly: unknown keys are errors with file, line, key)
// and prints what the launchers need. --write-config writes the run's
// effective robot configuration: BASE <- the robot profile (--robot, or the
// scenario's robot.profile) <- the scenario's own footprint and LiDAR model
// and height (config/robot_profile.h), so the drivers decode what the
// simulator sends and the planner keeps the simulated body clear; a header
// names every value that did not come from BASE and where it came from.
// The profile goes beside OUT too (robots/NAME.yaml), so that a process
// given OUT with --scenario (sim, route) merges the same values again.
// --robot-profile prints the profile the run uses (empty line: none).
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "sim/scenario.h"

namespace {

void write_config(const evade::config::Node& root, const std::string& base, const std::string& scenario,
                  const std::string& out) {
  std::ofstream f(out);
  f << "# Written by scenario-info: the effective robot configuration of scenario " << scenario << "\n"
    << "# " << base << " <- robot profile "
    << (root.provenance()->profile.empty() ? "(none)" : root.provenance()->profile) << " <- the scenario's own values\n"
    << "# " << evade::config::footprint_line(root) << "\n";
  for (const auto& v : root.provenance()->values)
    f << "#   " << v.key << ": " << YAML::Dump(v.node) << "  (" << v.file << ":" << v.node.Mark().line + 1 << ")\n";
  f << root.yaml() << "\n";
  if (!f) throw std::runtime_error("cannot write " + out);
  const std::string& profile = root.provenance()->profile;
  if (profile.empty()) return;
  namespace fs = std::filesystem;
  const fs::path from = fs::path(evade::config::profiles_dir(base)) / (profile + ".yaml");
  const fs::path to = fs::path(evade::config::profiles_dir(out)) / (profile + ".yaml");
  std::error_code ec;
  if (fs::equivalent(from, to, ec)) return;
  fs::create_directories(to.parent_path());
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Print facts of a scenario file"};
  std::string path, out;
  bool start = false, duration = false, name = false, profile = false;
  evade::bus::CommonOptions opts;
  app.add_option("scenario", path, "scenario YAML")->required();
  app.add_flag("--start-pose", start, "print X,Y,YAW of the robot's start");
  app.add_flag("--duration", duration, "print duration_s");
  app.add_flag("--name", name, "print the scenario name");
  app.add_flag("--robot-profile", profile, "print the robot profile of the run (--robot or the scenario's)");
  app.add_option("--write-config", out, "write the run's effective robot configuration here");
  evade::bus::add_robot_options(app, opts, false);  // --config BASE, --robot NAME
  CLI11_PARSE(app, argc, argv);
  try {
    evade::sim::Scenario sc = evade::sim::load_scenario(path);
    if (start) std::printf("%.17g,%.17g,%.17g\n", sc.start.x, sc.start.y, sc.start.yaw);
    if (duration) std::printf("%.17g\n", sc.duration_s);
    if (name) std::printf("%s\n", sc.name.c_str());
    if (profile || !out.empty()) {
      const std::string base = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
      const evade::config::Node root = evade::config::load_robot_config(base, {opts.robot, path});
      if (profile) std::printf("%s\n", root.provenance()->profile.c_str());
      if (!out.empty()) write_config(root, base, path, out);
    }
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "scenario-info: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scenario-info: %s\n", e.what());
    return 1;
  }
  return 0;
}
