// estop: stop the robot, signed, so that it stays stopped (issue 20).
//
//   estop [--release] [--hold] [--reason TEXT] [--config F] [--lcm-url U]
//
// Publishes ESTOP {engaged: true} teleop.estop_repeats times at
// teleop.estop_rate_hz (--hold: until Ctrl-C), signed with the bus key.
// base_driver latches it: every motion frame is zero and every CMD_VEL is
// ignored until `estop --release` (a new CMD_VEL is then needed to drive).
// A restarted base_driver starts released: keep `estop --hold` running
// when the stop must outlive one.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "bus/live_bus.h"
#include "bus/process_main.h"
#include "teleop/teleop_core.h"

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  constexpr const char* kName = "estop";
  CLI::App app{"evade estop: signed, latched e-stop"};
  bus::CommonOptions opts;
  bool release = false, hold = false;
  std::string reason = "operator";
  bus::add_robot_options(app, opts, false);  // --config, --robot
  app.add_option("--lcm-url", opts.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  app.add_flag("--release", release, "release the e-stop instead");
  app.add_flag("--hold", hold, "keep sending until interrupted");
  app.add_option("--reason", reason, "free text, recorded in the message");
  CLI11_PARSE(app, argc, argv);
  const evade::config::Node root = bus::load_config_or_exit(kName, opts);
  std::unique_ptr<evade::teleop::EstopCore> made;
  try {
    made = evade::teleop::EstopCore::from_config(root, !release, reason, hold);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
  evade::teleop::EstopCore& core = *made;
  const auto auth = bus::authenticate_or_exit(kName, root, core, /*publishes_signed=*/true);
  try {
    bus::LiveBus live(opts.lcm_url.empty() ? bus::default_lcm_url() : opts.lcm_url);
    live.add(core);
    const auto& stop = bus::stop_on_signals();
    while (!stop.load() && !core.done()) live.spin_once(50);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 1;
  }
  std::fprintf(stderr, "%s: %s sent %d times\n", kName, release ? "release" : "stop", core.sent());
  return 0;
}
