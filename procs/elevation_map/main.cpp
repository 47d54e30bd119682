// elevation_map: LIDAR_POINTS + ODOMETRY -> ELEVATION_MAP (paper III-B, local map).
#include "bus/process_main.h"
#include "mapping/elevation_map_core.h"

int main(int argc, char** argv) {
  return evade::bus::process_main(
      argc, argv, "elevation_map", [](CLI::App&) {},
      [](const evade::config::Node& root) { return evade::mapping::ElevationMapCore::from_config(root); });
}
