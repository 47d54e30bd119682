// config-dump [--config FILE] [--robot NAME] [--scenario FILE]: the
// effective configuration (robot.yaml <- profile <- the scenario's own
// values, config/robot_profile.h), every value as its owner loads it,
// followed by the file and line it came from. Exit 2
// (one line naming file, line and key) when the configuration is wrong.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "sections.h"

int main(int argc, char** argv) {
  CLI::App app{"config-dump: the effective configuration with the source file and line of each value"};
  evade::bus::CommonOptions opts;
  evade::bus::add_robot_options(app, opts);  // --config, --robot, --scenario
  CLI11_PARSE(app, argc, argv);
  try {
    const std::string path = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
    const evade::config::Node root = evade::config::load_robot_config(path, {opts.robot, opts.scenario});
    std::fputs(evade::config_dump::dump(root).c_str(), stdout);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "config-dump: %s\n", e.what());
    return 2;
  }
  return 0;
}
