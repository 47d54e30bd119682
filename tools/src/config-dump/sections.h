// Every section of the robot configuration with the params struct whose
// field list reads it (config/fields.h): what tools/config-dump prints and
// what the per-section test compares with config/robot.yaml.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "config/config.h"

namespace evade::config_dump {

struct Section {
  std::string name;  // the top-level key in robot.yaml
  // The section's values as its owner loads them from the whole
  // configuration (its from_config, every check applied), keyed as the YAML.
  std::function<YAML::Node(const config::Node& root)> load;
  // The values of a default-constructed struct (the C++ defaults).
  std::function<YAML::Node()> defaults;
};

// In robot.yaml's order; one per name of config::robot_sections().
const std::vector<Section>& sections();

// The effective configuration: each section loaded by its owner and
// written with the source file and line of every value.
std::string dump(const config::Node& root);

}  // namespace evade::config_dump
