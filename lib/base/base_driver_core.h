// The base_driver process core: CMD_VEL in, Scout UART v1 bytes out;
// Scout status bytes in, ODOMETRY and BASE_STATUS out. Socket- and
// clock-free: the main (or a test) owns the serial port, feeds received
// bytes through on_serial_bytes() inside Core::input(), reports the port
// opening/closing, and writes whatever take_tx() returns.
//
// Behaviour:
// - Every command period (config command_rate_hz, 50 Hz) one motion command
//   frame is queued while the port is open: the latest CMD_VEL clamped to
//   the robot's velocity limits and rate-limited by its acceleration limits
//   (see limit_step in kinematics.h).
// - A CMD_VEL stamped more than cmd_vel_max_age_s before (or after) the bus
//   time it arrives at is late (or from a skewed clock) and ignored,
//   counted as cmd_vel_late / cmd_vel_future: it does not feed the watchdog.
// - Watchdog: when no CMD_VEL has arrived for watchdog_timeout_s (or none
//   ever), zero velocity is commanded at once (the upstream planner is gone;
//   stopping is the safe state and the base's own controller brakes) and
//   BASE_STATUS.watchdog_tripped is true. The next CMD_VEL clears it and the
//   command ramps up again from zero under the acceleration limits.
// - Odometry: every motion-status frame publishes ODOMETRY stamped with its
//   receive time. The pose is integrated with the exact arc over the time
//   since the previous motion-status frame, holding the previous frame's
//   velocity (the one in force during that interval). Intervals longer than
//   max_odometry_gap_s are not integrated (the base's motion in a gap is
//   unknown) and counted.
// - Link: link_ok = port open and a valid status frame within
//   link_timeout_s. While it is not ok every motion frame sent is zero
//   speed (the base may still be listening), so after a silent link the
//   robot does not resume on a stale command. When the link is lost the
//   robot is considered stopped: one ODOMETRY with v = omega = 0 is
//   published at the current pose, stamped with the time of the last real
//   one (so no consumer takes it for a fresh measurement), integration
//   restarts at the next motion status, and the command ramp restarts from
//   zero.
// - ODOMETRY.epoch is params.epoch (the driver's start time, set by its
//   main): odometry of one epoch is one continuous frame; a new epoch (a
//   restarted driver, its pose reset) tells the planner and the map to
//   start over.
// - E-stop: a (signed) ESTOP with engaged = true latches the stop: from
//   then on every motion frame is zero and every CMD_VEL is ignored
//   (counted cmd_vel_during_estop), until an ESTOP with engaged = false,
//   stamped within cmd_vel_max_age_s of its arrival, releases it. After a
//   release the robot waits for a new CMD_VEL and ramps up from zero.
//   BASE_STATUS.estop_engaged tells the state.
// - stop(): queues one zero-speed frame, whatever the state (a main being
//   stopped by a signal sends it before closing the port).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/kinematics.h"
#include "base/scout_protocol.h"
#include "bus/core.h"
#include "config/config.h"
#include "config/fields.h"

namespace evade::base {

inline constexpr const char* kCmdVelChannel = "CMD_VEL";
inline constexpr const char* kOdometryChannel = "ODOMETRY";
inline constexpr const char* kBaseStatusChannel = "BASE_STATUS";
inline constexpr const char* kEstopChannel = "ESTOP";

struct BaseDriverParams {
  std::string device = "/tmp/evade_scout";  // serial device (a pty symlink for the simulator)
  int baud_rate = 115200;
  double command_rate_hz = 50.0;
  double watchdog_timeout_s = 0.25;
  double cmd_vel_max_age_s = 0.4;
  double link_timeout_s = 0.5;
  double status_rate_hz = 10.0;  // BASE_STATUS heartbeat (also sent on every change)
  double max_odometry_gap_s = 0.5;
  double reopen_backoff_min_s = 0.1;
  double reopen_backoff_max_s = 2.0;
  Pose2 initial_pose;     // [x m, y m, yaw rad] in the YAML; yaw wrapped to (-pi, pi]
  VelocityLimits limits;  // robot: (config/robot_params.h), not in this section's list
  int64_t epoch = 0;      // ODOMETRY.epoch: not from config; the main sets its start time

  // The `base_driver:` section.
  template <class V>
  void fields(V& v) {
    v.field("device", device);
    v.rule(!device.empty(), "device", "must not be empty");
    v.choice("baud_rate", baud_rate,
             config::Choices<int>{{"9600", 9600},
                                  {"19200", 19200},
                                  {"38400", 38400},
                                  {"57600", 57600},
                                  {"115200", 115200},
                                  {"230400", 230400},
                                  {"460800", 460800}});
    v.field("command_rate_hz", command_rate_hz, config::between(1.0, 1000.0));
    v.field("watchdog_timeout_s", watchdog_timeout_s, config::between(0.001, 10.0));
    v.field("cmd_vel_max_age_s", cmd_vel_max_age_s, config::between(0.001, 10.0));
    v.field("link_timeout_s", link_timeout_s, config::between(0.001, 10.0));
    v.field("status_rate_hz", status_rate_hz, config::between(0.1, 1000.0));
    v.field("max_odometry_gap_s", max_odometry_gap_s, config::between(0.001, 10.0));
    v.field("reopen_backoff_min_s", reopen_backoff_min_s, config::between(0.001, 60.0));
    v.field("reopen_backoff_max_s", reopen_backoff_max_s, config::between(reopen_backoff_min_s, 600.0));
    v.convert("initial_pose", initial_pose, pose_converter());
  }
  static config::Converter<Pose2> pose_converter();

  // Reads the `base_driver:` section (closed) and the velocity and
  // acceleration limits of the shared `robot:` section (not closed: other
  // processes own its other keys).
  static BaseDriverParams from_config(const config::Node& root);
};

// Parses "X,Y,YAW" (metres, metres, radians); throws std::invalid_argument.
Pose2 parse_pose(const std::string& text);

// What a run sets beside the configuration: the command line's device and
// start pose (empty: the configuration's), and ODOMETRY.epoch (0 in a
// replay or lockstep run, which stay deterministic).
struct BaseDriverRun {
  std::string device;
  std::optional<Pose2> initial_pose;
  int64_t epoch = 0;
};

class BaseDriverCore : public bus::Core {
 public:
  explicit BaseDriverCore(const BaseDriverParams& params);
  // The core of the whole configuration (BaseDriverParams::from_config)
  // for this run; throws ConfigError (file:line: key).
  static std::unique_ptr<BaseDriverCore> from_config(const config::Node& root, const BaseDriverRun& run = {});

  // ---- called by the I/O owner, inside Core::input(now, ...) ----
  void on_serial_bytes(const uint8_t* data, size_t size);
  void on_link_opened();
  void on_link_lost(const std::string& reason);
  // Queues one zero-speed motion frame and holds the command at zero.
  void stop();
  // Bytes queued for the port since the last call.
  std::vector<uint8_t> take_tx();
  // Serial-side events the I/O owner counts in this core's HEALTH
  // (serial_open_failures, serial_tx_dropped_bytes, serial_ports_leaked).
  void count_link_event(const std::string& counter, int64_t n = 1) { count(counter, n); }

  // ---- state, for tests and logs ----
  const Pose2& pose() const { return pose_; }
  const Twist& commanded() const { return commanded_; }
  const Twist& measured() const { return measured_; }
  bool watchdog_tripped() const { return watchdog_tripped_; }
  bool estop_engaged() const { return estop_; }
  bool link_ok() const { return link_ok_; }
  bool port_open() const { return port_open_; }
  const ParserStats& parser_stats() const { return parser_.stats(); }
  const BaseDriverParams& params() const { return params_; }

 private:
  void on_cmd_vel(int64_t utime, double v, double omega);
  void on_estop(int64_t utime, bool engaged);
  // Saturating now() - utime.
  int64_t age_of(int64_t utime) const;
  void queue_motion_frame();
  void command_tick();
  // Trips the watchdog if CMD_VEL is stale at now(); true if it just tripped.
  bool update_watchdog();
  void on_frame(const Frame& frame);
  void on_motion_status(const MotionStatus& status);
  void set_link_ok(bool ok, const std::string& why);
  void publish_status();
  void publish_odometry(int64_t utime, double v, double omega);
  void sync_parser_counters();

  BaseDriverParams params_;
  int64_t command_period_us_;
  StreamParser parser_;
  ParserStats reported_;  // parser figures already passed to count()

  // command side
  bool have_cmd_ = false;
  int64_t last_cmd_now_ = 0;
  Twist target_;
  Twist commanded_;
  bool watchdog_tripped_ = true;  // until the first CMD_VEL
  bool estop_ = false;            // latched by ESTOP engaged, cleared by a release
  uint8_t tx_count_ = 0;
  std::vector<uint8_t> tx_;

  // status side
  bool port_open_ = false;
  bool link_ok_ = false;
  int64_t last_status_now_ = -1;  // receive time of the last valid status frame
  SystemStatus system_;
  bool have_system_ = false;
  Twist measured_;
  Pose2 pose_;
  bool have_motion_ = false;  // integration anchor valid
  int64_t last_motion_now_ = 0;
};

}  // namespace evade::base
