// config-dump [--config FILE]: the effective configuration, every value as
// its owner loads it, followed by the file and line it came from. Exit 2
// (one line naming file, line and key) when the configuration is wrong.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "config/config.h"
#include "sections.h"

int main(int argc, char** argv) {
  CLI::App app{"config-dump: the effective configuration with the source file and line of each value"};
  std::string config_path = evade::config::default_config_path();
  app.add_option("--config", config_path, "robot configuration (default: config/robot.yaml)");
  CLI11_PARSE(app, argc, argv);
  try {
    const evade::config::Node root = evade::config::load_robot_config(config_path);
    std::fputs(evade::config_dump::dump(root).c_str(), stdout);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "config-dump: %s\n", e.what());
    return 2;
  }
  return 0;
}
