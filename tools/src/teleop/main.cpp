// teleop: drive the robot from the keyboard (issue 20).
//
//   teleop [--config F] [--lcm-url U]
//
// w / s faster / slower, a / d turn, space or x stop, q quit. Publishes
// CMD_VEL signed with the bus key (lib/bus/auth.h), so base_driver obeys
// it; while the planner runs too, base_driver takes whichever came last.
// A key must come at least every teleop.hold_s (hold it down), else the
// command falls to zero. Quitting sends zero. An ESTOP beats it
// (tools/estop).
#include <termios.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "bus/live_bus.h"
#include "bus/process_main.h"
#include "teleop/teleop_core.h"

namespace {
constexpr const char* kName = "teleop";

// Raw keys from a terminal for the life of the object.
class RawTerminal {
 public:
  RawTerminal() : ok_(::isatty(0) && ::tcgetattr(0, &saved_) == 0) {
    if (!ok_) return;
    termios raw = saved_;
    raw.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
    raw.c_cc[VMIN] = 0;
    raw.c_cc[VTIME] = 0;
    ::tcsetattr(0, TCSANOW, &raw);
  }
  ~RawTerminal() {
    if (ok_) ::tcsetattr(0, TCSANOW, &saved_);
  }
  bool ok() const { return ok_; }

 private:
  bool ok_;
  termios saved_{};
};
}  // namespace

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  CLI::App app{"evade teleop: keyboard driving, signed CMD_VEL"};
  bus::CommonOptions opts;
  bus::add_robot_options(app, opts, false);  // --config, --robot
  app.add_option("--lcm-url", opts.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  CLI11_PARSE(app, argc, argv);
  const evade::config::Node root = bus::load_config_or_exit(kName, opts);
  std::unique_ptr<evade::teleop::TeleopCore> made;
  try {
    made = evade::teleop::TeleopCore::from_config(root);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
  evade::teleop::TeleopCore& core = *made;
  const auto auth = bus::authenticate_or_exit(kName, root, core, /*publishes_signed=*/true);
  RawTerminal term;
  if (!term.ok()) {
    std::fprintf(stderr, "%s: standard input is not a terminal\n", kName);
    return 2;
  }
  try {
    bus::LiveBus live(opts.lcm_url.empty() ? bus::default_lcm_url() : opts.lcm_url);
    live.add(core);
    bool quit = false;
    live.add_fd(0, [&](int64_t now) {
      char c;
      while (::read(0, &c, 1) == 1) {
        if (c == 'q')
          quit = true;
        else
          core.input(now, [&] { core.on_key(c); });
      }
      std::fprintf(stderr, "\r%s: v %+.2f m/s  omega %+.2f rad/s   ", kName, core.v(), core.omega());
    });
    std::fprintf(stderr, "%s: w/s faster/slower, a/d turn, space stop, q quit (hold the key)\n", kName);
    const auto& stop = bus::stop_on_signals();
    while (!stop.load() && !quit) live.spin_once(50);
    core.input(bus::bus_utime(), [&] { core.stop(); });
    std::fprintf(stderr, "\n%s: zero sent\n", kName);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 1;
  }
  return 0;
}
