// Logic fuzzer: the perception cores over random well-formed sequences
// (sequence.h); the first byte picks the core. elevation_map: ODOMETRY and
// LIDAR_POINTS; tracker: ELEVATION_MAP; predictor: OBSTACLES. Their outputs
// must stay finite (grid_map_t.elevation's "no data" NaN excepted).
#include "config/config.h"
#include "mapping/elevation_map_core.h"
#include "messages.h"
#include "prediction/predictor_core.h"
#include "tracking/tracker_core.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace evade;
  static const config::Node root = config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  static const prediction::PredictorParams predictor =
      prediction::PredictorParams::from_config(root.section("predictor"));
  fuzz::Bytes in(data, size);
  switch (in.u8() % 3) {
    case 0: {
      auto core = mapping::ElevationMapCore::from_config(root);
      fuzz::run_sequence(
          *core, {{"ODOMETRY", fuzz::odometry}, {"ODOMETRY", fuzz::odometry}, {"LIDAR_POINTS", fuzz::pointcloud}}, in,
          24);
      break;
    }
    case 1: {
      auto core = tracking::TrackerCore::from_config(root);
      fuzz::run_sequence(*core, {{"ELEVATION_MAP", fuzz::grid_map}}, in, 16);
      break;
    }
    default: {
      prediction::PredictorCore core(predictor);
      fuzz::run_sequence(core, {{"OBSTACLES", fuzz::obstacles}}, in, 32);
      break;
    }
  }
  return 0;
}
