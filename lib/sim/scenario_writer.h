// Writes a Scenario as a scenario YAML file (SPEC.md "Scenario file") that
// load_scenario() reads back to the same values. Numbers are written with
// at most 4 decimals (fixed notation, trailing zeros dropped): round the
// values to that before writing if the file must read back exactly.
#pragma once

#include <string>
#include <vector>

#include "sim/scenario.h"

namespace evade::sim {

// `header`: comment lines written first (without the "# "); `notes`: one
// comment line per obstacle written above it (empty: none).
std::string scenario_yaml(const Scenario& sc, const std::vector<std::string>& header,
                          const std::vector<std::string>& notes);

// v in fixed notation with at most 4 decimals, trailing zeros dropped
// ("1.5", "-10.0", "0.0"; never "-0.0").
std::string yaml_number(double v);

}  // namespace evade::sim
