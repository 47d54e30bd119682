// The thin main every process shares: --config, --lcm-url, and
// --replay IN.lcmlog --replay-out OUT.lcmlog (run the same core over a log,
// in process, as fast as the CPU allows). Bad configuration exits with
// status 2 and one line naming file, line and key.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>

#include "bus/auth.h"
#include "bus/core.h"
#include "config/config.h"

namespace evade::bus {

struct CommonOptions {
  std::string config_path;
  std::string robot;     // --robot NAME: the profile config/robots/NAME.yaml (lib/config/robot_profile.h)
  std::string scenario;  // --scenario FILE: its own robot values go on top of the profile's
  std::string lcm_url;
  std::string replay_in;
  std::string replay_out;
  bool force = false;  // --force: --replay-out may replace an existing file
};

// --config, --robot, --scenario (unless the app has its own, whose value
// then counts: robot_options_from), --lcm-url, --replay, --replay-out, --force.
void add_common_options(CLI::App& app, CommonOptions& opts);
// --config, --robot and --scenario alone (tools that load the robot
// configuration but are no bus process); the same rule for --scenario.
void add_robot_options(CLI::App& app, CommonOptions& opts, bool with_scenario = true);
// After parsing: an app's own --scenario (route, sim, lockstep) is the
// scenario whose robot values the configuration takes.
void robot_options_from(const CLI::App& app, CommonOptions& opts);

// Loads the configuration named by opts (or the default one) merged with
// the robot profile and the scenario's own values (config/robot_profile.h)
// and prints "<process>: footprint L x W m, profile P, source FILE:LINE"
// on stderr; on error prints "<process>: <file>:<line>: key '...': reason"
// and exits with status 2.
config::Node load_config_or_exit(const std::string& process, const CommonOptions& opts);

// For a live process: reads the `bus:` section, warns once on stderr when
// the bus is reachable from an interface it does not allow (bus_guard.h),
// and puts the number of such interfaces in each core's HEALTH counter
// bus_exposed_interfaces. Throws config::ConfigError on a bad section.
void guard_bus(const std::string& process, const std::string& url, const config::Node& root,
               const std::vector<Core*>& cores);

// Refuses to write a replay's output over its input, or over an existing
// regular file unless `force` (tools never destroy logs): false with *why
// set. /dev/null and other non-regular files are fine.
bool replay_paths_ok(const std::string& in, const std::string& out, bool force, std::string* why);

// Signs and checks the authenticated channels (auth.h) of a core that
// subscribes to one or, with `publishes_signed`, publishes one: loads the
// key of the configuration and sets it on the core. nullptr (and no key
// needed) for any other core. On a missing or exposed key, or a bad
// `bus.auth` section, prints "<process>: <reason>" and exits with status 2.
std::unique_ptr<HmacAuth> authenticate_or_exit(const std::string& process, const config::Node& root, Core& core,
                                               bool publishes_signed);

using CoreFactory = std::function<std::unique_ptr<Core>(const config::Node& root)>;

struct ProcessOptions {
  // Live only: channels whose queued messages are conflated to the newest
  // (see LiveBus::conflate). A log replay delivers every message.
  std::vector<std::string> conflate;
  // The core publishes an authenticated channel (auth.h) and so needs the
  // key even if it subscribes to none.
  bool publishes_signed = false;
  // Live only: the process asks the others for their clocks on CLOCK_SYNC
  // and reports the offset in HEALTH, warning beyond
  // bus.clock_sync.max_offset_s (clock_sync.h). Every live process answers.
  bool clock_sync_requests = false;
};

// Parses the command line (flags added by `add_flags` too), builds the core
// from the configuration and runs it live on LCM, or over a log with
// --replay. Returns the process exit status.
int process_main(int argc, char** argv, const std::string& name, const std::function<void(CLI::App&)>& add_flags,
                 const CoreFactory& make, const ProcessOptions& options = {});

}  // namespace evade::bus
