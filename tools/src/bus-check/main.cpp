// bus-check: is this host's LCM bus closed to the interfaces that
// bus.allowed_interfaces does not name? The check every process runs at
// start (lib/bus/bus_guard.h), as a command for tools/bus-firewall.
//
//   bus-check [--config F] [--lcm-url U]     exit 0 closed, 1 exposed, 2 bad config or URL
//   bus-check [--config F] --allowed         prints the allowed interfaces, one a line
//   bus-check [--lcm-url U] --group          prints the bus's group and port: "239.255.76.67 7667"
#include <CLI/CLI.hpp>
#include <cstdio>

#include "bus/bus_guard.h"
#include "bus/live_bus.h"
#include "bus/process_main.h"

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  CLI::App app{"evade bus-check: is the LCM bus reachable from an interface it should not be?"};
  bus::CommonOptions opts;
  bus::add_robot_options(app, opts, false);  // --config, --robot
  app.add_option("--lcm-url", opts.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  bool allowed = false, group = false;
  app.add_flag("--allowed", allowed, "print bus.allowed_interfaces, one a line");
  app.add_flag("--group", group, "print the URL's multicast group and port");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  const std::string url = opts.lcm_url.empty() ? bus::default_lcm_url() : opts.lcm_url;
  if (group) {
    const auto a = bus::parse_udpm_url(url);
    if (!a) {
      std::fprintf(stderr, "bus-check: %s is not a udpm:// URL\n", url.c_str());
      return 2;
    }
    std::printf("%u.%u.%u.%u %d\n", a->group >> 24, (a->group >> 16) & 255, (a->group >> 8) & 255, a->group & 255,
                a->port);
    return 0;
  }
  const evade::config::Node root = bus::load_config_or_exit("bus-check", opts);
  bus::BusGuardParams params;
  try {
    params = bus::BusGuardParams::from_config(root);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "bus-check: %s\n", e.what());
    return 2;
  }
  if (allowed) {
    for (const auto& i : params.allowed_interfaces) std::printf("%s\n", i.c_str());
    return 0;
  }
  const bus::Exposure e = bus::host_exposure(url, params.allowed_interfaces);
  if (e.closed()) {
    std::printf("bus-check: %s closed (reachable only through allowed interfaces)\n", url.c_str());
    return 0;
  }
  for (const auto& r : e.reasons) std::printf("bus-check: exposed: %s\n", r.c_str());
  return 1;
}
