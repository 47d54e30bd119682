// sim: the world for evade, speaking the real wire formats.
//
//   sim --scenario FILE [--config F] [--lcm-url U] [--device PATH]
//       [--lidar-dest HOST:PORT] [--speed X]
//
// The core (lib/sim/sim_core.h) holds the world and is socket-free; this
// main owns the I/O: a pseudo-terminal pair whose slave is linked at the
// configured device path (the emulated Scout base; base_driver opens it),
// UDP sockets that send the LiDAR packets to lidar_driver (VLP-16 data, or
// RS-Helios MSOP and DIFOP, by the scenario's lidar.model), and LCM for
// SIM_TRUTH and HEALTH.
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
#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
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
#include "sim/scenario.h"
#include "sim/sim_core.h"

namespace {

using evade::sim::SimCore;

[[noreturn]] void die(const std::string& why, int status = 1) {
  std::fprintf(stderr, "sim: %s\n", why.c_str());
  std::exit(status);
}

// The emulated base's serial port: a pty pair, the slave linked at `link`.
class PseudoTerminal {
 public:
  explicit PseudoTerminal(const std::string& link) : link_(link) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (master_ < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
    if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0)
      throw std::runtime_error(std::string("grantpt/unlockpt: ") + std::strerror(errno));
    const char* name = ::ptsname(master_);
    if (!name) throw std::runtime_error("ptsname failed");
    slave_path_ = name;
    // Our own slave descriptor stays open for the whole run: with no slave
    // open, reading the master gives EIO, and a driver that closes and
    // reopens the port must find it as it was.
    slave_ = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (slave_ < 0) throw std::runtime_error("open " + slave_path_ + ": " + std::strerror(errno));
    termios tio{};
    if (::tcgetattr(slave_, &tio) != 0) throw std::runtime_error(std::string("tcgetattr: ") + std::strerror(errno));
    ::cfmakeraw(&tio);  // no echo, no newline rewriting: binary frames pass unchanged
    ::cfsetispeed(&tio, B115200);
    ::cfsetospeed(&tio, B115200);
    if (::tcsetattr(slave_, TCSANOW, &tio) != 0)
      throw std::runtime_error(std::string("tcsetattr: ") + std::strerror(errno));

    struct stat st {};
    if (::lstat(link_.c_str(), &st) == 0) {
      // Replace a stale link from an earlier run; never delete a real file or device.
      if (!S_ISLNK(st.st_mode))
        throw std::runtime_error(link_ + " exists and is not a symbolic link; not replacing it");
      ::unlink(link_.c_str());
    }
    if (::symlink(slave_path_.c_str(), link_.c_str()) != 0)
      throw std::runtime_error("symlink " + link_ + " -> " + slave_path_ + ": " + std::strerror(errno));
  }
  ~PseudoTerminal() {
    char target[256];
    ssize_t n = ::readlink(link_.c_str(), target, sizeof(target) - 1);
    if (n > 0) {
      target[n] = 0;
      if (slave_path_ == target) ::unlink(link_.c_str());  // only our own link
    }
    if (slave_ >= 0) ::close(slave_);
    if (master_ >= 0) ::close(master_);
  }
  int master() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }

  // Bytes not yet read by whoever has the slave open (or by nobody).
  int unread() const {
    int n = 0;
    return ::ioctl(slave_, FIONREAD, &n) == 0 ? n : 0;
  }
  // Drops them: a real serial line does not keep what nobody read.
  void discard_unread() { ::tcflush(slave_, TCIFLUSH); }

 private:
  std::string link_;
  std::string slave_path_;
  int master_ = -1;
  int slave_ = -1;
};

class UdpSender {
 public:
  UdpSender(const std::string& host, int port) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
    if (fd_ < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* res = nullptr;
    if (::getaddrinfo(host.c_str(), nullptr, &hints, &res) != 0 || !res)
      throw std::runtime_error("cannot resolve LiDAR destination host '" + host + "'");
    std::memcpy(&dest_, res->ai_addr, sizeof(dest_));
    ::freeaddrinfo(res);
    dest_.sin_port = htons(static_cast<uint16_t>(port));
  }
  ~UdpSender() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool send(const uint8_t* data, size_t size) {
    return ::sendto(fd_, data, size, 0, reinterpret_cast<const sockaddr*>(&dest_), sizeof(dest_)) ==
           static_cast<ssize_t>(size);
  }

 private:
  int fd_ = -1;
  sockaddr_in dest_{};
};

// "host:port" -> (host, port); false if malformed.
bool parse_dest(const std::string& s, std::string* host, int* port) {
  size_t colon = s.rfind(':');
  if (colon == std::string::npos || colon == 0) return false;
  try {
    size_t used = 0;
    int p = std::stoi(s.substr(colon + 1), &used);
    if (used != s.size() - colon - 1 || p < 1 || p > 65535) return false;
    *host = s.substr(0, colon);
    *port = p;
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

namespace {

// The LiDAR's UDP destinations: data (VLP-16 data, RS-Helios MSOP) and,
// for the RS-Helios, DIFOP, on the host of sim.lidar_dest_host.
class LidarSenders {
 public:
  LidarSenders(const evade::sim::SimParams& p, const std::string& model)
      : host_(p.lidar_dest_host),
        model_(model),
        data_port_(p.dest_port(model, evade::sim::LidarPort::kData)),
        difop_port_(p.dest_port(model, evade::sim::LidarPort::kDifop)),
        data_(host_, data_port_),
        difop_(host_, difop_port_) {}
  bool send(const evade::sim::Packet& p) {
    return (p.port == evade::sim::LidarPort::kDifop ? difop_ : data_).send(p.data(), p.size());
  }
  std::string describe() const {
    std::string s = model_ + " to " + host_ + ":" + std::to_string(data_port_);
    if (model_ != "vlp16") s += " (DIFOP :" + std::to_string(difop_port_) + ")";
    return s;
  }

 private:
  std::string host_, model_;
  int data_port_, difop_port_;
  UdpSender data_, difop_;
};

// The drivers decode what the configuration says; warn when it is not what
// the scenario simulates.
void warn_on_lidar_mismatch(const evade::config::Node& root, const evade::sim::Scenario& scenario) {
  const evade::config::Node lidar = root.section("lidar");
  if (lidar.has("model") && lidar.get<std::string>("model") != scenario.lidar.model)
    std::fprintf(stderr, "sim: warning: scenario lidar model %s differs from lidar.model %s in the config\n",
                 scenario.lidar.model.c_str(), lidar.get<std::string>("model").c_str());
  if (lidar.section("mount").has("z_m")) {
    double z = lidar.section("mount").get<double>("z_m");
    if (std::abs(z - scenario.lidar.height) > 1e-6)
      std::fprintf(stderr,
                   "sim: warning: scenario lidar height %.3f m differs from lidar.mount.z_m %.3f m in the config\n",
                   scenario.lidar.height, z);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade sim: the simulated world (VLP-16 or RS-Helios UDP packets, Scout UART on a pty, SIM_TRUTH)"};
  std::string scenario_path, lcm_url, device, lidar_dest;
  double speed = 1.0;
  evade::bus::CommonOptions common;
  app.add_option("--scenario", scenario_path, "scenario YAML (SPEC.md format)")->required();
  evade::bus::add_robot_options(app, common);  // --config, --robot
  app.add_option("--lcm-url", lcm_url, "LCM URL (default $LCM_DEFAULT_URL, else host-local udpm)");
  app.add_option("--device", device, "link the emulated Scout's pty here (default: sim.device_path)");
  app.add_option("--lidar-dest", lidar_dest,
                 "HOST:PORT for the LiDAR's data packets (VLP-16 data, RS-Helios MSOP; default: sim.*dest*)");
  app.add_option("--speed", speed, "world time / wall time (1 = real time; see the limits in the source)")
      ->check(CLI::Range(0.01, 100.0));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }

  evade::bus::robot_options_from(app, common);
  evade::config::Node root = evade::bus::load_config_or_exit("sim", common);
  evade::sim::SimParams params;
  evade::sim::Scenario scenario;
  try {
    params = evade::sim::SimParams::from_config(root);
    scenario = evade::sim::load_scenario(scenario_path);
    evade::sim::resolve_robot(&scenario, root);
  } catch (const std::exception& e) {  // ConfigError: file:line: key: reason
    die(e.what(), 2);
  }
  if (!device.empty()) params.device_path = device;
  const bool vlp16 = scenario.lidar.model == "vlp16";
  if (!lidar_dest.empty() && !parse_dest(lidar_dest, &params.lidar_dest_host,
                                         vlp16 ? &params.lidar_dest_port : &params.rs_helios_msop_dest_port))
    die("--lidar-dest '" + lidar_dest + "': expected HOST:PORT", 2);
  warn_on_lidar_mismatch(root, scenario);

  try {
    PseudoTerminal pty(params.device_path);
    LidarSenders lidar(params, scenario.lidar.model);
    const std::string url = lcm_url.empty() ? evade::bus::default_lcm_url() : lcm_url;
    SimCore core(scenario, params);
    evade::bus::guard_bus("sim", url, root, {&core});
    evade::bus::LiveBus bus(url);

    core.attach(&bus);  // publishes through LCM; the sim clock below drives it
    core.set_packet_sink([&](const evade::sim::Packet& p) {
      if (!lidar.send(p)) core.count_io("lidar_send_errors");
    });
    core.set_serial_sink([&](const uint8_t* data, size_t size) {
      if (pty.unread() > params.pty_backlog_bytes) {
        pty.discard_unread();
        core.count_io("scout_backlog_flushes");
      }
      ssize_t n = ::write(pty.master(), data, size);
      if (n != static_cast<ssize_t>(size)) core.count_io("scout_write_errors");
    });

    // Sim clock: t0 + speed * (wall - t0); the identity at speed 1.
    const int64_t t0 = evade::bus::bus_utime();
    auto sim_now = [&](int64_t wall) { return t0 + std::llround(speed * static_cast<double>(wall - t0)); };
    auto wall_of = [&](int64_t sim) { return t0 + std::llround(static_cast<double>(sim - t0) / speed); };

    bus.add_fd(pty.master(), [&](int64_t wall) {
      uint8_t buf[512];
      ssize_t n = ::read(pty.master(), buf, sizeof(buf));
      if (n > 0) {
        core.input(sim_now(wall), [&] { core.on_serial_bytes(buf, static_cast<size_t>(n)); });
      } else if (n < 0 && errno != EAGAIN && errno != EINTR) {
        core.count_io("scout_read_errors");
      }
    });

    std::fprintf(stderr, "sim: scenario %s (%zu obstacles, %.0f s); Scout on %s -> %s; %s; speed %.2f\n",
                 scenario.name.c_str(), scenario.obstacles.size(), scenario.duration_s, params.device_path.c_str(),
                 pty.slave_path().c_str(), lidar.describe().c_str(), speed);
    const std::atomic<bool>& stop = evade::bus::stop_on_signals();
    core.advance_to(sim_now(evade::bus::bus_utime()));
    while (!stop.load() && !core.finished()) {
      int64_t next = core.next_deadline();
      if (next != evade::bus::kNever) bus.wake_at(wall_of(next));
      bus.spin_once(50);
      core.advance_to(sim_now(evade::bus::bus_utime()));
    }
    if (core.finished()) std::fprintf(stderr, "sim: scenario duration %.0f s reached\n", scenario.duration_s);
  } catch (const evade::config::ConfigError& e) {  // the bus: section
    die(e.what(), 2);
  } catch (const std::invalid_argument& e) {  // a LiDAR the sim cannot simulate with this configuration
    die(e.what(), 2);
  } catch (const std::exception& e) {
    die(e.what());
  }
  return 0;
}
