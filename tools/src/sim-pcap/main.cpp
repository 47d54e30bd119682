// sim-pcap --scenario FILE --out CAPTURE.pcap [--config F] [--seconds S] [--seed K]
//
// Writes the LiDAR packets the simulator sends for a scenario, its robot
// standing at the start, into a libpcap capture as the sensor's traffic
// would be recorded (Ethernet, IPv4, UDP to the model's ports: VLP-16 data
// 2368; RS-Helios MSOP 6699 and DIFOP 7788; from sim.*dest_port*). The
// capture starts at 2026-01-01 00:00:00 UTC, so the same scenario, seed
// and configuration give the same bytes. `lidar_driver --pcap` reads it.
// Exit 0 written, 2 bad arguments or configuration, 1 I/O error.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "bus/memory_bus.h"
#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "sensing/packet_sources.h"
#include "sim/scenario.h"
#include "sim/sim_core.h"

namespace {
constexpr int64_t kStartUtime = 1'767'225'600'000'000;  // 2026-01-01 00:00:00 UTC
}

int main(int argc, char** argv) {
  CLI::App app{"Write a scenario's simulated LiDAR packets (standing robot) into a pcap capture"};
  std::string scenario_path, out;
  evade::bus::CommonOptions opts;
  double seconds = 1.0;
  int64_t seed = -1;
  app.add_option("--scenario", scenario_path, "scenario YAML")->required();
  app.add_option("--out", out, "capture file to write")->required();
  evade::bus::add_robot_options(app, opts);  // --config, --robot
  app.add_option("--seconds", seconds, "how much sensor time to write")->check(CLI::Range(0.001, 600.0));
  app.add_option("--seed", seed, "range-noise seed (default: the scenario's)")->check(CLI::NonNegativeNumber);
  CLI11_PARSE(app, argc, argv);
  try {
    const std::string cfg = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
    const evade::config::Node root = evade::config::load_robot_config(cfg, {opts.robot, scenario_path});
    evade::sim::SimParams params = evade::sim::SimParams::from_config(root);
    evade::sim::Scenario scenario = evade::sim::load_scenario(scenario_path);
    evade::sim::resolve_robot(&scenario, root);
    if (seed >= 0) scenario.seed = static_cast<uint64_t>(seed);
    std::unique_ptr<evade::sim::SimCore> core = evade::sim::SimCore::from_config(root, scenario);
    evade::sensing::PcapUdpWriter writer(out, "192.168.1.200", "192.168.1.102");
    int64_t now = kStartUtime, packets = 0;
    core->set_packet_sink([&](const evade::sim::Packet& p) {
      const int port = params.dest_port(scenario.lidar.model, p.port);
      writer.write(now, port, port, p.data(), p.size());
      ++packets;
    });
    evade::bus::MemoryBus bus;
    bus.add(*core);
    const int64_t end = kStartUtime + std::llround(seconds * 1e6);
    for (; now <= end; now += 1000) bus.advance_to(now);
    writer.close();
    std::fprintf(stderr, "sim-pcap: %s: %lld %s packets, %.3f s\n", out.c_str(), static_cast<long long>(packets),
                 scenario.lidar.model.c_str(), seconds);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "sim-pcap: %s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "sim-pcap: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim-pcap: %s\n", e.what());
    return 1;
  }
  return 0;
}
