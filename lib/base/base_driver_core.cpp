#include "base/base_driver_core.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "config/robot_params.h"
#include "evade/base_status_t.hpp"
#include "evade/cmd_vel_t.hpp"
#include "evade/estop_t.hpp"
#include "evade/odometry_t.hpp"

namespace evade::base {

namespace {
constexpr double kUsPerS = 1e6;
int64_t to_us(double seconds) { return static_cast<int64_t>(std::llround(seconds * kUsPerS)); }
}  // namespace

config::Converter<Pose2> BaseDriverParams::pose_converter() {
  return {[](const config::Node& n, const std::string& key) {
            const std::vector<double> pose = n.get_doubles(key, 3);
            return Pose2{pose[0], pose[1], wrap_angle(pose[2])};
          },
          [](const Pose2& p) {
            YAML::Node list(YAML::NodeType::Sequence);
            for (double v : {p.x, p.y, p.yaw}) list.push_back(config::number_node(v));
            return list;
          }};
}

BaseDriverParams BaseDriverParams::from_config(const config::Node& root) {
  const config::Node robot_node = root.section("robot");
  const config::RobotParams robot = config::load<config::RobotParams>(robot_node);
  if (robot.max_v_mps > kMaxLinearMps)
    robot_node.fail("max_v_mps", "above the Scout's " + config::number_text(kMaxLinearMps) + " m/s");
  if (robot.max_omega_radps > kMaxAngularRadps)
    robot_node.fail("max_omega_radps", "above the Scout's " + config::number_text(kMaxAngularRadps) + " rad/s");
  BaseDriverParams p = config::load<BaseDriverParams>(root.section("base_driver"));
  p.limits.max_v_mps = robot.max_v_mps;
  p.limits.min_v_mps = robot.min_v_mps;
  p.limits.max_omega_radps = robot.max_omega_radps;
  p.limits.max_accel_mps2 = robot.max_accel_mps2;
  p.limits.max_decel_mps2 = robot.max_decel_mps2;
  p.limits.max_alpha_radps2 = robot.max_alpha_radps2;
  return p;
}

Pose2 parse_pose(const std::string& text) {
  std::stringstream ss(text);
  std::string item;
  double v[3];
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n == 3) throw std::invalid_argument("expected X,Y,YAW, got '" + text + "'");
    size_t used = 0;
    try {
      v[n] = std::stod(item, &used);
    } catch (const std::exception&) {
      throw std::invalid_argument("not a number: '" + item + "' in '" + text + "'");
    }
    if (used != item.size() || !std::isfinite(v[n]))
      throw std::invalid_argument("not a finite number: '" + item + "' in '" + text + "'");
    ++n;
  }
  if (n != 3) throw std::invalid_argument("expected X,Y,YAW, got '" + text + "'");
  return Pose2{v[0], v[1], wrap_angle(v[2])};
}

std::unique_ptr<BaseDriverCore> BaseDriverCore::from_config(const config::Node& root, const BaseDriverRun& run) {
  BaseDriverParams params = BaseDriverParams::from_config(root);
  if (!run.device.empty()) params.device = run.device;
  if (run.initial_pose) params.initial_pose = *run.initial_pose;
  params.epoch = run.epoch;
  return std::make_unique<BaseDriverCore>(params);
}

BaseDriverCore::BaseDriverCore(const BaseDriverParams& params)
    : bus::Core("base_driver"),
      params_(params),
      command_period_us_(std::max<int64_t>(1, to_us(1.0 / params.command_rate_hz))),
      pose_(params.initial_pose) {
  subscribe<evade::cmd_vel_t>(kCmdVelChannel, [this](const evade::cmd_vel_t& m) { on_cmd_vel(m.utime, m.v, m.omega); });
  subscribe<evade::estop_t>(kEstopChannel, [this](const evade::estop_t& m) { on_estop(m.utime, m.engaged); });
  every(command_period_us_, [this] { command_tick(); });
  every(std::max<int64_t>(1, to_us(1.0 / params.status_rate_hz)), [this] { publish_status(); });
}

// ------------------------------------------------------------- commands ----

int64_t BaseDriverCore::age_of(int64_t utime) const {
  // saturating: utime may be anything a sender put there
  int64_t age;
  if (__builtin_sub_overflow(now(), utime, &age)) age = utime < 0 ? bus::kNever : -bus::kNever;
  return age;
}

void BaseDriverCore::on_estop(int64_t utime, bool engaged) {
  if (engaged) {
    // Stopping is always safe: no age check beyond the bus's window.
    if (!estop_) count("estop_engaged");
    estop_ = true;
    target_ = Twist{};
    commanded_ = Twist{};
    publish_status();
    return;
  }
  const int64_t age = age_of(utime);
  const int64_t max_age = to_us(params_.cmd_vel_max_age_s);
  if (age > max_age || age < -max_age) {
    count("estop_release_late");
    return;
  }
  if (!estop_) return;
  estop_ = false;
  count("estop_released");
  // Nothing said before the release drives the robot: a new CMD_VEL must come.
  have_cmd_ = false;
  watchdog_tripped_ = true;
  publish_status();
}

void BaseDriverCore::on_cmd_vel(int64_t utime, double v, double omega) {
  if (estop_) {
    count("cmd_vel_during_estop");
    return;
  }
  if (!std::isfinite(v) || !std::isfinite(omega)) {
    count("cmd_vel_not_finite");
    return;
  }
  const int64_t max_age = to_us(params_.cmd_vel_max_age_s);
  const int64_t age = age_of(utime);
  if (age > max_age) {
    count("cmd_vel_late");
    return;
  }
  if (age < -max_age) {
    count("cmd_vel_future");
    return;
  }
  target_ = Twist{v, omega};
  last_cmd_now_ = now();
  have_cmd_ = true;
  if (watchdog_tripped_) {
    watchdog_tripped_ = false;
    publish_status();
  }
}

bool BaseDriverCore::update_watchdog() {
  const bool stale = !have_cmd_ || now() - last_cmd_now_ > to_us(params_.watchdog_timeout_s);
  if (!stale || watchdog_tripped_) return false;
  watchdog_tripped_ = true;
  commanded_ = Twist{};
  count("watchdog_trips");
  return true;
}

void BaseDriverCore::command_tick() {
  // Link supervision shares the command clock: a port that is open but has
  // been silent for link_timeout_s is a lost link.
  if (link_ok_ && now() - last_status_now_ > to_us(params_.link_timeout_s)) {
    char why[64];
    std::snprintf(why, sizeof why, "no status frame for %.2f s", params_.link_timeout_s);
    set_link_ok(false, why);
  }

  if (update_watchdog()) publish_status();
  if (estop_ || watchdog_tripped_ || !link_ok_) {
    // e-stop, no planner, or no word from the base: zero until all are clear
    commanded_ = Twist{};
  } else {
    commanded_ = limit_step(commanded_, target_, params_.limits, command_period_us_ / kUsPerS);
  }
  if (!port_open_) return;  // nothing to send to; the ramp restarts when it opens
  queue_motion_frame();
}

void BaseDriverCore::stop() {
  target_ = Twist{};
  commanded_ = Twist{};
  have_cmd_ = false;
  watchdog_tripped_ = true;
  queue_motion_frame();
  count("stopped");
}

void BaseDriverCore::queue_motion_frame() {
  MotionCommand cmd;
  cmd.control_mode = kControlModeSerial;
  cmd.linear_percent = linear_percent(commanded_.v);
  cmd.angular_percent = angular_percent(commanded_.omega);
  FrameBytes bytes = encode(cmd, tx_count_++);
  tx_.insert(tx_.end(), bytes.begin(), bytes.end());
  count("commands_sent");
}

std::vector<uint8_t> BaseDriverCore::take_tx() {
  std::vector<uint8_t> out;
  out.swap(tx_);
  return out;
}

// --------------------------------------------------------------- status ----

void BaseDriverCore::on_serial_bytes(const uint8_t* data, size_t size) {
  parser_.feed(data, size, [this](const Frame& f) { on_frame(f); });
  sync_parser_counters();
}

void BaseDriverCore::sync_parser_counters() {
  const ParserStats& s = parser_.stats();
  auto delta = [this](const char* name, uint64_t now_value, uint64_t& reported) {
    if (now_value != reported) count(name, static_cast<int64_t>(now_value - reported));
    reported = now_value;
  };
  delta("serial_frames", s.frames, reported_.frames);
  delta("serial_noise_bytes", s.noise_bytes, reported_.noise_bytes);
  delta("serial_bad_length", s.bad_length, reported_.bad_length);
  delta("serial_bad_checksum", s.bad_checksum, reported_.bad_checksum);
  delta("serial_bad_type", s.bad_type, reported_.bad_type);
}

void BaseDriverCore::on_frame(const Frame& frame) {
  if (frame.type != kTypeStatus) {
    count("serial_unexpected_command_frame");  // our own commands echoed back?
    return;
  }
  last_status_now_ = now();
  if (!link_ok_ && port_open_) set_link_ok(true, "status frames arriving");

  SystemStatus sys;
  MotionStatus motion;
  MotorStatus motor;
  LightState light;
  if (from_frame(frame, &motion)) {
    on_motion_status(motion);
  } else if (from_frame(frame, &sys)) {
    const bool changed = !have_system_ || sys.base_state != system_.base_state ||
                         sys.fault_code != system_.fault_code || sys.control_mode != system_.control_mode;
    system_ = sys;
    have_system_ = true;
    count("system_status_frames");
    if (changed) publish_status();
  } else if (from_frame(frame, &motor)) {
    count("motor_status_frames");
  } else if (light_status_from_frame(frame, &light)) {
    count("light_status_frames");
  } else {
    count("serial_unknown_status_id");
  }
}

void BaseDriverCore::on_motion_status(const MotionStatus& status) {
  count("motion_status_frames");
  const int64_t t = now();
  if (have_motion_) {
    const int64_t dt_us = t - last_motion_now_;
    if (dt_us > 0 && dt_us <= to_us(params_.max_odometry_gap_s)) {
      // Zero-order hold of the previous measurement over [t_prev, t].
      pose_ = integrate_arc(pose_, measured_.v, measured_.omega, dt_us / kUsPerS);
    } else if (dt_us > 0) {
      count("odometry_gaps");
    } else {
      count("odometry_time_not_increasing");
    }
  }
  measured_ = Twist{linear_mps(status), angular_radps(status)};
  last_motion_now_ = t;
  have_motion_ = true;
  publish_odometry(t, measured_.v, measured_.omega);
}

void BaseDriverCore::publish_odometry(int64_t utime, double v, double omega) {
  evade::odometry_t m{};
  m.utime = utime;
  m.epoch = params_.epoch;
  m.x = pose_.x;
  m.y = pose_.y;
  m.yaw = pose_.yaw;
  m.v = v;
  m.omega = omega;
  publish(kOdometryChannel, m);
}

void BaseDriverCore::publish_status() {
  // Evaluated here too, so that BASE_STATUS is right even when it is
  // published between command ticks (or the command timer was skipped).
  update_watchdog();
  evade::base_status_t m;
  m.utime = now();
  m.state = static_cast<int8_t>(system_.base_state);
  m.control_mode = static_cast<int8_t>(system_.control_mode);
  m.battery_voltage = have_system_ ? battery_volts(system_) : 0.0;
  m.fault_code = system_.fault_code;
  m.watchdog_tripped = watchdog_tripped_;
  m.link_ok = link_ok_;
  m.estop_engaged = estop_;
  m.commanded_v = commanded_.v;
  m.commanded_omega = commanded_.omega;
  m.measured_v = link_ok_ ? measured_.v : 0.0;
  m.measured_omega = link_ok_ ? measured_.omega : 0.0;
  publish(kBaseStatusChannel, m);
}

// ----------------------------------------------------------------- link ----

void BaseDriverCore::on_link_opened() {
  port_open_ = true;
  parser_.reset();  // bytes of the previous connection mean nothing now
  commanded_ = Twist{};
  count("link_opened");
  publish_status();
}

void BaseDriverCore::on_link_lost(const std::string& reason) {
  port_open_ = false;
  parser_.reset();
  tx_.clear();
  set_link_ok(false, reason);
}

void BaseDriverCore::set_link_ok(bool ok, const std::string& why) {
  if (ok == link_ok_) {
    if (!ok) publish_status();  // e.g. the port closed while already silent
    return;
  }
  link_ok_ = ok;
  std::fprintf(stderr, "base_driver: link %s (%s)\n", ok ? "up" : "lost", why.c_str());
  if (!ok) {
    count("link_lost");
    // The robot is considered stopped: say so once, at the current pose, and
    // do not integrate across the outage. Stamped with the last real
    // odometry's time: the pose is from then, and nothing measured it since.
    const bool had_motion = have_motion_;
    measured_ = Twist{};
    have_motion_ = false;
    commanded_ = Twist{};
    if (had_motion) publish_odometry(last_motion_now_, 0.0, 0.0);
  }
  publish_status();
}

}  // namespace evade::base
