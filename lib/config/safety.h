// Safety rules that span sections of the robot configuration, checked by
// load_robot_config so that no process starts on a configuration that
// would let the robot drive blind. Each violation is a ConfigError naming
// file, line and key:
// - base_driver.watchdog_timeout_s at most kMaxWatchdogS (1 s): beyond it
//   a dead planner leaves the base driving on its last command for longer
//   than the stack's promise (docs/safety.md);
// - the planner's period (1 / planner.rate_hz) below that watchdog, or
//   every gap between commands would trip it;
// - planner.require_obstacles: false only in a configuration that says
//   it is a test configuration (top-level `test_config: true`): a planner
//   that plans with no perception at all is for tests of the planner alone.
// A rule whose keys are absent (a partial configuration in a test) is not
// checked; the owning process's from_config reports the missing key.
#pragma once

#include "config/config.h"

namespace evade::config {

inline constexpr double kMaxWatchdogS = 1.0;
inline constexpr const char* kTestConfigKey = "test_config";

void check_safety(const Node& root);

}  // namespace evade::config
