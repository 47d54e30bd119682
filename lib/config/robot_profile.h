// Robot profiles and the one merge rule of the robot configuration.
//
// The effective configuration of a run is, key by key,
//
//   robot.yaml (common)  <-  robots/<profile>.yaml  <-  the scenario's own values
//
// each level replacing the values it names and keeping the rest. A profile
// (config/robots/NAME.yaml, beside robot.yaml) is a partial robot.yaml: it
// may only name keys robot.yaml has. The scenario's own values are its
// `robot.footprint` {length, width} (-> robot.footprint_length_m /
// footprint_width_m), `lidar.model` (-> lidar.model) and `lidar.height`
// (-> lidar.mount.z_m), where it gives them. Maps merge key by key; a
// scalar or a list is replaced whole.
//
// The profile is `--robot NAME` or the scenario's `robot.profile`; both
// naming different robots is an error (one robot per run). Neither: no
// profile, robot.yaml alone.
//
// Every merged value keeps the file and line it came from (Provenance), so
// that a bad value is reported where it was written, e.g.
// `config/robots/scout2.yaml:12: key 'robot.max_v_mps': value 3 outside [0, 1.5]`.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "config/config.h"

namespace evade::config {

struct Provenance {
  std::string profile;  // the profile merged in ("" none)
  // Every value a profile or scenario replaced: the node, the file it came
  // from, its dotted key in robot.yaml.
  struct Value {
    YAML::Node node;
    std::string file;
    std::string key;
  };
  std::vector<Value> values;
  // The file a merged value came from; nullptr for one of the base file.
  const std::string* file_of(const YAML::Node& value) const;
};

struct RobotSelection {
  std::string profile;   // --robot NAME ("" none)
  std::string scenario;  // a scenario file whose own robot values go on top ("" none)
};

// robot.yaml <- profile <- scenario, then the checks of load_robot_config
// (known sections, config/safety.h). ConfigError for an unknown profile
// (naming the profiles there are), a profile key robot.yaml does not have,
// a profile that is not a map of maps, and --robot against the scenario's
// robot.profile.
Node load_robot_config(const std::string& path, const RobotSelection& selection);

// config/robots beside a robot.yaml, and the profile names found there.
std::string profiles_dir(const std::string& config_path);
std::vector<std::string> profile_names(const std::string& config_path);

// The one effective footprint and where it came from, as every process
// prints it at start: "footprint 0.93 x 0.70 m, profile scout2, source
// config/robots/scout2.yaml:9" (profile "none" without one).
struct Footprint {
  double length_m = 0.0;
  double width_m = 0.0;
  std::string profile;  // "none" without one
  std::string source;   // file:line of the length (and of the width, when elsewhere)
};
Footprint effective_footprint(const Node& root);
std::string footprint_line(const Node& root);

}  // namespace evade::config
