#include "scenario.h"

#include "config/config.h"

namespace evade::prediction::testing {

PredictorParams default_params() {
  const auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  return PredictorParams::from_config(root.section("predictor"));
}

}  // namespace evade::prediction::testing
