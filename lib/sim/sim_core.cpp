#include "sim/sim_core.h"

#include <cmath>
#include <stdexcept>

namespace evade::sim {
namespace {
int64_t us_from_s(double s) { return std::llround(s * 1e6); }
}  // namespace

config::Converter<uint8_t> SimParams::byte_converter() {
  return {[](const config::Node& n, const std::string& key) { return static_cast<uint8_t>(n.get_int(key, 0, 255)); },
          [](const uint8_t& b) { return config::number_node(b); }};
}

SimParams SimParams::from_config(const config::Node& root) {
  SimParams p = config::load<SimParams>(root.section("sim"));
  p.robot = config::load<config::RobotParams>(root.section("robot"));
  p.lidar = config::load<config::LidarParams>(root.section("lidar"));
  return p;
}

RobotLimits SimParams::robot_limits() const {
  RobotLimits l;
  l.max_accel_mps2 = robot.max_accel_mps2;
  l.max_decel_mps2 = robot.max_decel_mps2;
  l.max_alpha_radps2 = robot.max_alpha_radps2;
  l.command_timeout_us = command_timeout_us;
  l.step_us = physics_step_us;
  return l;
}

LidarSimParams SimParams::lidar_sim(const Scenario& scenario) const {
  LidarSimParams l;
  l.rate_hz = scenario.lidar.rate_hz;
  l.range_noise_std_m = scenario.lidar.range_noise_std;
  l.max_range_m = lidar_max_range_m;
  l.mount_x_m = lidar.mount.x_m;
  l.mount_y_m = lidar.mount.y_m;
  l.mount_height_m = scenario.lidar.height;
  l.mount_roll_rad = lidar.mount.roll_rad;
  l.mount_pitch_rad = lidar.mount.pitch_rad;
  l.mount_yaw_rad = lidar.mount.yaw_rad;
  l.noise_seed = scenario.seed;
  l.ground_reflectivity = ground_reflectivity;
  l.obstacle_reflectivity = obstacle_reflectivity;
  return l;
}

int SimParams::dest_port(const std::string& model, LidarPort port) const {
  if (model == "vlp16") return lidar_dest_port;
  return port == LidarPort::kDifop ? rs_helios_difop_dest_port : rs_helios_msop_dest_port;
}

std::unique_ptr<SimCore> SimCore::from_config(const config::Node& root, const Scenario& scenario) {
  return std::make_unique<SimCore>(scenario, SimParams::from_config(root));
}

SimCore::SimCore(const Scenario& scenario, const SimParams& params)
    : bus::Core("sim"), scenario_(scenario), params_(params) {
  if (!robot_resolved(scenario_))
    throw std::invalid_argument("scenario " + scenario_.name +
                                ": its robot (footprint, lidar model and height) is not resolved from the robot "
                                "configuration (sim::resolve_robot)");
  lidar_params_ = params_.lidar_sim(scenario_);
  if (params_.robot_body_height_m >= lidar_params_.mount_height_m)
    throw std::invalid_argument("sim.robot_body_height_m must be below the LiDAR (scenario lidar.height)");
  make_lidar_simulator(scenario_.lidar.model, lidar_params_, 0);  // refuses what it cannot simulate, now

  every(params_.lidar_send_period_us, [this] {
    start(now());
    send_due_packets();
  });
  every(params_.status_period_us, [this] {
    start(now());
    send_status();
  });
  every(params_.truth_period_us, [this] {
    start(now());
    publish_truth();
  });
}

void SimCore::start(int64_t now) {
  if (robot_) return;
  start_us_ = now;
  robot_ = std::make_unique<UnicycleRobot>(scenario_.start, params_.robot_limits(), now);
  lidar_ = make_lidar_simulator(scenario_.lidar.model, lidar_params_, now);
}

bool SimCore::finished() const {
  return robot_ && params_.stop_at_duration && now() - start_us_ >= us_from_s(scenario_.duration_s);
}

std::optional<int64_t> SimCore::motion_start_us() const {
  if (!robot_) return std::nullopt;
  if (scenario_.obstacles_start == ObstaclesStart::kAtStart) return start_us_;
  if (robot_->first_motion_us() >= 0) return robot_->first_motion_us();
  return std::nullopt;
}

void SimCore::world_at(int64_t utime, WorldSnapshot* out) const {
  out->robot = robot_->pose_at(utime);
  out->solids.resize(scenario_.obstacles.size());
  std::optional<int64_t> t0 = motion_start_us();
  double t_s = t0 ? (utime - *t0) * 1e-6 : 0.0;
  for (size_t i = 0; i < scenario_.obstacles.size(); ++i) {
    const ObstacleSpec& o = scenario_.obstacles[i];
    ObstacleState st = obstacle_state(o, t_s);
    Solid& s = out->solids[i];
    s.shape = o.shape;
    s.x = st.x;
    s.y = st.y;
    s.yaw = o.yaw;
    s.radius = o.radius;
    s.length = o.length;
    s.width = o.width;
    s.height = o.height;
  }
}

void SimCore::lidar_world_at(int64_t utime, WorldSnapshot* out) const {
  world_at(utime, out);
  if (params_.robot_body_height_m <= 0.0) return;
  Solid body;
  body.shape = Shape::kBox;
  body.x = out->robot.x;
  body.y = out->robot.y;
  body.yaw = out->robot.yaw;
  body.length = scenario_.footprint_length;
  body.width = scenario_.footprint_width;
  body.height = params_.robot_body_height_m;
  out->solids.push_back(body);
}

void SimCore::send_due_packets() {
  robot_->advance_to(now());
  WorldAt world = [this](int64_t t, WorldSnapshot* out) { lidar_world_at(t, out); };
  while (lidar_->next_packet_ready_us() <= now()) {
    if (now() - lidar_->next_packet_ready_us() > params_.lidar_max_lag_us) {
      lidar_->skip_packet();
      count("lidar_packets_skipped");
      continue;
    }
    Packet packet = lidar_->make_packet(world);
    count("lidar_packets");
    if (packet_sink_) packet_sink_(packet);
  }
}

void SimCore::send_status() {
  robot_->advance_to(now());
  base::SystemStatus sys;
  sys.base_state = 0;  // normal
  sys.control_mode = robot_->commanded_recently(now()) ? base::kControlModeSerial : base::kControlModeStandby;
  sys.battery_decivolts = base::battery_decivolts(params_.battery_voltage_v);
  sys.fault_code = 0;
  base::MotionStatus motion;
  motion.linear_mm_s = base::linear_mm_s(robot_->v());
  motion.angular_mrad_s = base::angular_mrad_s(robot_->omega());
  base::FrameBytes a = base::encode(sys, tx_count_++);
  base::FrameBytes b = base::encode(motion, tx_count_++);
  uint8_t bytes[2 * base::kFrameSize];
  std::copy(a.begin(), a.end(), bytes);
  std::copy(b.begin(), b.end(), bytes + base::kFrameSize);
  count("scout_status_frames", 2);
  if (robot_->command_timeouts() != reported_timeouts_) {
    count("scout_command_timeouts", robot_->command_timeouts() - reported_timeouts_);
    reported_timeouts_ = robot_->command_timeouts();
  }
  if (serial_sink_) serial_sink_(bytes, sizeof(bytes));
}

void SimCore::on_serial_bytes(const uint8_t* data, size_t size) {
  start(now());
  robot_->advance_to(now());
  parser_.feed(data, size, [this](const base::Frame& f) {
    if (f.type != base::kTypeCommand) {
      count("scout_unexpected_status_frames");
      return;
    }
    base::MotionCommand cmd;
    base::LightState light;
    if (base::from_frame(f, &cmd)) {
      if (cmd.control_mode != base::kControlModeSerial) {
        // The real base ignores motion commands unless serial control is selected.
        count("scout_commands_not_serial_mode");
        return;
      }
      robot_->command(base::linear_from_percent(cmd.linear_percent), base::angular_from_percent(cmd.angular_percent),
                      now());
      count("scout_motion_commands");
    } else if (base::light_command_from_frame(f, &light)) {
      count("scout_light_commands");  // the simulated base has no lights to show
    } else {
      count("scout_unknown_frames");
    }
  });
  count_parser_errors();
}

void SimCore::count_parser_errors() {
  const base::ParserStats& s = parser_.stats();
  if (s.noise_bytes != reported_.noise_bytes)
    count("scout_noise_bytes", static_cast<int64_t>(s.noise_bytes - reported_.noise_bytes));
  if (s.bad_length != reported_.bad_length)
    count("scout_bad_length", static_cast<int64_t>(s.bad_length - reported_.bad_length));
  if (s.bad_checksum != reported_.bad_checksum)
    count("scout_bad_checksum", static_cast<int64_t>(s.bad_checksum - reported_.bad_checksum));
  if (s.bad_type != reported_.bad_type) count("scout_bad_type", static_cast<int64_t>(s.bad_type - reported_.bad_type));
  reported_ = s;
}

evade::sim_truth_t SimCore::truth_at(int64_t utime) {
  robot_->advance_to(utime);
  evade::sim_truth_t t;
  t.utime = utime;
  Pose2 p = robot_->pose_at(utime);
  t.x = p.x;
  t.y = p.y;
  t.yaw = p.yaw;
  t.v = robot_->v();
  t.omega = robot_->omega();
  t.footprint_length = scenario_.footprint_length;
  t.footprint_width = scenario_.footprint_width;
  t.scenario = scenario_.name;
  t.goal_x = scenario_.goal.x;
  t.goal_y = scenario_.goal.y;
  t.goal_tolerance = scenario_.goal_tolerance;
  t.duration_s = scenario_.duration_s;
  std::optional<int64_t> t0 = motion_start_us();
  t.obstacles_moving = t0.has_value();
  double t_s = t0 ? (utime - *t0) * 1e-6 : 0.0;
  for (const ObstacleSpec& o : scenario_.obstacles) {
    ObstacleState st = obstacle_state(o, t_s);
    evade::sim_obstacle_t m;
    m.id = o.id;
    m.shape = o.shape == Shape::kCylinder ? "cylinder" : "box";
    m.x = st.x;
    m.y = st.y;
    m.yaw = o.yaw;
    m.radius = o.radius;
    m.length = o.length;
    m.width = o.width;
    m.height = o.height;
    m.vx = st.vx;
    m.vy = st.vy;
    t.obstacles.push_back(m);
  }
  t.num_obstacles = static_cast<int32_t>(t.obstacles.size());
  t.lidar_returns = lidar_->returns_last_revolution(t.obstacles.size());
  return t;
}

void SimCore::publish_truth() { publish("SIM_TRUTH", truth_at(now())); }

}  // namespace evade::sim
