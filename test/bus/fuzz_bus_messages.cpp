// Fuzz target: arbitrary bytes arriving on every evade channel. The first
// byte picks the channel; the rest is delivered to a core subscribed to
// every message type, and decoded generically (lcmlog-export's path).
// Nothing may crash, hang or allocate beyond the message; every rejected
// message must be counted as malformed.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "bus/core.h"
#include "bus/lcm_schema.h"
#include "evade/base_status_t.hpp"
#include "evade/cmd_vel_t.hpp"
#include "evade/grid_map_t.hpp"
#include "evade/health_t.hpp"
#include "evade/lidar_scan_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "evade/sim_truth_t.hpp"

namespace {

class EveryType : public evade::bus::Core {
 public:
  EveryType() : Core("fuzz") {
    sub<evade::pointcloud_t>("LIDAR_POINTS");
    sub<evade::lidar_scan_t>("LIDAR_SCAN");
    sub<evade::odometry_t>("ODOMETRY");
    sub<evade::grid_map_t>("ELEVATION_MAP");
    sub<evade::obstacle_list_t>("OBSTACLES");
    sub<evade::prediction_list_t>("OBSTACLE_PREDICTIONS");
    sub<evade::path_t>("ROUTE");
    sub<evade::plan_t>("PLAN");
    sub<evade::cmd_vel_t>("CMD_VEL");
    sub<evade::base_status_t>("BASE_STATUS");
    sub<evade::sim_truth_t>("SIM_TRUTH");
    sub<evade::health_t>("HEALTH");
  }
  std::vector<std::string> names;
  int64_t handled = 0;

 private:
  template <class Msg>
  void sub(const std::string& ch) {
    names.push_back(ch);
    subscribe<Msg>(ch, [this](const Msg&) { ++handled; });
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static EveryType core;
  if (size < 1) return 0;
  const std::string& ch = core.names[data[0] % core.names.size()];
  const int64_t before = core.handled;
  const bool ok = core.deliver(ch, data + 1, size - 1, 0);
  // A message is either handled or rejected, never both or neither.
  if (ok != (core.handled == before + 1)) std::abort();
  auto v = evade::bus::LcmSchema::evade().decode(data + 1, size - 1);
  if (v) (void)evade::bus::to_json(*v);
  // The structural check and the generic decoder agree.
  if (static_cast<bool>(v) != evade::bus::LcmSchema::evade().check(data + 1, size - 1)) std::abort();
  return 0;
}
