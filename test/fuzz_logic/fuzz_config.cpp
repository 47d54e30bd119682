// Fuzzer: the YAML configuration loader and every process's from_config,
// and the scenario loader, on arbitrary text. Bad input must end in a
// config::ConfigError (one line: file, line, key); any other exception
// escaping, a crash or a sanitizer report is a bug. The first byte picks
// robot configuration or scenario.
#include <cstdlib>
#include <string>

#include "base/base_driver_core.h"
#include "bus/auth.h"
#include "bus/bus_guard.h"
#include "bus/clock_sync.h"
#include "config/config.h"
#include "config/safety.h"
#include "mapping/elevation_map.h"
#include "planning/params.h"
#include "prediction/params.h"
#include "route/route_publisher.h"
#include "sensing/lidar_driver_core.h"
#include "sim/scenario.h"
#include "sim/sim_core.h"
#include "tracking/tracker.h"

namespace {

void robot_config(const std::string& text) {
  using namespace evade;
  const config::Node root = config::load_string(text, "fuzz.yaml");
  const auto& known = config::robot_sections();
  for (const auto& k : root.keys())
    if (k != config::kTestConfigKey && std::find(known.begin(), known.end(), k) == known.end()) return;
  config::check_safety(root);
  auto each = [](const std::function<void()>& fn) {
    try {
      fn();
    } catch (const config::ConfigError&) {
    }
  };
  each([&] { base::BaseDriverParams::from_config(root); });
  each([&] { planning::PlannerParams::from_config(root); });
  each([&] { mapping::ElevationMapParams::from_config(root.section("elevation_map")); });
  each([&] { tracking::TrackerParams::from_config(root.section("tracker")); });
  each([&] { prediction::PredictorParams::from_config(root.section("predictor")); });
  each([&] { route::RouteParams::from_config(root.section("route")); });
  each([&] { sensing::LidarDriverParams::from_config(root); });
  each([&] { sim::SimParams::from_config(root); });
  each([&] { bus::BusGuardParams::from_config(root); });
  each([&] { bus::AuthParams::from_config(root); });
  each([&] { bus::ClockSyncParams::from_config(root); });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] % 2 == 0) {
      robot_config(text);
    } else {
      evade::sim::parse_scenario(text, "fuzz.yaml");
    }
  } catch (const evade::config::ConfigError&) {
    // the one way to refuse
  }
  return 0;
}
