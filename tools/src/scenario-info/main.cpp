// scenario-info SCENARIO.yaml [--start-pose] [--duration] [--name]
//               [--write-config OUT --config BASE]
// Reads a scenario (strictly: unknown keys are errors with file, line, key)
// and prints what the launchers need. --write-config writes a copy of the
// robot configuration whose LiDAR model and mount height are the
// scenario's, so the drivers decode what the simulator sends, and whose
// footprint is the scenario's robot's, so the planner keeps it clear.
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>

#include "config/config.h"
#include "sim/scenario.h"

int main(int argc, char** argv) {
  CLI::App app{"Print facts of a scenario file"};
  std::string path, out, base;
  bool start = false, duration = false, name = false;
  app.add_option("scenario", path, "scenario YAML")->required();
  app.add_flag("--start-pose", start, "print X,Y,YAW of the robot's start");
  app.add_flag("--duration", duration, "print duration_s");
  app.add_flag("--name", name, "print the scenario name");
  app.add_option("--write-config", out, "write a run configuration here");
  app.add_option("--config", base, "base robot configuration for --write-config");
  CLI11_PARSE(app, argc, argv);
  try {
    evade::sim::Scenario sc = evade::sim::load_scenario(path);
    if (start) std::printf("%.17g,%.17g,%.17g\n", sc.start.x, sc.start.y, sc.start.yaw);
    if (duration) std::printf("%.17g\n", sc.duration_s);
    if (name) std::printf("%s\n", sc.name.c_str());
    if (!out.empty()) {
      std::string base_path = base.empty() ? evade::config::default_config_path() : base;
      evade::config::load_robot_config(base_path);  // same checks as a process would make
      YAML::Node root = YAML::LoadFile(base_path);
      root["lidar"]["model"] = sc.lidar.model;
      root["lidar"]["mount"]["z_m"] = sc.lidar.height;
      root["robot"]["footprint_length_m"] = sc.footprint_length;  // the planner plans for the robot simulated
      root["robot"]["footprint_width_m"] = sc.footprint_width;
      std::ofstream f(out);
      f << "# Written by scenario-info from " << base_path << " for scenario " << sc.name << "\n" << root << "\n";
      if (!f) throw std::runtime_error("cannot write " + out);
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
