#include "bus/process_main.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "bus/bus_guard.h"
#include "bus/clock_sync.h"
#include "bus/live_bus.h"
#include "bus/log_replay.h"
#include "config/robot_profile.h"

namespace evade::bus {

void add_robot_options(CLI::App& app, CommonOptions& opts, bool with_scenario) {
  app.add_option("--config", opts.config_path,
                 "robot configuration (default: $EVADE_CONFIG, ./config/robot.yaml, the source tree's, or the "
                 "installed <sysconfdir>/evade/robot.yaml; lib/config/README.md)");
  app.add_option("--robot", opts.robot,
                 "robot profile: config/robots/NAME.yaml beside the configuration overrides it (default: the "
                 "scenario's robot.profile, else none)");
  if (with_scenario && !app.get_option_no_throw("--scenario"))
    app.add_option("--scenario", opts.scenario,
                   "a scenario whose own robot values (robot.profile, robot.footprint, lidar.model, lidar.height) "
                   "override the profile's");
}

void robot_options_from(const CLI::App& app, CommonOptions& opts) {
  const CLI::Option* own = app.get_option_no_throw("--scenario");
  if (opts.scenario.empty() && own && own->count() > 0) opts.scenario = own->as<std::string>();
}

void add_common_options(CLI::App& app, CommonOptions& opts) {
  add_robot_options(app, opts);
  app.add_option("--lcm-url", opts.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  app.add_option("--replay", opts.replay_in, "run over this lcm-logger log instead of live LCM");
  app.add_option("--replay-out", opts.replay_out, "with --replay: write the outputs to this log (a new file)");
  app.add_flag("--force", opts.force, "with --replay-out: replace an existing file (never the input)");
}

config::Node load_config_or_exit(const std::string& process, const CommonOptions& opts) {
  try {
    const std::string path = opts.config_path.empty() ? config::default_config_path() : opts.config_path;
    config::Node root = config::load_robot_config(path, {opts.robot, opts.scenario});
    std::fprintf(stderr, "%s: %s\n", process.c_str(), config::footprint_line(root).c_str());
    return root;
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", process.c_str(), e.what());
    std::exit(2);
  }
}

void guard_bus(const std::string& process, const std::string& url, const config::Node& root,
               const std::vector<Core*>& cores) {
  const BusGuardParams params = BusGuardParams::from_config(root);
  const int64_t exposed = warn_if_exposed(process, url, params);
  for (Core* c : cores) c->note("bus_exposed_interfaces", exposed);
}

std::unique_ptr<HmacAuth> authenticate_or_exit(const std::string& process, const config::Node& root, Core& core,
                                               bool publishes_signed) {
  bool needed = publishes_signed;
  for (const auto& ch : core.channels()) needed |= is_authenticated(ch);
  if (!needed) return nullptr;
  try {
    auto auth = load_auth(root).make(process);
    core.set_authenticator(auth.get());
    return auth;
  } catch (const std::exception& e) {  // KeyError, ConfigError
    std::fprintf(stderr, "%s: %s\n", process.c_str(), e.what());
    std::exit(2);
  }
}

bool replay_paths_ok(const std::string& in, const std::string& out, bool force, std::string* why) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (fs::equivalent(in, out, ec)) {
      *why = "--replay-out " + out + " is the input log itself; refusing to overwrite it";
      return false;
    }
    if (!force && fs::is_regular_file(out, ec)) {  // /dev/null and the like are no log
      *why = "--replay-out " + out + " exists; refusing to overwrite it without --force";
      return false;
    }
  }
  return true;
}

int process_main(int argc, char** argv, const std::string& name, const std::function<void(CLI::App&)>& add_flags,
                 const CoreFactory& make, const ProcessOptions& options) {
  CLI::App app{"evade " + name};
  CommonOptions opts;
  if (add_flags) add_flags(app);
  add_common_options(app, opts);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  robot_options_from(app, opts);
  config::Node root = load_config_or_exit(name, opts);
  std::unique_ptr<Core> core;
  try {
    core = make(root);
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
    return 2;
  }
  const std::unique_ptr<HmacAuth> auth = authenticate_or_exit(name, root, *core, options.publishes_signed);

  if (!opts.replay_in.empty()) {
    if (opts.replay_out.empty()) {
      std::fprintf(stderr, "%s: --replay needs --replay-out\n", name.c_str());
      return 2;
    }
    std::string why;
    if (!replay_paths_ok(opts.replay_in, opts.replay_out, opts.force, &why)) {
      std::fprintf(stderr, "%s: %s\n", name.c_str(), why.c_str());
      return 2;
    }
    try {
      int64_t n = replay_file({core.get()}, opts.replay_in, opts.replay_out);
      std::fprintf(stderr, "%s: replayed %s -> %s (%lld events out)\n", name.c_str(), opts.replay_in.c_str(),
                   opts.replay_out.c_str(), static_cast<long long>(n));
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
      return 1;
    }
  }

  std::string url = opts.lcm_url.empty() ? default_lcm_url() : opts.lcm_url;
  try {
    guard_bus(name, url, root, {core.get()});
    ClockSync clock_sync(name, ClockSyncParams::from_config(root), options.clock_sync_requests);
    clock_sync.on_warning = [&name](const std::string& line) {
      std::fprintf(stderr, "%s: %s\n", name.c_str(), line.c_str());
    };
    core->set_clock_sync(&clock_sync);
    LiveBus bus(url);
    bus.add(*core);
    for (const auto& ch : options.conflate) bus.conflate(ch);
    std::fprintf(stderr, "%s: running on %s\n", name.c_str(), url.c_str());
    bus.run(stop_on_signals());
  } catch (const config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", name.c_str(), e.what());
    return 1;
  }
  return 0;
}

}  // namespace evade::bus
