// predictor: per-track 9-state Kalman filter with adaptive position noise and
// N-step predictions of uncertainty-inflated ellipses (paper section III-B).
// Reads OBSTACLES, writes OBSTACLE_PREDICTIONS; parameters: `predictor:` in config/robot.yaml.
#include "bus/process_main.h"
#include "prediction/predictor_core.h"

int main(int argc, char** argv) {
  using namespace evade;
  return bus::process_main(
      argc, argv, "predictor", nullptr,
      [](const config::Node& root) { return prediction::PredictorCore::from_config(root); },
      bus::ProcessOptions{{}, /*publishes_signed=*/true});
}
