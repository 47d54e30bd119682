#include "config/safety.h"

#include <sstream>

namespace evade::config {
namespace {

bool has_path(const Node& root, const std::string& section, const std::string& key) {
  return root.has(section) && root.yaml()[section].IsMap() && root.yaml()[section][key].IsDefined();
}

}  // namespace

void check_safety(const Node& root) {
  bool test_config = false;
  if (root.has(kTestConfigKey)) test_config = root.get<bool>(kTestConfigKey);

  double watchdog_s = -1.0;
  if (has_path(root, "base_driver", "watchdog_timeout_s")) {
    const Node b = root.section("base_driver");
    watchdog_s = b.get<double>("watchdog_timeout_s");
    if (watchdog_s > kMaxWatchdogS) {
      std::ostringstream os;
      os << "must be at most " << kMaxWatchdogS << " s (safety: a dead planner must stop the base within it)";
      b.fail("watchdog_timeout_s", os.str());
    }
  }
  if (watchdog_s > 0.0 && has_path(root, "planner", "rate_hz")) {
    const Node p = root.section("planner");
    const double rate = p.get<double>("rate_hz");
    if (!(rate > 0.0) || 1.0 / rate >= watchdog_s) {
      std::ostringstream os;
      os << "the planner's period (1 / rate_hz) must be below base_driver.watchdog_timeout_s (" << watchdog_s
         << " s), or every gap between commands trips the watchdog";
      p.fail("rate_hz", os.str());
    }
  }
  if (has_path(root, "planner", "require_obstacles")) {
    const Node p = root.section("planner");
    if (!p.get<bool>("require_obstacles") && !test_config)
      p.fail("require_obstacles",
             "false (plan with no perception at all) is allowed only in a test configuration "
             "(top-level 'test_config: true')");
  }
}

}  // namespace evade::config
