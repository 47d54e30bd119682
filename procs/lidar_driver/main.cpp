// lidar_driver: LiDAR UDP packets (or a pcap capture) -> LIDAR_POINTS,
// LIDAR_SCAN and HEALTH on LCM.
//
//   lidar_driver [--config F] [--lcm-url U]                 live: UDP from config
//   lidar_driver --pcap FILE [--rate X]                     capture at X times its pace
//                                                           (0 = as fast as possible),
//                                                           last revolution flushed, exit 0
//   lidar_driver --from-scan                                live: LIDAR_SCAN from the bus (a log
//                                                           played back) -> LIDAR_POINTS
//   lidar_driver --replay IN.lcmlog --replay-out OUT.lcmlog re-decode LIDAR_SCAN messages
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "bus/live_bus.h"
#include "bus/log_replay.h"
#include "bus/process_main.h"
#include "sensing/lidar_driver_core.h"
#include "sensing/packet_sources.h"

namespace {

constexpr const char* kName = "lidar_driver";
constexpr size_t kMaxDatagram = 65536;
// While pacing a capture, LCM and timers are serviced at least this often.
constexpr int kMaxWaitMs = 50;
// Capture read as fast as possible: service LCM and timers every so many packets.
constexpr int kPacketsPerSpin = 64;

using evade::sensing::LidarDriverCore;
using evade::sensing::LidarDriverParams;

int run_pcap(LidarDriverCore& core, evade::bus::LiveBus& bus, const std::string& path, double rate) {
  evade::sensing::PcapUdpReader reader(path);
  const auto& stop = evade::bus::stop_on_signals();
  evade::sensing::UdpDatagram d;
  const std::vector<int> ports = core.params().ports();
  int64_t first_capture = -1, start_wall = 0, last_stamp = 0;
  int64_t packets = 0, other_ports = 0, truncated = 0;
  while (!stop.load() && reader.next(&d)) {
    if (first_capture < 0) {
      first_capture = d.utime;
      start_wall = evade::bus::bus_utime();
    }
    if (rate > 0.0) {
      const int64_t due = start_wall + static_cast<int64_t>(std::llround((d.utime - first_capture) / rate));
      for (int64_t now = evade::bus::bus_utime(); now < due && !stop.load(); now = evade::bus::bus_utime())
        bus.spin_once(static_cast<int>(std::min<int64_t>((due - now) / 1000 + 1, kMaxWaitMs)));
    } else if (packets % kPacketsPerSpin == 0) {
      bus.spin_once(0);
    }
    ++packets;
    // Each datagram is stamped with its capture time, moved to when the
    // replay started: outputs keep the sensor's own spacing (and so the same
    // utimes relative to the first packet) at any --rate, 0 included.
    const int64_t now = std::max(last_stamp, start_wall + (d.utime - first_capture));
    last_stamp = now;
    // Every UDP payload goes to the decoder, whatever its port: the capture's
    // ports are the sensor's, not necessarily the configured ones, and the
    // decoder tells data from position / DIFOP packets by size and header.
    if (std::find(ports.begin(), ports.end(), d.dst_port) == ports.end()) ++other_ports;
    if (d.truncated) {
      ++truncated;
      core.input(now, [&] { core.count_external("pcap_truncated_datagrams"); });
      continue;
    }
    core.input(now, [&] { core.on_packet(d.payload.data(), d.payload.size()); });
  }
  if (!reader.error().empty()) std::fprintf(stderr, "%s: %s: %s\n", kName, path.c_str(), reader.error().c_str());
  core.input(last_stamp, [&] { core.flush(); });
  bus.spin_once(0);
  std::fprintf(
      stderr,
      "%s: %s: %lld datagrams, %lld not on the configured ports, %lld truncated, %lld data packets, %lld revolutions\n",
      kName, path.c_str(), static_cast<long long>(packets), static_cast<long long>(other_ports),
      static_cast<long long>(truncated), static_cast<long long>(core.counter("data_packets")),
      static_cast<long long>(core.counter("revolutions")));
  return reader.error().empty() ? 0 : 1;
}

int run_live(LidarDriverCore& core, evade::bus::LiveBus& bus) {
  const LidarDriverParams& p = core.params();
  std::vector<int> fds;
  for (int port : p.ports())
    fds.push_back(evade::sensing::open_udp_socket(p.bind_address, port, p.socket_receive_buffer_bytes));
  std::vector<uint8_t> buffer(kMaxDatagram);
  evade::sensing::UdpDatagram d;
  for (size_t i = 0; i < fds.size(); ++i) {
    const int fd = fds[i];
    const std::string source = "udp:" + std::to_string(p.ports()[i]);  // reported in HEALTH with its age
    bus.add_fd(fd, [&core, &buffer, &d, fd, source](int64_t now) {
      while (evade::sensing::receive_datagram(fd, buffer, &d, now)) {
        core.input(
            d.utime, [&] { core.on_packet(d.payload.data(), d.payload.size()); }, source);
      }
    });
  }
  std::fprintf(stderr, "%s: %s on %s port(s)", kName, evade::sensing::model_name(p.model), p.bind_address.c_str());
  for (int port : p.ports()) std::fprintf(stderr, " %d", port);
  std::fprintf(stderr, "\n");
  bus.run(evade::bus::stop_on_signals());
  for (int fd : fds) ::close(fd);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade lidar_driver: VLP-16 / RS-Helios packets to LIDAR_POINTS"};
  evade::bus::CommonOptions opts;
  evade::bus::add_common_options(app, opts);
  std::string pcap_path;
  double rate = 1.0;
  auto* pcap_opt = app.add_option("--pcap", pcap_path, "read packets from this capture instead of UDP");
  app.add_option("--rate", rate, "with --pcap: replay speed (1 = recorded pace, 0 = as fast as possible)")
      ->needs(pcap_opt)
      ->check(CLI::NonNegativeNumber);
  bool from_scan = false;
  app.add_flag("--from-scan", from_scan,
               "decode LIDAR_SCAN from the bus (a played-back log) instead of UDP; publishes LIDAR_POINTS only")
      ->excludes(pcap_opt);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  evade::config::Node root = evade::bus::load_config_or_exit(kName, opts);
  // A log replay and --from-scan decode LIDAR_SCAN messages; live and
  // --pcap decode UDP payloads.
  const bool scans = !opts.replay_in.empty() || from_scan;
  std::unique_ptr<LidarDriverCore> core;
  try {
    core =
        LidarDriverCore::from_config(root, scans ? LidarDriverCore::Source::kScans : LidarDriverCore::Source::kPackets);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  }

  if (!opts.replay_in.empty()) {
    if (opts.replay_out.empty() || !pcap_path.empty() || from_scan) {
      std::fprintf(stderr, "%s: --replay needs --replay-out and excludes --pcap and --from-scan\n", kName);
      return 2;
    }
    std::string why;
    if (!evade::bus::replay_paths_ok(opts.replay_in, opts.replay_out, opts.force, &why)) {
      std::fprintf(stderr, "%s: %s\n", kName, why.c_str());
      return 2;
    }
    try {
      evade::bus::ReplayOptions ro;
      ro.channels = {evade::sensing::kLidarScanChannel};
      int64_t n = evade::bus::replay_file({core.get()}, opts.replay_in, opts.replay_out, ro);
      std::fprintf(stderr, "%s: replayed %s -> %s (%lld events out)\n", kName, opts.replay_in.c_str(),
                   opts.replay_out.c_str(), static_cast<long long>(n));
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", kName, e.what());
      return 1;
    }
  }

  const std::string url = opts.lcm_url.empty() ? evade::bus::default_lcm_url() : opts.lcm_url;
  try {
    if (from_scan) {
      evade::bus::LiveBus bus(url);
      bus.add(*core);
      std::fprintf(stderr, "%s: decoding %s from the bus\n", kName, evade::sensing::kLidarScanChannel);
      bus.run(evade::bus::stop_on_signals());
      return 0;
    }
    evade::bus::guard_bus(kName, url, root, {core.get()});
    evade::bus::LiveBus bus(url);
    bus.add(*core);
    if (!pcap_path.empty()) return run_pcap(*core, bus, pcap_path, rate);
    return run_live(*core, bus);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", kName, e.what());
    return 1;
  }
}
