// tracker: ELEVATION_MAP -> OBSTACLES (paper III-B, obstacle parameterization).
#include "bus/process_main.h"
#include "tracking/tracker_core.h"

int main(int argc, char** argv) {
  return evade::bus::process_main(
      argc, argv, "tracker", [](CLI::App&) {},
      [](const evade::config::Node& root) { return evade::tracking::TrackerCore::from_config(root); });
}
