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

// The serial link of a live run: opens and reopens the port, feeds the
// core what arrives, writes what it queues, and mirrors the link's events
// into the core's HEALTH.
class LiveLink {
 public:
  LiveLink(evade::base::BaseDriverCore& core, evade::bus::LiveBus& live)
      : core_(core),
        live_(live),
        link_(core.params().device, core.params().baud_rate, core.params().reopen_backoff_min_s,
              core.params().reopen_backoff_max_s) {}

  // Opens the port when it is closed and a retry is due.
  void try_open(int64_t now) {
    using evade::base::SerialLink;
    std::string message;
    switch (link_.try_open(now, &message)) {
      case SerialLink::OpenResult::kOpened:
        std::fprintf(stderr, "%s: %s\n", kName, message.c_str());
        last_error_.clear();
        registered_fd_ = link_.fd();
        live_.add_fd(registered_fd_, [this](int64_t t) { on_readable(t); });
        core_.input(now, [&] { core_.on_link_opened(); });
        break;
      case SerialLink::OpenResult::kFailed:
        open_failed(now, message);
        break;
      default:
        break;
    }
  }

  // Writes what the core queued (the command timer fires inside spin_once).
  void send_pending() {
    std::vector<uint8_t> tx = core_.take_tx();
    if (tx.empty() || !link_.is_open()) return;
    const int64_t t = evade::bus::bus_utime();
    std::string why;
    if (!link_.write(t, tx.data(), tx.size(), &why)) lost(t, why);
    report_link_counters(t);
  }

  // Stopped (SIGTERM, SIGINT) while perhaps driving: the last frame the
  // base gets says zero speed, rather than the last command in force until
  // the base's own timeout.
  void stop_base() {
    if (link_.is_open()) {
      const int64_t t = evade::bus::bus_utime();
      core_.input(t, [&] { core_.stop(); });
      std::vector<uint8_t> tx = core_.take_tx();
      std::string why;
      if (link_.write(t, tx.data(), tx.size(), &why))
        std::fprintf(stderr, "%s: stopping: zero speed sent\n", kName);
      else
        std::fprintf(stderr, "%s: stopping: the zero-speed frame was not sent: %s\n", kName, why.c_str());
    }
    if (link_.dropped_tx_bytes() > 0)
      std::fprintf(stderr, "%s: %llu command bytes dropped (port busy)\n", kName,
                   static_cast<unsigned long long>(link_.dropped_tx_bytes()));
  }

 private:
  void open_failed(int64_t now, const std::string& message) {
    if (message != last_error_ || now - last_error_log_ >= kRepeatLogUs) {
      std::fprintf(stderr, "%s: %s\n", kName, message.c_str());
      last_error_log_ = now;
    }
    last_error_ = message;
    core_.input(now, [&] { core_.count_link_event("serial_open_failures"); });
    report_link_counters(now);
    live_.wake_at(link_.next_attempt());
  }

  void on_readable(int64_t now) {
    rx_.clear();
    std::string why;
    const bool ok = link_.read_available(now, &rx_, &why);
    if (!rx_.empty())
      core_.input(
          now, [&] { core_.on_serial_bytes(rx_.data(), rx_.size()); }, "serial");
    if (!ok) lost(now, why);
  }

  void lost(int64_t now, const std::string& why) {
    if (registered_fd_ >= 0) live_.remove_fd(registered_fd_);
    registered_fd_ = -1;
    std::fprintf(stderr, "%s: serial link lost: %s; reopening in %.2f s\n", kName, why.c_str(),
                 (link_.next_attempt() - now) * 1e-6);
    core_.input(now, [&] { core_.on_link_lost(why); });
    report_link_counters(now);
    live_.wake_at(link_.next_attempt());
  }

  // Mirrors the link's own tallies into HEALTH counters.
  void report_link_counters(int64_t now) {
    if (link_.leaked_ports() == leaked_reported_ && link_.dropped_tx_bytes() == dropped_reported_) return;
    core_.input(now, [&] {
      core_.count_link_event("serial_ports_leaked", static_cast<int64_t>(link_.leaked_ports() - leaked_reported_));
      core_.count_link_event("serial_tx_dropped_bytes",
                             static_cast<int64_t>(link_.dropped_tx_bytes() - dropped_reported_));
    });
    leaked_reported_ = link_.leaked_ports();
    dropped_reported_ = link_.dropped_tx_bytes();
  }

  evade::base::BaseDriverCore& core_;
  evade::bus::LiveBus& live_;
  evade::base::SerialLink link_;
  std::vector<uint8_t> rx_;
  int registered_fd_ = -1;
  uint64_t leaked_reported_ = 0;
  uint64_t dropped_reported_ = 0;
  std::string last_error_;
  int64_t last_error_log_ = 0;
};

int run_live(evade::base::BaseDriverCore& core, const std::string& url) {
  evade::bus::LiveBus live(url);
  live.add(core);
  LiveLink link(core, live);
  std::fprintf(stderr, "%s: running on %s, device %s\n", kName, url.c_str(), core.params().device.c_str());
  const auto& stop = evade::bus::stop_on_signals();
  while (!stop.load()) {
    link.try_open(evade::bus::bus_utime());
    live.spin_once(kPollTimeoutMs);
    link.send_pending();
  }
  link.stop_base();
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
  base::BaseDriverRun run;
  run.device = device;
  if (!pose_text.empty()) {
    try {
      run.initial_pose = base::parse_pose(pose_text);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: --initial-pose: %s\n", kName, e.what());
      return 2;
    }
  }
  // ODOMETRY.epoch: this run's odometry frame (a restart resets the pose);
  // 0 in a replay, which stays deterministic.
  run.epoch = opts.replay_in.empty() ? bus::bus_utime() : 0;
  std::unique_ptr<base::BaseDriverCore> core;
  try {
    core = base::BaseDriverCore::from_config(root, run);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }
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
