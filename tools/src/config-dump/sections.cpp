#include "sections.h"

#include <health_board.h>
#include <world_state.h>

#include "base/base_driver_core.h"
#include "bus/auth.h"
#include "bus/bus_guard.h"
#include "closedloop/lockstep_params.h"
#include "config/fields.h"
#include "config/robot_params.h"
#include "mapping/elevation_map.h"
#include "metrics/perception_metrics.h"
#include "metrics/run_metrics.h"
#include "planning/params.h"
#include "prediction/params.h"
#include "route/route_publisher.h"
#include "sensing/lidar_driver_core.h"
#include "sim/sim_core.h"
#include "teleop/teleop_core.h"
#include "tracking/tracker.h"

namespace evade::config_dump {
namespace {

// A section read by T's field list alone.
template <class T>
Section plain(const std::string& name) {
  return {name, [name](const config::Node& root) { return config::to_yaml(config::load<T>(root.section(name))); },
          [] { return config::to_yaml(T{}); }};
}

// A section whose owner's from_config reads the whole configuration.
template <class T>
Section from_root(const std::string& name) {
  return {name, [](const config::Node& root) { return config::to_yaml(T::from_config(root)); },
          [] { return config::to_yaml(T{}); }};
}

}  // namespace

const std::vector<Section>& sections() {
  static const std::vector<Section> all = {
      plain<config::RobotParams>("robot"),
      plain<config::LidarParams>("lidar"),
      from_root<sim::SimParams>("sim"),
      from_root<sensing::LidarDriverParams>("lidar_driver"),
      from_root<base::BaseDriverParams>("base_driver"),
      plain<mapping::ElevationMapParams>("elevation_map"),
      plain<tracking::TrackerParams>("tracker"),
      plain<prediction::PredictorParams>("predictor"),
      from_root<planning::PlannerParams>("planner"),
      plain<route::RouteParams>("route"),
      plain<metrics::MetricsParams>("metrics"),
      plain<metrics::PerceptionParams>("perception_metrics"),
      from_root<closedloop::LockstepParams>("lockstep"),
      plain<health::HealthBoardParams>("health_board"),
      from_root<viz::VizParams>("viz"),
      from_root<bus::BusGuardParams>("bus"),
      from_root<teleop::TeleopParams>("teleop"),
  };
  return all;
}

std::string dump(const config::Node& root) {
  std::string out;
  for (const auto& s : sections()) {
    if (!root.has(s.name)) continue;
    out += config::dump_yaml(s.name, s.load(root), root.section(s.name));
  }
  return out;
}

}  // namespace evade::config_dump
