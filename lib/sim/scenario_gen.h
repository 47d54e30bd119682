// Randomized scenario families for closed-loop benchmarks (issue 17): a
// family name and a seed give one scenario, the same bytes every time.
// Every scene is drawn from the ranges in config/scenario_families.yaml
// (table: lib/sim/README.md) for the robot of config/robot.yaml, written
// as a scenario YAML, read back with parse_scenario() and checked with
// check_scenario() (scenario_check.h); a scene that fails a check is
// redrawn from the same random stream, up to common.max_attempts times.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/scenario.h"
#include "sim/scenario_check.h"
#include "sim/scenario_gen_params.h"

namespace evade::sim::gen {

struct Generated {
  std::string yaml;   // the scenario file
  Scenario scenario;  // `yaml` read back
  int attempts = 0;   // scenes drawn, the last one kept
};

// Throws std::invalid_argument for a family not in family_names() or a
// seed above 2^63 - 1 (what a scenario file holds), and
// std::runtime_error when max_attempts scenes all fail a check (naming
// the last scene's failures).
Generated generate(const std::string& family, uint64_t seed, const FamilyParams& p, const RobotFacts& robot);

// The checks every generated scene passes, from the families' parameters.
ScenarioCheckParams check_params(const FamilyParams& p, const RobotFacts& robot);

}  // namespace evade::sim::gen
