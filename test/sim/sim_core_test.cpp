// The sim core on the test bus: Scout frames round-trip through the
// emulated base (commands in, system and motion status out at 50 Hz), bad
// frames are counted, the robot follows through its limits and stops on
// the command timeout, obstacles start with the robot, SIM_TRUTH and the
// LiDAR packets come at their rates.
#include "sim/sim_core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "base/scout_protocol.h"
#include "bus/memory_bus.h"
#include "sensing/lidar_decoder.h"
#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"

namespace evade::sim {
namespace {

constexpr int64_t kT0 = 1'700'000'000'000'000;

const char* kScenario = R"(name: test
duration_s: 30
robot:
  start: {x: -10.0, y: 0.0, yaw: 0.0}
  goal: {x: 9.0, y: 0.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
lidar: {model: vlp16, rate_hz: 10, height: 0.5, range_noise_std: 0.0}
obstacles:
  - {shape: cylinder, radius: 0.25, height: 0.5, x: -4.5, y: 0.5, vx: -1.0, vy: 0.5}
  - {shape: box, size: [1.0, 2.0, 1.0], x: 2.0, y: 3.0, yaw: 0.3}
)";

SimParams test_params() {
  config::Node root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  return SimParams::from_config(root);
}

class SimCoreTest : public ::testing::Test {
 protected:
  SimCoreTest() : params_(test_params()), core_(parse_scenario(kScenario, "test.yaml"), params_) {
    core_.set_serial_sink([this](const uint8_t* d, size_t n) { serial_.insert(serial_.end(), d, d + n); });
    core_.set_packet_sink([this](const Packet& p) { packets_.push_back(p); });
    bus_.add(core_);
    bus_.advance_to(kT0);
  }

  // Moves time on in 1 ms steps, as the live loop does (a core more than
  // ten periods behind skips its missed timer ticks, like a stalled process).
  void run_until(int64_t t) {
    for (int64_t now = last_ + 1000; now < t; now += 1000) bus_.advance_to(now);
    bus_.advance_to(t);
    last_ = t;
  }

  void send(const std::vector<uint8_t>& bytes, int64_t t) {
    run_until(t);
    bus_.input(core_, t, [&] { core_.on_serial_bytes(bytes.data(), bytes.size()); });
  }
  void command(double v, double w, int64_t t) {
    base::MotionCommand c;
    c.control_mode = base::kControlModeSerial;
    c.linear_percent = base::linear_percent(v);
    c.angular_percent = base::angular_percent(w);
    base::FrameBytes f = base::encode(c, count_++);
    send(std::vector<uint8_t>(f.begin(), f.end()), t);
  }
  // Every status frame the base sent so far.
  std::vector<base::Frame> status_frames() {
    std::vector<base::Frame> out;
    base::StreamParser p;
    p.feed(serial_.data(), serial_.size(), [&](const base::Frame& f) { out.push_back(f); });
    EXPECT_EQ(p.stats().noise_bytes + p.stats().bad_checksum + p.stats().bad_length, 0u);
    return out;
  }

  SimParams params_;
  SimCore core_;
  bus::MemoryBus bus_;
  std::vector<uint8_t> serial_;
  std::vector<Packet> packets_;
  uint8_t count_ = 0;
  int64_t last_ = kT0;
};

TEST_F(SimCoreTest, StatusFramesAt50HzReportTheRobotsVelocity) {
  for (int64_t t = kT0; t <= kT0 + 2'000'000; t += 20'000) command(0.75, -0.2618, t);
  std::vector<base::Frame> frames = status_frames();
  int system = 0, motion = 0;
  base::MotionStatus last{};
  base::SystemStatus sys{};
  for (const auto& f : frames) {
    base::MotionStatus m;
    base::SystemStatus s;
    if (base::from_frame(f, &m)) motion++, last = m;
    if (base::from_frame(f, &s)) system++, sys = s;
  }
  // 2 s at 50 Hz, both ends included.
  EXPECT_EQ(system, 101);
  EXPECT_EQ(motion, 101);
  // After 2 s the robot is at the commanded 50 % of 1.5 m/s and -50 % of 0.5235 rad/s.
  EXPECT_EQ(last.linear_mm_s, 750);
  EXPECT_EQ(last.angular_mrad_s, -262);
  EXPECT_EQ(sys.control_mode, base::kControlModeSerial);
  EXPECT_EQ(sys.battery_decivolts, base::battery_decivolts(params_.battery_voltage_v));
  EXPECT_EQ(core_.counter("scout_motion_commands"), 101);
  // Rolling counter increments frame by frame.
  for (size_t i = 1; i < frames.size(); ++i) EXPECT_EQ(static_cast<uint8_t>(frames[i - 1].count + 1), frames[i].count);
}

TEST_F(SimCoreTest, RobotAcceleratesAtTheConfiguredLimit) {
  command(0.75, 0.0, kT0 + 1000);
  run_until(kT0 + 201'000);
  // max_accel_mps2 for 0.2 s
  EXPECT_NEAR(core_.robot()->v(), std::min(0.75, params_.robot.max_accel_mps2 * 0.2), 1e-9);
}

// The Scout manual: motion frames every 20 ms, receive timeout 500 ms
// (lib/base/README.md). Frames stop -> the base holds the last command for
// 500 ms, then brakes to rest at its deceleration limit and reports standby.
TEST_F(SimCoreTest, FramesStopTheBaseHoldsTheCommandForHalfASecondThenBrakesToRest) {
  ASSERT_EQ(params_.command_timeout_us, 500'000);  // config/robot.yaml sim.command_timeout_s
  int64_t last = 0;
  for (int64_t t = kT0 + 1000; t <= kT0 + 1'001'000; t += 20'000) command(0.75, 0.0, last = t);
  run_until(last + 1000);
  ASSERT_NEAR(core_.robot()->v(), 0.75, 1e-9);
  // 490 ms of silence: still the commanded speed, still in serial control.
  run_until(last + 490'000);
  EXPECT_NEAR(core_.robot()->v(), 0.75, 1e-9);
  EXPECT_EQ(core_.counter("scout_command_timeouts"), 0);
  // 500 ms: the timeout; 50 ms later the speed has dropped by 50 ms of braking.
  run_until(last + 501'000);
  const double v_at_timeout = core_.robot()->v();
  EXPECT_NEAR(v_at_timeout, 0.75, params_.robot.max_decel_mps2 * 0.0011);
  run_until(last + 551'000);
  EXPECT_NEAR(core_.robot()->v(), v_at_timeout - params_.robot.max_decel_mps2 * 0.05, 2e-3);
  // At rest after 0.75 / max_decel, and it stays there.
  run_until(last + 500'000 + static_cast<int64_t>(0.75 / params_.robot.max_decel_mps2 * 1e6) + 2000);
  EXPECT_EQ(core_.robot()->v(), 0.0);
  run_until(last + 3'000'000);
  EXPECT_EQ(core_.robot()->v(), 0.0);
  EXPECT_EQ(core_.counter("scout_command_timeouts"), 1);
  std::vector<base::Frame> frames = status_frames();
  base::MotionStatus m;
  ASSERT_TRUE(base::from_frame(frames.back(), &m));
  EXPECT_EQ(m.linear_mm_s, 0);
  base::SystemStatus s;
  ASSERT_TRUE(base::from_frame(frames[frames.size() - 2], &s));
  EXPECT_EQ(s.control_mode, base::kControlModeStandby);
  // The next frame is obeyed again.
  command(0.3, 0.0, last + 3'001'000);
  run_until(last + 3'400'000);
  EXPECT_NEAR(core_.robot()->v(), 0.3, 1e-9);
}

TEST_F(SimCoreTest, BadFramesAreCountedAndIgnored) {
  base::MotionCommand c;
  c.linear_percent = 50;
  base::FrameBytes f = base::encode(c, 0);
  std::vector<uint8_t> bad(f.begin(), f.end());
  bad[12] ^= 0x01;  // checksum
  send(bad, kT0 + 1000);
  std::vector<uint8_t> noise = {0x00, 0x13, 0x5A, 0x00};
  send(noise, kT0 + 2000);
  c.control_mode = base::kControlModeRemote;  // not serial control: the base ignores it
  f = base::encode(c, 1);
  send(std::vector<uint8_t>(f.begin(), f.end()), kT0 + 3000);
  run_until(kT0 + 200'000);
  EXPECT_EQ(core_.robot()->v(), 0.0);
  EXPECT_EQ(core_.counter("scout_bad_checksum"), 1);
  EXPECT_GE(core_.counter("scout_noise_bytes"), 3);
  EXPECT_EQ(core_.counter("scout_commands_not_serial_mode"), 1);
  EXPECT_EQ(core_.counter("scout_motion_commands"), 0);
  // A frame split over two reads still counts.
  c.control_mode = base::kControlModeSerial;
  f = base::encode(c, 2);
  send(std::vector<uint8_t>(f.begin(), f.begin() + 5), kT0 + 201'000);
  send(std::vector<uint8_t>(f.begin() + 5, f.end()), kT0 + 202'000);
  EXPECT_EQ(core_.counter("scout_motion_commands"), 1);
}

TEST_F(SimCoreTest, RandomBytesNeverCrashAndAreCounted) {
  std::mt19937 rng(7);
  std::vector<uint8_t> junk(4096);
  int64_t t = kT0;
  for (int i = 0; i < 25; ++i) {
    for (auto& b : junk) b = static_cast<uint8_t>(rng());
    // Sprinkle frame starts so the parser also sees headers with bad lengths and checksums.
    for (size_t k = 0; k + 3 < junk.size(); k += 97) junk[k] = 0x5A, junk[k + 1] = 0xA5;
    t += 10'000;
    send(junk, t);
  }
  EXPECT_GT(core_.counter("scout_noise_bytes"), 50'000);
  EXPECT_GT(core_.counter("scout_bad_length") + core_.counter("scout_bad_checksum"), 500);
  // Status frames still go out, clean.
  EXPECT_FALSE(status_frames().empty());
}

TEST_F(SimCoreTest, ObstaclesStartWhenTheRobotFirstMoves) {
  run_until(kT0 + 1'000'000);
  auto truths = bus_.decoded<evade::sim_truth_t>("SIM_TRUTH");
  ASSERT_FALSE(truths.empty());
  EXPECT_FALSE(truths.back().obstacles_moving);
  EXPECT_DOUBLE_EQ(truths.back().obstacles[0].x, -4.5);
  EXPECT_DOUBLE_EQ(truths.back().obstacles[0].vx, 0.0);
  command(0.5, 0.0, kT0 + 1'000'000);
  run_until(kT0 + 3'000'000);
  ASSERT_TRUE(core_.motion_start_us().has_value());
  const int64_t t_motion = *core_.motion_start_us();
  EXPECT_EQ(t_motion, kT0 + 1'001'000);  // first physics step after the command
  evade::sim_truth_t last = bus_.decoded<evade::sim_truth_t>("SIM_TRUTH").back();
  EXPECT_TRUE(last.obstacles_moving);
  double t = (last.utime - t_motion) * 1e-6;
  ASSERT_EQ(last.num_obstacles, 2);
  EXPECT_NEAR(last.obstacles[0].x, -4.5 - 1.0 * t, 1e-9);
  EXPECT_NEAR(last.obstacles[0].y, 0.5 + 0.5 * t, 1e-9);
  EXPECT_DOUBLE_EQ(last.obstacles[0].vx, -1.0);
  EXPECT_EQ(last.obstacles[0].shape, "cylinder");
  EXPECT_DOUBLE_EQ(last.obstacles[0].radius, 0.25);
  EXPECT_EQ(last.obstacles[1].shape, "box");
  EXPECT_DOUBLE_EQ(last.obstacles[1].length, 1.0);
  EXPECT_DOUBLE_EQ(last.obstacles[1].width, 2.0);
  EXPECT_DOUBLE_EQ(last.obstacles[1].yaw, 0.3);
  EXPECT_DOUBLE_EQ(last.footprint_length, 0.42);
  EXPECT_EQ(last.scenario, "test");
  EXPECT_DOUBLE_EQ(last.goal_x, 9.0);
}

TEST_F(SimCoreTest, TruthAndPacketRates) {
  run_until(kT0 + 1'000'000);
  auto truths = bus_.decoded<evade::sim_truth_t>("SIM_TRUTH");
  EXPECT_EQ(truths.size(), 51u);  // 50 Hz, both ends
  EXPECT_EQ(truths.front().utime, kT0);
  EXPECT_EQ(truths.back().utime, kT0 + 1'000'000);
  EXPECT_DOUBLE_EQ(truths.back().x, -10.0);
  // 753.5 packets/s: the packets finished within the first second.
  EXPECT_EQ(packets_.size(), 753u);
  std::vector<sensing::vlp16::Return> pts;
  for (const auto& p : packets_)
    ASSERT_EQ(sensing::vlp16::decode_packet(p.data(), p.size(), {}, &pts, nullptr), sensing::vlp16::PacketStatus::kOk);
  EXPECT_GT(pts.size(), 8u * 1800u * 9u);  // nine revolutions of ground and obstacle returns
}

// The LiDAR packets of the first 0.2 s of a scenario with range noise.
std::vector<Packet> noisy_packets(const std::string& seed_line) {
  std::string text = kScenario;
  text.replace(text.find("range_noise_std: 0.0"), 20, "range_noise_std: 0.02");
  SimCore core(parse_scenario(text + seed_line, "noisy.yaml"), test_params());
  std::vector<Packet> packets;
  core.set_packet_sink([&](const Packet& p) { packets.push_back(p); });
  bus::MemoryBus bus;
  bus.add(core);
  for (int64_t t = kT0; t <= kT0 + 200'000; t += 1000) bus.advance_to(t);
  return packets;
}

TEST(SimCoreSeed, TheScenarioSeedSeedsTheRangeNoise) {
  std::vector<Packet> one = noisy_packets("");
  ASSERT_GT(one.size(), 100u);
  EXPECT_EQ(noisy_packets("seed: 1\n"), one);  // 1 is the default
  std::vector<Packet> seven = noisy_packets("seed: 7\n");
  EXPECT_EQ(noisy_packets("seed: 7\n"), seven);
  ASSERT_EQ(seven.size(), one.size());
  EXPECT_NE(seven, one);
}

TEST(SimCoreDelay, ADelayedObstacleWaitsInTheTruth) {
  std::string text = kScenario;
  text.replace(text.find("vx: -1.0, vy: 0.5}"), 18, "vx: -1.0, vy: 0.5, start_delay_s: 0.5}");
  text += "obstacles_start: at_start\n";
  SimCore core(parse_scenario(text, "delay.yaml"), test_params());
  bus::MemoryBus bus;
  bus.add(core);
  for (int64_t t = kT0; t <= kT0 + 1'500'000; t += 1000) bus.advance_to(t);
  auto truths = bus.decoded<evade::sim_truth_t>("SIM_TRUTH");
  ASSERT_GT(truths.size(), 70u);
  for (const auto& tr : truths) {
    double t = (tr.utime - kT0) * 1e-6;
    double moved = std::max(0.0, t - 0.5);
    EXPECT_NEAR(tr.obstacles[0].x, -4.5 - moved, 1e-9) << t;
    EXPECT_DOUBLE_EQ(tr.obstacles[0].vx, t > 0.5 ? -1.0 : 0.0) << t;
  }
}

TEST_F(SimCoreTest, FinishesAfterTheScenarioDuration) {
  run_until(kT0 + 29'000'000);
  EXPECT_FALSE(core_.finished());
  run_until(kT0 + 30'000'000);
  EXPECT_TRUE(core_.finished());
}

// A Scout-sized robot with an RS-Helios 0.9 m up and its 0.35 m body
// modelled: the sim sends MSOP to the data port and a DIFOP at once and
// every second; decoded without the self-filter, the -55..-43 deg channels
// land on the body's top; with it, nothing over the footprint is left and
// the ground around is.
const char* kHeliosScenario = R"(name: helios
duration_s: 30
robot:
  start: {x: 1.0, y: 2.0, yaw: 0.7}
  goal: {x: 9.0, y: 0.0, tolerance: 0.3}
  footprint: {length: 0.93, width: 0.70}
lidar: {model: rs_helios, rate_hz: 10, height: 0.9, range_noise_std: 0.0}
obstacles:
  - {shape: box, size: [1.0, 2.0, 1.0], x: 4.0, y: 3.0, yaw: 0.3}
)";

struct BodyPoints {
  int over_footprint = 0, body_top = 0, outside = 0;
  int64_t filtered = 0;
};
BodyPoints decode_helios(const std::vector<Packet>& packets, bool self_filter) {
  sensing::LidarDecoderParams dp;
  dp.model = sensing::LidarModel::kRsHelios;
  dp.mount.z = 0.9;
  dp.min_range_m = 0.0;
  dp.max_range_m = 200.0;
  dp.self_filter = self_filter;
  dp.footprint_length_m = 0.93;
  dp.footprint_width_m = 0.70;
  dp.self_filter_margin_m = 0.05;
  BodyPoints b;
  sensing::LidarDecoder dec(dp, [&](const std::string& n, int64_t k) {
    if (n == "self_filtered_points") b.filtered += k;
  });
  std::vector<sensing::Revolution> revs;
  int64_t t = kT0;
  for (const Packet& p : packets) dec.feed(p.data(), p.size(), t += 667, &revs);
  dec.flush(&revs);
  for (const auto& r : revs)
    for (int i = 0; i < r.cloud.n; ++i) {
      const double bz = 0.9 + r.cloud.z[i];  // mount: 0.9 m up on the base centre, level
      if (std::abs(r.cloud.x[i]) <= 0.465 + 0.05 && std::abs(r.cloud.y[i]) <= 0.35 + 0.05) {
        ++b.over_footprint;
        if (std::abs(bz - 0.35) < 0.01) ++b.body_top;
      } else {
        ++b.outside;
      }
    }
  return b;
}

TEST(SimCoreHelios, MsopAndDifopOnTheirPortsAndTheBodySeenThenFiltered) {
  SimParams params = test_params();
  EXPECT_EQ(params.dest_port("rs_helios", LidarPort::kData), 6699);
  EXPECT_EQ(params.dest_port("rs_helios", LidarPort::kDifop), 7788);
  EXPECT_EQ(params.dest_port("vlp16", LidarPort::kData), 2368);
  params.robot_body_height_m = 0.35;
  SimCore core(parse_scenario(kHeliosScenario, "helios.yaml"), params);
  std::vector<Packet> packets;
  core.set_packet_sink([&](const Packet& p) { packets.push_back(p); });
  bus::MemoryBus bus;
  bus.add(core);
  for (int64_t t = kT0; t <= kT0 + 1'200'000; t += 1000) bus.advance_to(t);
  ASSERT_FALSE(packets.empty());
  EXPECT_EQ(packets.front().port, LidarPort::kDifop);
  int difop = 0, msop = 0;
  for (const Packet& p : packets) {
    const auto kind = sensing::rs_helios::classify(p.data(), p.size());
    if (p.port == LidarPort::kDifop) {
      ++difop;
      EXPECT_EQ(kind, sensing::rs_helios::PacketKind::kDifop);
    } else {
      ++msop;
      EXPECT_EQ(kind, sensing::rs_helios::PacketKind::kMsop);
    }
  }
  EXPECT_EQ(difop, 2);                   // at the start and a second later
  EXPECT_NEAR(msop, 1.2e6 / 666.72, 2);  // 1499.9 a second
  EXPECT_EQ(core.counter("lidar_packets"), difop + msop);

  const BodyPoints raw = decode_helios(packets, false);
  const BodyPoints filtered = decode_helios(packets, true);
  EXPECT_GT(raw.body_top, 5000);  // a dozen channels x 1800 firings a revolution, a second
  EXPECT_EQ(raw.filtered, 0);
  EXPECT_EQ(filtered.over_footprint, 0);
  EXPECT_EQ(filtered.filtered, raw.over_footprint);
  EXPECT_EQ(filtered.outside, raw.outside);
  EXPECT_GT(filtered.outside, 200000);

  // The body cannot reach the sensor.
  params.robot_body_height_m = 0.9;
  EXPECT_THROW(SimCore(parse_scenario(kHeliosScenario, "helios.yaml"), params), std::invalid_argument);
}

}  // namespace
}  // namespace evade::sim

namespace evade::sim {
namespace {

// SIM_TRUTH's lidar_returns: -1 until the first revolution is complete, then
// the returns of each obstacle in the last one; a walker hidden behind a
// wall gives none, the wall and a walker in the open give many.
class SimCoreReturns : public ::testing::TestWithParam<std::string> {};

TEST_P(SimCoreReturns, EachObstacleReturnsOfTheLastRevolution) {
  std::string text = R"(name: returns
duration_s: 30
robot:
  start: {x: 0.0, y: 0.0, yaw: 0.0}
  goal: {x: 9.0, y: 0.0, tolerance: 0.3}
  footprint: {length: 0.42, width: 0.31}
lidar: {model: MODEL, rate_hz: 10, height: 0.5, range_noise_std: 0.0}
obstacles:
  - {shape: cylinder, radius: 0.25, height: 1.7, x: 3.0, y: 0.0}
  - {shape: box, size: [0.3, 4.0, 2.0], x: 0.0, y: 4.0, yaw: 1.5707963}
  - {shape: cylinder, radius: 0.25, height: 1.7, x: 0.0, y: 6.0}
  - {shape: cylinder, radius: 0.25, height: 1.7, x: 150.0, y: 0.0}
)";
  text.replace(text.find("MODEL"), 5, GetParam());
  SimCore core(parse_scenario(text, "returns.yaml"), test_params());
  bus::MemoryBus bus;
  bus.add(core);
  for (int64_t t = kT0; t <= kT0 + 350'000; t += 1000) bus.advance_to(t);
  auto truths = bus.decoded<evade::sim_truth_t>("SIM_TRUTH");
  ASSERT_GT(truths.size(), 15u);
  EXPECT_EQ(truths.front().lidar_returns, std::vector<int32_t>(4, -1));
  const auto& last = truths.back();
  ASSERT_EQ(last.lidar_returns.size(), 4u);
  EXPECT_GT(last.lidar_returns[0], 50);   // 0.5 m wide at 3 m: about 10 deg of the sweep, many rings
  EXPECT_GT(last.lidar_returns[1], 100);  // the wall
  EXPECT_EQ(last.lidar_returns[2], 0);    // behind the wall
  EXPECT_EQ(last.lidar_returns[3], 0);    // beyond the sensor's range
  // The revolution before, with the world at rest, gives about the same
  // counts (the firings' azimuths shift a little from one turn to the next).
  const auto& earlier = truths[truths.size() - 6];  // 0.1 s before
  ASSERT_EQ(earlier.lidar_returns.size(), 4u);
  for (size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(earlier.lidar_returns[i], last.lidar_returns[i], 0.05 * last.lidar_returns[i] + 1) << i;
}

INSTANTIATE_TEST_SUITE_P(EveryModel, SimCoreReturns, ::testing::Values("vlp16", "rs_helios"));

}  // namespace
}  // namespace evade::sim
