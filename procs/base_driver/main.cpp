// base_driver: AgileX Scout 2.0 over its UART (protocol v1).
//
//   base_driver [--config F] [--lcm-url U] [--device PATH] [--initial-pose X,Y,YAW]
//               [--replay IN --replay-out OUT]
//
// Reads CMD_VEL, writes motion commands to the serial port at the command
// rate; reads status frames and publishes ODOMETRY and BASE_STATUS (see
// lib/base/base_driver_core.h). The port is opened with libserial and
// reopened with back-off whenever it is missing or lost (see
// lib/base/serial_link.h for why a hang-up cannot abort this process).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "base/base_driver_core.h"
#include "base/serial_link.h"
#include "bus/live_bus.h"
#include "bus/log_replay.h"
#include "bus/process_main.h"

namespace {

constexpr const char* kName = "base_driver";
// A persistent "device missing" is repeated at most this often in the log.
constexpr int64_t kRepeatLogUs = 10'000'000;
constexpr int kPollTimeoutMs = 50;

int run_live(evade::base::BaseDriverCore& core, const std::string& url) {
  using evade::base::SerialLink;
  namespace bus = evade::bus;
  const auto& params = core.params();
  bus::LiveBus live(url);
  live.add(core);
  SerialLink link(params.device, params.baud_rate, params.reopen_backoff_min_s, params.reopen_backoff_max_s);
  std::fprintf(stderr, "%s: running on %s, device %s\n", kName, url.c_str(), params.device.c_str());

  std::vector<uint8_t> rx;
  int registered_fd = -1;
  uint64_t leaked_reported = 0;
  uint64_t dropped_reported = 0;
  // Mirrors the link's own tallies into HEALTH counters.
  auto report_link_counters = [&](int64_t now) {
    if (link.leaked_ports() == leaked_reported && link.dropped_tx_bytes() == dropped_reported) return;
    core.input(now, [&] {
      core.count_link_event("serial_ports_leaked", static_cast<int64_t>(link.leaked_ports() - leaked_reported));
      core.count_link_event("serial_tx_dropped_bytes",
                            static_cast<int64_t>(link.dropped_tx_bytes() - dropped_reported));
    });
    leaked_reported = link.leaked_ports();
    dropped_reported = link.dropped_tx_bytes();
  };
  std::string last_error;
  int64_t last_error_log = 0;

  auto lost = [&](int64_t now, const std::string& why) {
    if (registered_fd >= 0) live.remove_fd(registered_fd);
    registered_fd = -1;
    std::fprintf(stderr, "%s: serial link lost: %s; reopening in %.2f s\n", kName, why.c_str(),
                 (link.next_attempt() - now) * 1e-6);
    core.input(now, [&] { core.on_link_lost(why); });
    report_link_counters(now);
    live.wake_at(link.next_attempt());
  };
  auto on_readable = [&](int64_t now) {
    rx.clear();
    std::string why;
    const bool ok = link.read_available(now, &rx, &why);
    if (!rx.empty())
      core.input(
          now, [&] { core.on_serial_bytes(rx.data(), rx.size()); }, "serial");
    if (!ok) lost(now, why);
  };

  const auto& stop = bus::stop_on_signals();
  while (!stop.load()) {
    const int64_t now = bus::bus_utime();
    std::string message;
    switch (link.try_open(now, &message)) {
      case SerialLink::OpenResult::kOpened:
        std::fprintf(stderr, "%s: %s\n", kName, message.c_str());
        last_error.clear();
        registered_fd = link.fd();
        live.add_fd(registered_fd, on_readable);
        core.input(now, [&] { core.on_link_opened(); });
        break;
      case SerialLink::OpenResult::kFailed:
        if (message != last_error || now - last_error_log >= kRepeatLogUs) {
          std::fprintf(stderr, "%s: %s\n", kName, message.c_str());
          last_error_log = now;
        }
        last_error = message;
        core.input(now, [&] { core.count_link_event("serial_open_failures"); });
        report_link_counters(now);
        live.wake_at(link.next_attempt());
        break;
      default:
        break;
    }
    live.spin_once(kPollTimeoutMs);
    // The command timer fires inside spin_once; send what it queued.
    std::vector<uint8_t> tx = core.take_tx();
    if (!tx.empty() && link.is_open()) {
      const int64_t t = bus::bus_utime();
      std::string why;
      if (!link.write(t, tx.data(), tx.size(), &why)) lost(t, why);
      report_link_counters(t);
    }
  }
  // Stopped (SIGTERM, SIGINT) while perhaps driving: the last frame the
  // base gets says zero speed, rather than the last command in force until
  // the base's own timeout.
  if (link.is_open()) {
    const int64_t t = bus::bus_utime();
    core.input(t, [&] { core.stop(); });
    std::vector<uint8_t> tx = core.take_tx();
    std::string why;
    if (link.write(t, tx.data(), tx.size(), &why))
      std::fprintf(stderr, "%s: stopping: zero speed sent\n", kName);
    else
      std::fprintf(stderr, "%s: stopping: the zero-speed frame was not sent: %s\n", kName, why.c_str());
  }
  if (link.dropped_tx_bytes() > 0)
    std::fprintf(stderr, "%s: %llu command bytes dropped (port busy)\n", kName,
                 static_cast<unsigned long long>(link.dropped_tx_bytes()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  namespace bus = evade::bus;
  namespace base = evade::base;
  CLI::App app{"evade base_driver: AgileX Scout UART v1 driver"};
  bus::CommonOptions opts;
  bus::add_common_options(app, opts);
  std::string device;
  std::string pose_text;
  app.add_option("--device", device, "serial device (default: base_driver.device in the config)");
  app.add_option("--initial-pose", pose_text, "odometry start pose X,Y,YAW (m, m, rad)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  evade::config::Node root = bus::load_config_or_exit(kName, opts);
  base::BaseDriverParams params;
  try {
    params = base::BaseDriverParams::from_config(root);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
  if (!device.empty()) params.device = device;
  if (!pose_text.empty()) {
    try {
      params.initial_pose = base::parse_pose(pose_text);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: --initial-pose: %s\n", kName, e.what());
      return 2;
    }
  }

  // ODOMETRY.epoch: this run's odometry frame (a restart resets the pose);
  // 0 in a replay, which stays deterministic.
  params.epoch = opts.replay_in.empty() ? bus::bus_utime() : 0;
  auto core = std::make_unique<base::BaseDriverCore>(params);
  // Signs ODOMETRY; acts on CMD_VEL and ESTOP only when they are signed.
  const auto auth = bus::authenticate_or_exit(kName, root, *core, /*publishes_signed=*/true);
  if (!opts.replay_in.empty()) {
    // A log holds no serial bytes: the replay exercises the command side
    // (CMD_VEL -> watchdog, BASE_STATUS) deterministically.
    if (opts.replay_out.empty()) {
      std::fprintf(stderr, "%s: --replay needs --replay-out\n", kName);
      return 2;
    }
    std::string why;
    if (!bus::replay_paths_ok(opts.replay_in, opts.replay_out, opts.force, &why)) {
      std::fprintf(stderr, "%s: %s\n", kName, why.c_str());
      return 2;
    }
    try {
      bus::replay_file({core.get()}, opts.replay_in, opts.replay_out);
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", kName, e.what());
      return 1;
    }
  }

  const std::string url = opts.lcm_url.empty() ? bus::default_lcm_url() : opts.lcm_url;
  try {
    bus::guard_bus(kName, url, root, {core.get()});
    return run_live(*core, url);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 1;
  }
}
