// The base_driver core on the in-memory bus: limits and acceleration ramp,
// watchdog, exact-arc odometry, parser counters in HEALTH, link supervision.
// Serial bytes are handed to the core directly here; base_driver_pty_test
// runs the same core against a real pseudo-terminal.
#include "base/base_driver_core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "bus/auth.h"
#include "bus/memory_bus.h"
#include "config/config.h"
#include "evade/base_status_t.hpp"
#include "evade/cmd_vel_t.hpp"
#include "evade/estop_t.hpp"
#include "evade/health_t.hpp"
#include "evade/odometry_t.hpp"

namespace evade::base {
namespace {

constexpr int64_t kT0 = 1'000'000'000;  // us; any start time
constexpr int64_t kTick = 20'000;       // 50 Hz

BaseDriverParams test_params() {
  BaseDriverParams p;  // the defaults documented in the header = robot.yaml
  p.limits = VelocityLimits{-1.0, 1.0, 0.5, 1.0, 1.5, 3.0};
  return p;
}

evade::cmd_vel_t cmd(double v, double omega, int64_t utime = 0) {
  evade::cmd_vel_t m{};
  m.utime = utime;
  m.v = v;
  m.omega = omega;
  return m;
}

// Decodes every 13-byte motion command in a tx buffer.
std::vector<MotionCommand> commands(const std::vector<uint8_t>& tx) {
  std::vector<MotionCommand> out;
  StreamParser p;
  p.feed(tx.data(), tx.size(), [&](const Frame& f) {
    MotionCommand c;
    if (from_frame(f, &c)) out.push_back(c);
  });
  EXPECT_EQ(tx.size(), out.size() * kFrameSize);
  return out;
}

struct Rig {
  explicit Rig(const BaseDriverParams& p = test_params()) : core(p) {
    core.set_measure_latency(false);
    bus.add(core);
    bus.input(core, kT0, [&] { core.on_link_opened(); });
  }
  void serial(int64_t t, const std::vector<uint8_t>& bytes) {
    bus.input(core, t, [&] { core.on_serial_bytes(bytes.data(), bytes.size()); });
  }
  template <class Msg>
  void status(int64_t t, const Msg& msg, uint8_t count = 0) {
    FrameBytes b = encode(msg, count);
    serial(t, std::vector<uint8_t>(b.begin(), b.end()));
  }
  // Moves bus time forward one command period at a time (one jump of more
  // than Core::kMaxCatchUp periods would be a stalled process, which skips).
  // With base_alive, the base sends a system status frame just before each
  // step (the link is ok; without it every motion frame is zero).
  void run_to(int64_t t) {
    for (int64_t u = last_run_ + kTick; u < t; u += kTick) step(u);
    step(t);
    last_run_ = t;
  }
  void step(int64_t u) {
    if (base_alive) status(u - 1, SystemStatus{});
    bus.advance_to(u);
  }
  bool base_alive = false;
  bus::MemoryBus bus;
  BaseDriverCore core;
  int64_t last_run_ = kT0;
};

TEST(BaseDriverConfig, ReadsRobotYaml) {
  auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  BaseDriverParams p = BaseDriverParams::from_config(root);
  EXPECT_EQ(p.device, "/tmp/evade_scout");
  EXPECT_EQ(p.baud_rate, 115200);
  EXPECT_DOUBLE_EQ(p.command_rate_hz, 50.0);
  EXPECT_DOUBLE_EQ(p.watchdog_timeout_s, 0.25);
  EXPECT_DOUBLE_EQ(p.limits.max_v_mps, 1.0);
  EXPECT_DOUBLE_EQ(p.limits.min_v_mps, 0.0);
  EXPECT_DOUBLE_EQ(p.limits.max_omega_radps, 0.5);
}

TEST(BaseDriverConfig, UnknownKeyIsAnError) {
  auto root = config::load_string(
      "robot: {footprint_length_m: 0.42, footprint_width_m: 0.31, max_v_mps: 1.0, min_v_mps: 0.0,\n"
      "        max_omega_radps: 0.5, max_accel_mps2: 1.0, max_decel_mps2: 1.5, max_alpha_radps2: 3.0}\n"
      "base_driver: {device: /dev/ttyUSB0, baud_rate: 115200, command_rate_hz: 50.0,\n"
      "  watchdog_timeout_s: 0.25, cmd_vel_max_age_s: 0.4, link_timeout_s: 0.5, status_rate_hz: 10.0, "
      "max_odometry_gap_s: 0.5,\n"
      "  reopen_backoff_min_s: 0.1, reopen_backoff_max_s: 2.0, initial_pose: [0, 0, 0], watchdog_s: 1}\n",
      "test.yaml");
  try {
    BaseDriverParams::from_config(root);
    FAIL() << "expected ConfigError";
  } catch (const config::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("watchdog_s"), std::string::npos) << e.what();
  }
}

TEST(BaseDriverConfig, ParsesInitialPose) {
  Pose2 p = parse_pose("-10,0.5,3.5");
  EXPECT_DOUBLE_EQ(p.x, -10.0);
  EXPECT_DOUBLE_EQ(p.y, 0.5);
  EXPECT_NEAR(p.yaw, 3.5 - 2 * M_PI, 1e-12);  // wrapped
  EXPECT_THROW(parse_pose("1,2"), std::invalid_argument);
  EXPECT_THROW(parse_pose("1,2,3,4"), std::invalid_argument);
  EXPECT_THROW(parse_pose("1,x,3"), std::invalid_argument);
  EXPECT_THROW(parse_pose("1,2,nan"), std::invalid_argument);
}

TEST(Kinematics, LimitStepRampsAndBrakes) {
  VelocityLimits lim{-1.0, 1.0, 0.5, 1.0, 1.5, 3.0};
  Twist t = limit_step({0.0, 0.0}, {2.0, -2.0}, lim, 0.1);
  EXPECT_NEAR(t.v, 0.1, 1e-12);       // accel 1.0 * 0.1 s
  EXPECT_NEAR(t.omega, -0.3, 1e-12);  // alpha 3.0 * 0.1 s
  t = limit_step({0.5, 0.0}, {0.0, 0.0}, lim, 0.1);
  EXPECT_NEAR(t.v, 0.35, 1e-12);  // braking at 1.5
  // Through zero: 0.1 s braking 0.1 m/s at 1.5 m/s^2 takes 1/15 s, the
  // remaining 1/30 s accelerates backwards at 1.0 m/s^2.
  t = limit_step({0.1, 0.0}, {-1.0, 0.0}, lim, 0.1);
  EXPECT_NEAR(t.v, -1.0 / 30.0, 1e-12);
  t = limit_step({0.99, 0.49}, {5.0, 5.0}, lim, 1.0);
  EXPECT_DOUBLE_EQ(t.v, 1.0);  // clamped to max_v
  EXPECT_DOUBLE_EQ(t.omega, 0.5);
  VelocityLimits forward_only = lim;
  forward_only.min_v_mps = 0.0;
  t = limit_step({0.0, 0.0}, {-1.0, 0.0}, forward_only, 1.0);
  EXPECT_DOUBLE_EQ(t.v, 0.0);
}

TEST(Kinematics, ExactArcIsExactOnACircleAndStraightLine) {
  // Quarter circle of radius 2 at v = 1, omega = 0.5, from the origin
  // heading +x, in one step: ends at (2, 2) heading +y.
  Pose2 p = integrate_arc(Pose2{}, 1.0, 0.5, M_PI);
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_NEAR(p.y, 2.0, 1e-12);
  EXPECT_NEAR(p.yaw, M_PI / 2, 1e-12);
  p = integrate_arc(Pose2{1.0, 1.0, M_PI / 4}, std::sqrt(2.0), 0.0, 2.0);
  EXPECT_NEAR(p.x, 3.0, 1e-12);
  EXPECT_NEAR(p.y, 3.0, 1e-12);
  p = integrate_arc(Pose2{}, 1.0, 1e-9, 1.0);  // nearly straight: no 1/omega blow-up
  EXPECT_NEAR(p.x, 1.0, 1e-12);
  EXPECT_NEAR(p.y, 0.5e-9, 1e-15);
}

TEST(BaseDriverCore, CommandsAreClampedAndRampedAt50Hz) {
  Rig r;
  r.base_alive = true;
  for (int k = 1; k <= 60; ++k) {  // a planner sending 50 Hz, just before each tick
    r.bus.inject(kCmdVelChannel, cmd(2.0, -1.0, kT0 + k * kTick - 1), kT0 + k * kTick - 1);
    r.run_to(kT0 + k * kTick);
  }
  auto cmds = commands(r.core.take_tx());
  // The rig opened the port at kT0, after the tick at kT0: ticks 1..60.
  ASSERT_EQ(cmds.size(), 60u);
  for (size_t k = 1; k <= cmds.size(); ++k) {
    // v ramps 0.02 m/s per tick (1.0 m/s^2) up to max_v 1.0 (67 %);
    // omega ramps 0.06 rad/s per tick (3.0 rad/s^2) down to -0.5 (-96 %).
    const double v = std::min(1.0, 0.02 * static_cast<double>(k));
    const double w = std::max(-0.5, -0.06 * static_cast<double>(k));
    EXPECT_EQ(cmds[k - 1].linear_percent, linear_percent(v)) << k;
    EXPECT_EQ(cmds[k - 1].angular_percent, angular_percent(w)) << k;
    EXPECT_EQ(cmds[k - 1].control_mode, kControlModeSerial);
    EXPECT_FALSE(cmds[k - 1].clear_fault);
  }
  EXPECT_EQ(cmds.back().linear_percent, 67);
  EXPECT_EQ(cmds.back().angular_percent, -96);
}

TEST(BaseDriverCore, WatchdogStopsAndRecovers) {
  Rig r;
  r.base_alive = true;
  r.bus.inject(kCmdVelChannel, cmd(0.3, 0.0, kT0), kT0);
  r.run_to(kT0 + 12 * kTick);  // 0.24 s: within the watchdog time
  EXPECT_FALSE(r.core.watchdog_tripped());
  EXPECT_GT(r.core.commanded().v, 0.0);
  r.run_to(kT0 + 13 * kTick);  // 0.26 s > 0.25 s
  EXPECT_TRUE(r.core.watchdog_tripped());
  EXPECT_EQ(r.core.commanded().v, 0.0);
  EXPECT_EQ(r.core.counter("watchdog_trips"), 1);
  auto cmds = commands(r.core.take_tx());
  ASSERT_EQ(cmds.size(), 13u);                               // ticks 1..13
  EXPECT_EQ(cmds[11].linear_percent, linear_percent(0.24));  // ramp at 0.02 m/s per tick
  EXPECT_EQ(cmds[12].linear_percent, 0);
  auto statuses = r.bus.decoded<evade::base_status_t>(kBaseStatusChannel);
  ASSERT_FALSE(statuses.empty());
  EXPECT_TRUE(statuses.back().watchdog_tripped);
  EXPECT_EQ(statuses.back().utime, kT0 + 13 * kTick);

  // Zero keeps being commanded while nothing comes.
  r.run_to(kT0 + 40 * kTick);
  for (const auto& c : commands(r.core.take_tx())) EXPECT_EQ(c.linear_percent, 0);

  // Commands return: the trip clears at once and the ramp restarts from 0.
  r.bus.inject(kCmdVelChannel, cmd(0.3, 0.0, kT0 + 40 * kTick + 1), kT0 + 40 * kTick + 1);
  EXPECT_FALSE(r.core.watchdog_tripped());
  EXPECT_FALSE(r.bus.decoded<evade::base_status_t>(kBaseStatusChannel).back().watchdog_tripped);
  r.run_to(kT0 + 41 * kTick);
  cmds = commands(r.core.take_tx());
  ASSERT_EQ(cmds.size(), 1u);
  EXPECT_EQ(cmds[0].linear_percent, linear_percent(0.02));
  EXPECT_EQ(r.core.counter("watchdog_trips"), 1);
}

TEST(BaseDriverCore, NonFiniteCmdVelIsCountedAndIgnored) {
  Rig r;
  r.bus.inject(kCmdVelChannel, cmd(NAN, 0.0, kT0 + 1), kT0 + 1);
  EXPECT_EQ(r.core.counter("cmd_vel_not_finite"), 1);
  EXPECT_TRUE(r.core.watchdog_tripped());
}

// Drives the base around a circle with motion-status frames at irregular
// receive times; the exact-arc pose must sit on the analytic circle.
TEST(BaseDriverCore, OdometryFollowsTheExactCircle) {
  BaseDriverParams p = test_params();
  p.initial_pose = Pose2{1.0, 2.0, 0.5};
  Rig r(p);
  const double v = 0.5, w = 0.25, radius = v / w;  // 500 mm/s, 250 mrad/s
  const double cx = 1.0 - radius * std::sin(0.5), cy = 2.0 + radius * std::cos(0.5);
  MotionStatus ms{linear_mm_s(v), angular_mrad_s(w)};
  int64_t t = kT0 + 1000;
  const int64_t t_first = t;
  Pose2 euler = p.initial_pose;
  int64_t prev = t;
  uint32_t lcg = 7;
  for (int i = 0; i < 1400; ++i) {  // about 28 s: more than one full turn (25.1 s)
    r.status(t, ms, static_cast<uint8_t>(i));
    double dt = (t - prev) * 1e-6;
    euler = Pose2{euler.x + v * dt * std::cos(euler.yaw), euler.y + v * dt * std::sin(euler.yaw), euler.yaw + w * dt};
    prev = t;
    lcg = lcg * 1664525u + 1013904223u;
    t += 15'000 + static_cast<int64_t>((lcg >> 16) % 10'000);  // 15..25 ms apart
  }
  auto odo = r.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 1400u);
  EXPECT_EQ(odo.front().utime, t_first);
  EXPECT_DOUBLE_EQ(odo.front().x, 1.0);  // starts at the initial pose
  EXPECT_DOUBLE_EQ(odo.front().y, 2.0);
  for (const auto& o : odo) {
    const double yaw = 0.5 + w * (o.utime - t_first) * 1e-6;
    EXPECT_NEAR(o.x, cx + radius * std::sin(yaw), 1e-9);
    EXPECT_NEAR(o.y, cy - radius * std::cos(yaw), 1e-9);
    EXPECT_NEAR(std::remainder(o.yaw - yaw, 2 * M_PI), 0.0, 1e-9);
    EXPECT_GE(o.yaw, -M_PI);
    EXPECT_LT(o.yaw, M_PI);
    EXPECT_DOUBLE_EQ(o.v, 0.5);
    EXPECT_DOUBLE_EQ(o.omega, 0.25);
  }
  // Euler integration over the same times is visibly off the circle: the
  // test would catch a driver that used it.
  const double euler_off = std::hypot(euler.x - odo.back().x, euler.y - odo.back().y);
  EXPECT_GT(euler_off, 1e-3);
}

TEST(BaseDriverCore, OdometryHoldsThePreviousVelocityOverEachInterval) {
  Rig r;
  r.status(kT0 + 100'000, MotionStatus{1000, 0});  // 1 m/s from here
  r.status(kT0 + 200'000, MotionStatus{0, 0});     // 0.1 s at 1 m/s -> x = 0.1
  r.status(kT0 + 300'000, MotionStatus{500, 0});   // 0.1 s at 0 -> still 0.1
  auto odo = r.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 3u);
  EXPECT_DOUBLE_EQ(odo[0].x, 0.0);
  EXPECT_NEAR(odo[1].x, 0.1, 1e-12);
  EXPECT_NEAR(odo[2].x, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(odo[2].v, 0.5);
}

TEST(BaseDriverCore, SystemStatusFillsBaseStatus) {
  Rig r;
  r.status(kT0 + 5000, SystemStatus{1, kControlModeSerial, 251, 0x0204});
  auto st = r.bus.decoded<evade::base_status_t>(kBaseStatusChannel);
  ASSERT_FALSE(st.empty());
  EXPECT_EQ(st.back().utime, kT0 + 5000);
  EXPECT_EQ(st.back().state, 1);
  EXPECT_EQ(st.back().control_mode, kControlModeSerial);
  EXPECT_DOUBLE_EQ(st.back().battery_voltage, 25.1);
  EXPECT_EQ(st.back().fault_code, 0x0204);
  EXPECT_TRUE(st.back().link_ok);
}

TEST(BaseDriverCore, ParserCountersReachHealth) {
  Rig r;
  FrameBytes good = encode(MotionStatus{100, 0}, 1);
  FrameBytes bad = good;
  bad[12] ^= 0xFF;
  std::vector<uint8_t> s = {0x01, 0x02, 0x03, 0x5A, 0xA5, 0x0C};  // 3 noise, bad length, 2 noise
  s.insert(s.end(), bad.begin(), bad.end());
  s.insert(s.end(), good.begin(), good.end());
  Frame cmd_frame = to_frame(MotionCommand{}, 0);  // a command coming back from the base
  FrameBytes echoed = serialize(cmd_frame);
  s.insert(s.end(), echoed.begin(), echoed.end());
  // Byte by byte, as a slow port delivers it.
  for (size_t i = 0; i < s.size(); ++i) r.serial(kT0 + 1000 + static_cast<int64_t>(i), {s[i]});
  EXPECT_EQ(r.core.counter("serial_frames"), 2);  // good + echoed command
  EXPECT_EQ(r.core.counter("serial_bad_length"), 1);
  EXPECT_EQ(r.core.counter("serial_bad_checksum"), 1);
  EXPECT_EQ(r.core.counter("serial_unexpected_command_frame"), 1);
  EXPECT_EQ(r.core.counter("motion_status_frames"), 1);
  // bad checksum: its first byte is rejected, the other 12 are re-scanned and
  // skipped as noise up to the good frame.
  EXPECT_EQ(r.core.counter("serial_noise_bytes"), 3 + 2 + 12);
  // The HEALTH heartbeat carries them.
  r.run_to(kT0 + 2'000'000);
  auto health = r.bus.decoded<evade::health_t>(bus::kHealthChannel);
  ASSERT_FALSE(health.empty());
  bool found = false;
  for (const auto& c : health.back().counters)
    if (c.name == "serial_bad_checksum") found = c.value == 1;
  EXPECT_TRUE(found);
}

TEST(BaseDriverCore, SilentLinkStopsTheRobotAndRecovers) {
  Rig r;
  r.status(kT0 + 10'000, MotionStatus{1000, 0});
  r.status(kT0 + 30'000, MotionStatus{1000, 0});  // x = 0.02
  EXPECT_TRUE(r.core.link_ok());
  r.run_to(kT0 + 30'000 + 520'000);  // > link_timeout_s of silence
  EXPECT_FALSE(r.core.link_ok());
  auto odo = r.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 3u);
  EXPECT_DOUBLE_EQ(odo[2].v, 0.0);  // considered stopped
  EXPECT_DOUBLE_EQ(odo[2].omega, 0.0);
  EXPECT_NEAR(odo[2].x, 0.02, 1e-12);
  EXPECT_FALSE(r.bus.decoded<evade::base_status_t>(kBaseStatusChannel).back().link_ok);
  EXPECT_EQ(r.core.counter("link_lost"), 1);
  // Frames again, 2 s later: no integration over the outage.
  r.status(kT0 + 2'030'000, MotionStatus{1000, 0});
  EXPECT_TRUE(r.core.link_ok());
  r.status(kT0 + 2'050'000, MotionStatus{1000, 0});
  odo = r.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 5u);
  EXPECT_NEAR(odo[3].x, 0.02, 1e-12);
  EXPECT_NEAR(odo[4].x, 0.04, 1e-12);
}

TEST(BaseDriverCore, ClosedPortSendsNothingAndRampRestarts) {
  Rig r;
  r.base_alive = true;
  r.bus.inject(kCmdVelChannel, cmd(1.0, 0.0, kT0 + 1), kT0 + 1);
  r.run_to(kT0 + 10 * kTick);
  r.bus.input(r.core, kT0 + 10 * kTick + 1, [&] { r.core.on_link_lost("test hang-up"); });
  r.core.take_tx();
  for (int k = 11; k <= 12; ++k) {
    r.bus.inject(kCmdVelChannel, cmd(1.0, 0.0, kT0 + k * kTick - 1), kT0 + k * kTick - 1);
    r.run_to(kT0 + k * kTick);
  }
  EXPECT_TRUE(r.core.take_tx().empty());
  r.bus.input(r.core, kT0 + 12 * kTick + 1, [&] { r.core.on_link_opened(); });
  r.bus.inject(kCmdVelChannel, cmd(1.0, 0.0, kT0 + 13 * kTick - 1), kT0 + 13 * kTick - 1);
  r.run_to(kT0 + 13 * kTick);
  auto cmds = commands(r.core.take_tx());
  ASSERT_EQ(cmds.size(), 1u);
  EXPECT_EQ(cmds[0].linear_percent, linear_percent(0.02));  // from zero again
}

// ---- issue 20: fault holes ----

TEST(BaseDriverCore, SilentLinkMakesEveryFrameAfterTheLossZero) {
  Rig r;
  r.base_alive = true;
  int k = 1;
  for (; k <= 30; ++k) {
    r.bus.inject(kCmdVelChannel, cmd(0.5, 0.2, kT0 + k * kTick - 1), kT0 + k * kTick - 1);
    r.run_to(kT0 + k * kTick);
  }
  ASSERT_GT(commands(r.core.take_tx()).back().linear_percent, 0);
  r.base_alive = false;  // the base goes silent; the planner keeps commanding
  bool lost = false;
  std::vector<MotionCommand> after;
  for (; k <= 100; ++k) {
    r.bus.inject(kCmdVelChannel, cmd(0.5, 0.2, kT0 + k * kTick - 1), kT0 + k * kTick - 1);
    r.run_to(kT0 + k * kTick);
    auto cmds = commands(r.core.take_tx());
    if (lost) after.insert(after.end(), cmds.begin(), cmds.end());
    lost = lost || !r.core.link_ok();
  }
  ASSERT_TRUE(lost);
  ASSERT_GE(after.size(), 40u);
  for (const auto& c : after) {
    EXPECT_EQ(c.linear_percent, 0);
    EXPECT_EQ(c.angular_percent, 0);
  }
}

TEST(BaseDriverCore, TheStoppedOdometryAfterALostLinkIsStampedWithTheLastRealOne) {
  Rig r;
  r.status(kT0 + 20'000, MotionStatus{1000, 0});
  r.status(kT0 + 40'000, MotionStatus{1000, 0});
  r.run_to(kT0 + 700'000);  // silent for more than link_timeout_s
  ASSERT_FALSE(r.core.link_ok());
  auto odo = r.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 3u);
  EXPECT_EQ(odo[2].v, 0.0);
  EXPECT_EQ(odo[2].utime, odo[1].utime);  // not fresh: nothing measured it since
}

TEST(BaseDriverCore, LateAndFutureCommandsAreIgnored) {
  Rig r;
  r.base_alive = true;
  const int64_t t = kT0 + 5 * kTick - 1;
  r.bus.inject(kCmdVelChannel, cmd(0.5, 0.0, t - 500'000), t);     // 0.5 s old
  r.bus.inject(kCmdVelChannel, cmd(0.5, 0.0, t + 10'000'000), t);  // 10 s ahead
  r.bus.inject(kCmdVelChannel, cmd(0.5, 0.0, std::numeric_limits<int64_t>::max()), t);
  r.bus.inject(kCmdVelChannel, cmd(0.5, 0.0, std::numeric_limits<int64_t>::min()), t);
  EXPECT_EQ(r.core.counter("cmd_vel_late"), 2);
  EXPECT_EQ(r.core.counter("cmd_vel_future"), 2);
  r.run_to(kT0 + 10 * kTick);
  EXPECT_TRUE(r.core.watchdog_tripped());
  for (const auto& c : commands(r.core.take_tx())) EXPECT_EQ(c.linear_percent, 0);
  // a fresh one (0.1 s old: within cmd_vel_max_age_s) is obeyed
  r.bus.inject(kCmdVelChannel, cmd(0.5, 0.0, kT0 + 10 * kTick - 100'000), kT0 + 10 * kTick + 1);
  EXPECT_FALSE(r.core.watchdog_tripped());
}

TEST(BaseDriverCore, StopQueuesAZeroFrameWhileDriving) {
  Rig r;
  r.base_alive = true;
  for (int k = 1; k <= 20; ++k) {
    r.bus.inject(kCmdVelChannel, cmd(0.8, 0.3, kT0 + k * kTick - 1), kT0 + k * kTick - 1);
    r.run_to(kT0 + k * kTick);
  }
  ASSERT_GT(commands(r.core.take_tx()).back().linear_percent, 0);
  r.bus.input(r.core, kT0 + 20 * kTick + 5, [&] { r.core.stop(); });
  auto cmds = commands(r.core.take_tx());
  ASSERT_EQ(cmds.size(), 1u);
  EXPECT_EQ(cmds[0].linear_percent, 0);
  EXPECT_EQ(cmds[0].angular_percent, 0);
}

TEST(BaseDriverCore, OdometryCarriesTheDriversEpoch) {
  BaseDriverParams p = test_params();
  p.epoch = 1234567;
  Rig r(p);
  r.status(kT0 + 20'000, MotionStatus{1000, 0});
  auto odo = r.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 1u);
  EXPECT_EQ(odo[0].epoch, 1234567);
}

// ---- authenticated commands and the e-stop (issue 20) ----

std::vector<uint8_t> signed_msg(bus::HmacAuth& signer, const std::string& channel, std::vector<uint8_t> data,
                                int64_t now) {
  EXPECT_TRUE(signer.sign(channel, now, &data));
  return data;
}
evade::estop_t estop(bool engaged, int64_t utime) {
  evade::estop_t m{};
  m.utime = utime;
  m.engaged = engaged;
  m.reason = "test";
  return m;
}

struct SignedRig : Rig {
  SignedRig() : Rig() { core.set_authenticator(&auth); }
  // The planner's CMD_VEL just before tick k.
  void planner_cmd(int k, double v) {
    const int64_t t = kT0 + k * kTick - 1;
    bus.inject(kCmdVelChannel, signed_msg(planner, kCmdVelChannel, bus::encode(cmd(v, 0.0, t)), t), t);
  }
  void estop_from(bus::HmacAuth& who, bool engaged, int64_t t) {
    bus.inject(kEstopChannel, signed_msg(who, kEstopChannel, bus::encode(estop(engaged, t)), t), t);
  }
  std::vector<uint8_t> key = std::vector<uint8_t>(32, 0x42);
  bus::HmacAuth auth{key, "base_driver", 2.0};
  bus::HmacAuth planner{key, "planner", 2.0};
  bus::HmacAuth operator_tool{key, "estop", 2.0};
};

TEST(BaseDriverAuth, AnEstopWinsOverAConcurrentCmdVelStreamUntilReleased) {
  SignedRig r;
  r.base_alive = true;
  for (int k = 1; k <= 20; ++k) {
    r.planner_cmd(k, 0.5);
    r.run_to(kT0 + k * kTick);
  }
  EXPECT_GT(r.core.commanded().v, 0.3);
  (void)r.core.take_tx();
  // The e-stop arrives between two planner commands; the planner goes on at 50 Hz.
  r.estop_from(r.operator_tool, true, kT0 + 20 * kTick + 500);
  EXPECT_TRUE(r.core.estop_engaged());
  EXPECT_TRUE(r.bus.decoded<evade::base_status_t>(kBaseStatusChannel).back().estop_engaged);
  for (int k = 21; k <= 120; ++k) {
    r.planner_cmd(k, 0.5);
    r.run_to(kT0 + k * kTick);
  }
  auto cmds = commands(r.core.take_tx());
  ASSERT_EQ(cmds.size(), 100u);
  for (const auto& c : cmds) EXPECT_EQ(c.linear_percent, 0);  // every frame, from the first tick on
  EXPECT_EQ(r.core.counter("cmd_vel_during_estop"), 100);
  EXPECT_EQ(r.core.counter("estop_engaged"), 1);

  // A release signed with another key is refused; the stop holds.
  bus::HmacAuth forger(std::vector<uint8_t>(32, 0x43), "estop", 2.0);
  r.estop_from(forger, false, kT0 + 120 * kTick + 500);
  EXPECT_TRUE(r.core.estop_engaged());
  EXPECT_EQ(r.core.counter("auth_bad_mac"), 1);
  // The genuine release: the planner's next command drives again, from zero.
  r.estop_from(r.operator_tool, false, kT0 + 120 * kTick + 600);
  EXPECT_FALSE(r.core.estop_engaged());
  EXPECT_EQ(r.core.counter("estop_released"), 1);
  r.run_to(kT0 + 121 * kTick);
  for (const auto& c : commands(r.core.take_tx())) EXPECT_EQ(c.linear_percent, 0);  // no command since the release
  r.planner_cmd(122, 0.5);
  r.run_to(kT0 + 122 * kTick);
  cmds = commands(r.core.take_tx());
  ASSERT_EQ(cmds.size(), 1u);
  EXPECT_EQ(cmds[0].linear_percent, linear_percent(0.02));
}

TEST(BaseDriverAuth, ForgedReplayedAndUnsignedCommandsNeverDrive) {
  SignedRig r;
  r.base_alive = true;
  bus::HmacAuth forger(std::vector<uint8_t>(32, 0x43), "planner", 2.0);
  const int64_t t1 = kT0 + kTick - 1;
  const auto recorded = signed_msg(r.planner, kCmdVelChannel, bus::encode(cmd(0.5, 0.0, t1)), t1);
  r.bus.inject(kCmdVelChannel, recorded, t1);
  r.run_to(kT0 + kTick);
  EXPECT_FALSE(r.core.watchdog_tripped());
  r.run_to(kT0 + 30 * kTick);  // the planner is gone: the watchdog trips
  ASSERT_TRUE(r.core.watchdog_tripped());
  (void)r.core.take_tx();
  for (int k = 31; k <= 80; ++k) {
    const int64_t t = kT0 + k * kTick - 1;
    r.bus.inject(kCmdVelChannel, recorded, t);                                                              // replayed
    r.bus.inject(kCmdVelChannel, signed_msg(forger, kCmdVelChannel, bus::encode(cmd(1.0, 0.0, t)), t), t);  // forged
    r.bus.inject(kCmdVelChannel, cmd(1.0, 0.0, t), t);                                                      // unsigned
    r.run_to(kT0 + k * kTick);
  }
  EXPECT_TRUE(r.core.watchdog_tripped());
  for (const auto& c : commands(r.core.take_tx())) EXPECT_EQ(c.linear_percent, 0);
  EXPECT_EQ(r.core.counter("auth_old_seq"), 50);
  EXPECT_EQ(r.core.counter("auth_bad_mac"), 50);
  EXPECT_EQ(r.core.counter("auth_unsigned"), 50);
  // A forged e-stop release of a genuine e-stop changes nothing either.
  r.estop_from(r.operator_tool, true, kT0 + 80 * kTick + 1);
  r.bus.inject(kEstopChannel, bus::encode(estop(false, kT0 + 80 * kTick + 2)), kT0 + 80 * kTick + 2);
  EXPECT_TRUE(r.core.estop_engaged());
}

TEST(BaseDriverConfig, FactoryReadsTheWholeConfigAndAppliesTheRunsSettings) {
  auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  const BaseDriverParams file = BaseDriverParams::from_config(root);
  auto plain = BaseDriverCore::from_config(root);
  EXPECT_EQ(plain->params().device, file.device);
  EXPECT_EQ(plain->params().baud_rate, file.baud_rate);
  EXPECT_DOUBLE_EQ(plain->pose().x, file.initial_pose.x);
  EXPECT_EQ(plain->params().epoch, 0);  // a replay's: deterministic

  BaseDriverRun run;
  run.device = "/dev/ttyUSB7";
  run.initial_pose = Pose2{1.5, -2.0, 0.25};
  run.epoch = 1'700'000'000'000'000;
  auto core = BaseDriverCore::from_config(root, run);
  EXPECT_EQ(core->params().device, "/dev/ttyUSB7");
  EXPECT_DOUBLE_EQ(core->pose().x, 1.5);
  EXPECT_DOUBLE_EQ(core->pose().y, -2.0);
  EXPECT_DOUBLE_EQ(core->pose().yaw, 0.25);
  EXPECT_EQ(core->params().epoch, 1'700'000'000'000'000);
  EXPECT_DOUBLE_EQ(core->params().watchdog_timeout_s, file.watchdog_timeout_s);  // the rest from the file

  auto bad = config::load_string("robot: {max_v_mps: 1.0}\nbase_driver: {device: /dev/x}\n", "bad.yaml");
  EXPECT_THROW(BaseDriverCore::from_config(bad, run), config::ConfigError);
}

}  // namespace
}  // namespace evade::base
