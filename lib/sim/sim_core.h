// The simulator's process core: the world (robot + obstacles), the LiDAR
// of the scenario's lidar.model (VLP-16 or RS-Helios) and the emulated
// Scout base, driven only by bus time. It never touches a
// socket or a clock: the main (procs/sim) hands it the bytes read from the
// pseudo-terminal (on_serial_bytes, inside Core::input) and gives it two
// sinks, one for the LiDAR packets it produces (sent over UDP) and one for
// the Scout status bytes (written to the pty). Tests run it on a MemoryBus.
//
// Timers: LiDAR packets (each with the port it goes to) are produced as soon as their last firing is past
// (checked every lidar_send_period_us); Scout system + motion status every
// status_period_us; SIM_TRUTH every truth_period_us; HEALTH every second.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "base/scout_protocol.h"
#include "bus/core.h"
#include "config/config.h"
#include "config/fields.h"
#include "config/robot_params.h"
#include "evade/sim_truth_t.hpp"
#include "sim/lidar_sim.h"
#include "sim/motion.h"
#include "sim/robot.h"
#include "sim/scenario.h"

namespace evade::sim {

struct SimParams {
  // Pseudo-terminal link and LiDAR destination (overridable by flags).
  std::string device_path = "/tmp/evade_scout";
  std::string lidar_dest_host = "127.0.0.1";
  int lidar_dest_port = 2368;            // VLP-16 data packets
  int rs_helios_msop_dest_port = 6699;   // RS-Helios point packets
  int rs_helios_difop_dest_port = 7788;  // RS-Helios device info packets
  // The robot's own body as the LiDAR sees it: a box over the footprint
  // from the ground to this height (0: no body). Below the sensor.
  double robot_body_height_m = 0.3;

  int64_t truth_period_us = 20'000;
  int64_t status_period_us = 20'000;
  int64_t lidar_send_period_us = 1'000;
  // A LiDAR more than this behind (a stalled process) drops the packets it
  // missed instead of sending them in a burst.
  int64_t lidar_max_lag_us = 100'000;
  int64_t physics_step_us = 1'000;       // robot kinematics integration step
  int64_t command_timeout_us = 500'000;  // no motion frame for this long: the base brakes
  double lidar_max_range_m = 100.0;      // farther: no return
  uint8_t ground_reflectivity = 20;
  uint8_t obstacle_reflectivity = 100;
  double battery_voltage_v = 25.5;
  // Unread status bytes in the pty beyond which nobody is reading: the
  // queue is flushed so that a driver that (re)connects gets fresh frames.
  int pty_backlog_bytes = 260;
  bool stop_at_duration = true;

  // The shared sections, as loaded by from_config (not in this list): the
  // base's accelerations and the LiDAR's mount.
  config::RobotParams robot;
  config::LidarParams lidar;

  // The `sim:` section. Rates and times are converted to the periods in
  // microseconds the simulator steps by (a converted member carries its
  // own unit).
  template <class V>
  void fields(V& v) {
    v.field("device_path", device_path);
    v.field("lidar_dest_host", lidar_dest_host);
    v.field("lidar_dest_port", lidar_dest_port, config::between(1, 65535));
    v.field("rs_helios_msop_dest_port", rs_helios_msop_dest_port, config::between(1, 65535));
    v.field("rs_helios_difop_dest_port", rs_helios_difop_dest_port, config::between(1, 65535));
    v.rule(rs_helios_msop_dest_port != rs_helios_difop_dest_port, "rs_helios_difop_dest_port",
           "must differ from rs_helios_msop_dest_port");
    v.field("robot_body_height_m", robot_body_height_m, config::between(0.0, 10.0));
    v.convert("truth_rate_hz", truth_period_us, config::hz_as_period_us(config::between(1.0, 10000.0)));
    v.convert("status_rate_hz", status_period_us, config::hz_as_period_us(config::between(1.0, 10000.0)));
    v.convert("lidar_send_period_s", lidar_send_period_us, config::seconds_as_us_rounded(config::between(1e-4, 0.01)));
    v.convert("lidar_max_lag_s", lidar_max_lag_us, config::seconds_as_us_rounded(config::between(0.01, 1.0)));
    v.convert("physics_step_s", physics_step_us, config::seconds_as_us_rounded(config::between(1e-5, 0.01)));
    v.convert("command_timeout_s", command_timeout_us, config::seconds_as_us_rounded(config::positive()));
    v.field("lidar_max_range_m", lidar_max_range_m, config::positive());
    v.convert("ground_reflectivity", ground_reflectivity, byte_converter());
    v.convert("obstacle_reflectivity", obstacle_reflectivity, byte_converter());
    v.field("battery_voltage_v", battery_voltage_v, config::between(0.0, 6553.5));
    v.field("pty_backlog_bytes", pty_backlog_bytes, config::between(2.0 * base::kFrameSize, 1 << 20));
    v.field("stop_at_duration", stop_at_duration);
  }
  static config::Converter<uint8_t> byte_converter();  // 0..255

  // Reads the `sim:` section and the shared `robot:` and `lidar:` ones.
  static SimParams from_config(const config::Node& root);
  // The UDP port a packet goes to.
  int dest_port(const std::string& model, LidarPort port) const;
  // What the simulated base takes: robot's accelerations, this section's
  // physics step and command timeout.
  RobotLimits robot_limits() const;
  // What the simulated LiDAR of `scenario` takes: the scenario's rate,
  // range noise, height and seed, lidar's mount, this section's range and
  // reflectivities.
  LidarSimParams lidar_sim(const Scenario& scenario) const;
};

class SimCore : public bus::Core {
 public:
  using PacketSink = std::function<void(const Packet&)>;
  using SerialSink = std::function<void(const uint8_t* data, size_t size)>;

  // Throws std::invalid_argument when the scenario's LiDAR cannot be
  // simulated with these parameters (model rate, body above the sensor).
  SimCore(const Scenario& scenario, const SimParams& params);
  // The core of the whole configuration (SimParams::from_config) for this
  // scenario; throws ConfigError (file:line: key) or std::invalid_argument.
  static std::unique_ptr<SimCore> from_config(const config::Node& root, const Scenario& scenario);

  void set_packet_sink(PacketSink sink) { packet_sink_ = std::move(sink); }
  void set_serial_sink(SerialSink sink) { serial_sink_ = std::move(sink); }

  // Bytes from the host side of the serial link (call inside Core::input).
  void on_serial_bytes(const uint8_t* data, size_t size);

  // Counts an event seen by the I/O side (a failed send, a flushed
  // backlog) in this core's HEALTH counters.
  void count_io(const std::string& counter) { count(counter); }

  // True once the scenario's duration_s has passed (and stop_at_duration).
  bool finished() const;
  bool started() const { return robot_ != nullptr; }

  // The world at `utime` (robot pose from the robot's history, obstacles
  // from their motion models). Valid once started.
  void world_at(int64_t utime, WorldSnapshot* out) const;
  // The same as the LiDAR sees it: plus the robot's own body, if modelled.
  void lidar_world_at(int64_t utime, WorldSnapshot* out) const;
  evade::sim_truth_t truth_at(int64_t utime);
  const UnicycleRobot* robot() const { return robot_.get(); }
  const Scenario& scenario() const { return scenario_; }
  // Bus time at which obstacles started moving; nullopt while they wait.
  std::optional<int64_t> motion_start_us() const;

 private:
  void start(int64_t now);
  void send_due_packets();
  void send_status();
  void publish_truth();
  void count_parser_errors();

  Scenario scenario_;
  SimParams params_;
  LidarSimParams lidar_params_;
  std::unique_ptr<UnicycleRobot> robot_;
  std::unique_ptr<LidarSimulator> lidar_;
  int64_t start_us_ = 0;
  base::StreamParser parser_;
  base::ParserStats reported_{};
  int64_t reported_timeouts_ = 0;
  uint8_t tx_count_ = 0;
  PacketSink packet_sink_;
  SerialSink serial_sink_;
};

}  // namespace evade::sim
