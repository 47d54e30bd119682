// sim: the world for evade, speaking the real wire formats.
//
//   sim --scenario FILE [--config F] [--lcm-url U] [--device PATH]
//       [--lidar-dest HOST:PORT] [--speed X]
//
// The core (lib/sim/sim_core.h) holds the world and is socket-free; this
// main owns the I/O: a pseudo-terminal pair whose slave is linked at the
// configured device path (the emulated Scout base; base_driver opens it;
// lib/sim/pseudo_terminal.h), UDP sockets that send the LiDAR packets to
// lidar_driver (VLP-16 data, or RS-Helios MSOP and DIFOP, by the
// scenario's lidar.model; lib/sim/udp_sender.h), and LCM for SIM_TRUTH and
// HEALTH.
//
// Time: the sim clock is the host clock (bus::bus_utime), so every
// process's utimes agree. --speed X runs the world X times faster (or
// slower) than the wall clock: sim time = t0 + X (wall - t0). Only X = 1
// suits the live stack (the other processes stamp with the wall clock and
// the base_driver integrates status frames with their receive times), so
// X != 1 is for watching a scenario or feeding tools that use message
// utimes only. Above about 3x a 2-core machine cannot cast 754 packets per
// simulated second in time; the sim then drops LiDAR packets (counted as
// lidar_packets_skipped in HEALTH) rather than fall behind.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "bus/live_bus.h"
#include "bus/process_main.h"
#include "config/robot_params.h"
#include "sim/pseudo_terminal.h"
#include "sim/scenario.h"
#include "sim/sim_core.h"
#include "sim/udp_sender.h"

namespace {

using evade::sim::SimCore;

[[noreturn]] void die(const std::string& why, int status = 1) {
  std::fprintf(stderr, "sim: %s\n", why.c_str());
  std::exit(status);
}

struct Options {
  std::string scenario_path, lcm_url, device, lidar_dest;
  double speed = 1.0;
  evade::bus::CommonOptions common;  // --config, --robot; the scenario's robot values too
};

// Parses the command line; exits on --help or a parse error.
Options parse_options(int argc, char** argv) {
  CLI::App app{"evade sim: the simulated world (VLP-16 or RS-Helios UDP packets, Scout UART on a pty, SIM_TRUTH)"};
  Options o;
  app.add_option("--scenario", o.scenario_path, "scenario YAML (SPEC.md format)")->required();
  evade::bus::add_robot_options(app, o.common);  // --config, --robot
  app.add_option("--lcm-url", o.lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  app.add_option("--device", o.device, "link the emulated Scout's pty here (default: sim.device_path)");
  app.add_option("--lidar-dest", o.lidar_dest,
                 "HOST:PORT for the LiDAR's data packets (VLP-16 data, RS-Helios MSOP; default: sim.*dest*)");
  app.add_option("--speed", o.speed, "world time / wall time (1 = real time; see the limits in the source)")
      ->check(CLI::Range(0.01, 100.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::exit(app.exit(e));
  }
  evade::bus::robot_options_from(app, o.common);
  return o;
}

// The drivers decode what the configuration says; warn when it is not what
// the scenario simulates.
void warn_on_lidar_mismatch(const evade::config::Node& root, const evade::sim::Scenario& scenario) {
  const auto lidar = evade::config::load<evade::config::LidarParams>(root.section("lidar"));
  if (lidar.model != scenario.lidar.model)
    std::fprintf(stderr, "sim: warning: scenario lidar model %s differs from lidar.model %s in the config\n",
                 scenario.lidar.model.c_str(), lidar.model.c_str());
  if (std::abs(lidar.mount.z_m - scenario.lidar.height) > 1e-6)
    std::fprintf(stderr,
                 "sim: warning: scenario lidar height %.3f m differs from lidar.mount.z_m %.3f m in the config\n",
                 scenario.lidar.height, lidar.mount.z_m);
}

// The parameters with the command line's overrides (pty link, LiDAR
// destination of the scenario's model); exits 2 naming what is wrong.
void apply_overrides(const Options& o, const evade::sim::Scenario& scenario, evade::sim::SimParams* params) {
  if (!o.device.empty()) params->device_path = o.device;
  const bool vlp16 = scenario.lidar.model == "vlp16";
  if (!o.lidar_dest.empty() &&
      !evade::sim::parse_host_port(o.lidar_dest, &params->lidar_dest_host,
                                   vlp16 ? &params->lidar_dest_port : &params->rs_helios_msop_dest_port))
    die("--lidar-dest '" + o.lidar_dest + "': expected HOST:PORT", 2);
}

// The core's outputs: LiDAR packets to UDP, Scout status bytes to the pty
// (a backlog nobody reads is dropped, as a serial line does).
void connect_sinks(SimCore& core, evade::sim::PseudoTerminal& pty, evade::sim::LidarSenders& lidar, int backlog_bytes) {
  core.set_packet_sink([&core, &lidar](const evade::sim::Packet& p) {
    if (!lidar.send(p)) core.count_io("lidar_send_errors");
  });
  core.set_serial_sink([&core, &pty, backlog_bytes](const uint8_t* data, size_t size) {
    if (pty.unread() > backlog_bytes) {
      pty.discard_unread();
      core.count_io("scout_backlog_flushes");
    }
    ssize_t n = ::write(pty.master(), data, size);
    if (n != static_cast<ssize_t>(size)) core.count_io("scout_write_errors");
  });
}

// Sim clock: t0 + speed * (wall - t0); the identity at speed 1.
struct SimClock {
  int64_t t0;
  double speed;
  int64_t sim_of(int64_t wall) const { return t0 + std::llround(speed * static_cast<double>(wall - t0)); }
  int64_t wall_of(int64_t sim) const { return t0 + std::llround(static_cast<double>(sim - t0) / speed); }
};

// Runs the world until a signal or the scenario's end: pty bytes in, the
// core's timers on the sim clock.
void run(SimCore& core, evade::bus::LiveBus& bus, const evade::sim::PseudoTerminal& pty, const SimClock& clock) {
  bus.add_fd(pty.master(), [&](int64_t wall) {
    uint8_t buf[512];
    ssize_t n = ::read(pty.master(), buf, sizeof(buf));
    if (n > 0) {
      core.input(clock.sim_of(wall), [&] { core.on_serial_bytes(buf, static_cast<size_t>(n)); });
    } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
      core.count_io("scout_read_errors");
    }
  });
  const std::atomic<bool>& stop = evade::bus::stop_on_signals();
  core.advance_to(clock.sim_of(evade::bus::bus_utime()));
  while (!stop.load() && !core.finished()) {
    int64_t next = core.next_deadline();
    if (next != evade::bus::kNever) bus.wake_at(clock.wall_of(next));
    bus.spin_once(50);
    core.advance_to(clock.sim_of(evade::bus::bus_utime()));
  }
}

void run_live(const evade::config::Node& root, const evade::sim::Scenario& scenario,
              const evade::sim::SimParams& params, const Options& o) {
  evade::sim::PseudoTerminal pty(params.device_path);
  evade::sim::LidarSenders lidar(params, scenario.lidar.model);
  const std::string url = o.lcm_url.empty() ? evade::bus::default_lcm_url() : o.lcm_url;
  std::unique_ptr<SimCore> core = SimCore::from_config(root, scenario);
  evade::bus::guard_bus("sim", url, root, {core.get()});
  evade::bus::LiveBus bus(url);
  core->attach(&bus);  // publishes through LCM; the sim clock drives it
  connect_sinks(*core, pty, lidar, params.pty_backlog_bytes);
  std::fprintf(stderr, "sim: scenario %s (%zu obstacles, %.0f s); Scout on %s -> %s; %s; speed %.2f\n",
               scenario.name.c_str(), scenario.obstacles.size(), scenario.duration_s, params.device_path.c_str(),
               pty.slave_path().c_str(), lidar.describe().c_str(), o.speed);
  run(*core, bus, pty, SimClock{evade::bus::bus_utime(), o.speed});
  if (core->finished()) std::fprintf(stderr, "sim: scenario duration %.0f s reached\n", scenario.duration_s);
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse_options(argc, argv);
  const evade::bus::CommonOptions& common = o.common;
  evade::config::Node root = evade::bus::load_config_or_exit("sim", common);
  evade::sim::SimParams params;
  evade::sim::Scenario scenario;
  try {
    params = evade::sim::SimParams::from_config(root);
    scenario = evade::sim::load_scenario(o.scenario_path);
    evade::sim::resolve_robot(&scenario, root);
  } catch (const std::exception& e) {  // ConfigError: file:line: key: reason
    die(e.what(), 2);
  }
  apply_overrides(o, scenario, &params);
  warn_on_lidar_mismatch(root, scenario);
  try {
    run_live(root, scenario, params, o);
  } catch (const evade::config::ConfigError& e) {  // the bus: section
    die(e.what(), 2);
  } catch (const std::invalid_argument& e) {  // a LiDAR the sim cannot simulate with this configuration
    die(e.what(), 2);
  } catch (const std::exception& e) {
    die(e.what());
  }
  return 0;
}
