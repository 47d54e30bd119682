// Revolution assembly, time stamping, the lidar_driver core on the memory
// bus, and LIDAR_SCAN replay giving identical LIDAR_POINTS.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "bus/memory_bus.h"
#include "config/config.h"
#include "evade/health_t.hpp"
#include "sensing/lidar_decoder.h"
#include "sensing/lidar_driver_core.h"
#include "sensing/rs_helios.h"
#include "synthetic.h"

namespace evade::sensing {
namespace {

using testing::SyntheticVlp16;

constexpr int64_t kLatencyUs = 250;  // network + stack, constant in these tests

struct Counts {
  std::map<std::string, int64_t> c;
  LidarDecoder::CountFn fn() {
    return [this](const std::string& n, int64_t k) { c[n] += k; };
  }
};

double span_us() { return vlp16::firing_offset_us(11, 1, 15); }

LidarDecoderParams vlp_params() {
  LidarDecoderParams p;
  p.model = LidarModel::kVlp16;
  p.min_range_m = 0.0;
  p.max_range_m = 120.0;
  p.self_filter = false;
  return p;
}

// A Scout 2.0 sized robot (0.93 x 0.70 m; with the 0.05 m margin 1.03 x 0.80).
LidarDecoderParams scout_sized(bool self_filter, const evade::pose3d_t& mount) {
  LidarDecoderParams p;
  p.self_filter = self_filter;
  p.footprint_length_m = 0.93;
  p.footprint_width_m = 0.70;
  p.self_filter_margin_m = 0.05;
  p.mount = mount;
  return p;
}

// Feeds `n` synthetic packets received `kLatencyUs` after their last firing.
std::vector<Revolution> run(LidarDecoder& dec, const SyntheticVlp16& s, int n, bool flush = true,
                            const std::vector<int64_t>& jitter = {}) {
  std::vector<Revolution> out;
  for (int k = 0; k < n; ++k) {
    auto p = s.packet(k);
    int64_t recv = p.sensor_utime + std::llround(span_us()) + kLatencyUs + (jitter.empty() ? 0 : jitter[k]);
    dec.feed(p.bytes.data(), p.bytes.size(), recv, &out);
  }
  if (flush) dec.flush(&out);
  return out;
}

TEST(LidarDecoder, CutsOneCloudPerRevolutionAtTheCutAzimuth) {
  SyntheticVlp16 s;  // 10 Hz, starts at 300 deg
  Counts counts;
  LidarDecoder dec(vlp_params(), counts.fn());
  const double per_packet = 12 * s.degrees_per_block();
  const int n = static_cast<int>(std::ceil((60.0 + 720.0 + 100.0) / per_packet));
  auto revs = run(dec, s, n);
  ASSERT_EQ(revs.size(), 4u);  // 300->360, two full turns, the flushed rest
  // Every firing of a full turn: 360 deg / (deg per block) blocks, two firings each, 16 lasers.
  const double firings_per_turn = 2.0 * 360.0 / s.degrees_per_block();
  for (int i : {1, 2}) {
    const auto& c = revs[i].cloud;
    EXPECT_NEAR(c.n, 16.0 * firings_per_turn, 16.0 * 2) << i;
    EXPECT_EQ(c.n, static_cast<int>(c.x.size()));
    // The first points lie just past azimuth 0 (forward, +x, y slightly negative = right);
    // the last firing starts just before it (its laser 0 has y slightly positive).
    EXPECT_GT(c.x[0], 9.9);
    EXPECT_LE(c.y[0], 0.0f);
    EXPECT_GT(c.y[0], -0.2f);
    const int last_firing_laser0 = c.n - 16;
    EXPECT_GT(c.x[last_firing_laser0], 9.9);
    EXPECT_GT(c.y[last_firing_laser0], 0.0f);
    EXPECT_LT(c.y[last_firing_laser0], 0.2f);
    // 1 / rate apart, first-point times.
    EXPECT_NEAR(static_cast<double>(revs[i + 1].cloud.utime - c.utime), 1e5, 60.0);
    // Offsets rise monotonically to about one revolution.
    for (int j = 1; j < c.n; ++j) ASSERT_GE(c.time_offset[j], c.time_offset[j - 1]);
    EXPECT_NEAR(c.time_offset[c.n - 1], 1e5, 120.0);
    EXPECT_EQ(c.sensor_model, "vlp16");
  }
  EXPECT_EQ(counts.c["revolutions"], 4);
  EXPECT_EQ(counts.c["data_packets"], n);
  // Every packet appears in exactly one scan, in order.
  int total = 0;
  for (const auto& r : revs) total += r.scan.num_packets;
  EXPECT_EQ(total, n);
}

TEST(LidarDecoder, ReceiveTimeStampsAreExactSensorTimesPlusLatencyDespiteJitter) {
  SyntheticVlp16 s;
  s.start_azimuth_deg = 0.5;  // the first revolution starts with the first packet
  const int n = 200;
  std::vector<int64_t> jitter(n);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> u(0, 400);
  for (int k = 1; k < n; ++k) jitter[k] = u(rng);  // the anchor packet (0) arrives on time
  LidarDecoder dec(vlp_params(), nullptr);
  auto revs = run(dec, s, n, true, jitter);
  ASSERT_GE(revs.size(), 2u);
  const auto& c = revs[0].cloud;
  // utime = the first firing's true time + latency; offsets = true sensor deltas.
  EXPECT_EQ(c.utime, s.start_utime + kLatencyUs);
  // The point of laser l, sequence q, block b, packet k fired at
  // k * 1327.104 + firing_offset(b, q, l) after the first.
  int k = 3, b = 4, q = 1, l = 9;
  const size_t idx = static_cast<size_t>(((k * 12 + b) * 2 + q) * 16 + l);
  ASSERT_LT(idx, c.time_offset.size());
  // (the sensor's timestamps are whole microseconds)
  const int64_t packet_delta = s.packet(k).sensor_utime - s.packet(0).sensor_utime;
  EXPECT_EQ(c.time_offset[idx], std::llround(packet_delta + vlp16::firing_offset_us(b, q, l)));
  EXPECT_EQ(c.ring[idx], vlp16::kLaserTable[l].ring);
}

TEST(LidarDecoder, SensorTimeSourceResolvesThePastHourAgainstTheReceiveTime) {
  SyntheticVlp16 s;
  s.start_azimuth_deg = 0.5;
  // Start 0.5 ms before an hour boundary: the past-hour count wraps inside the revolution.
  s.start_utime = 3'600'000'000LL * 490'000 - 500;
  LidarDecoderParams p = vlp_params();
  p.time_source = TimeSource::kSensor;
  Counts counts;
  LidarDecoder dec(p, counts.fn());
  // Receive clock 20 s off the sensor clock: the sensor time wins.
  std::vector<Revolution> out;
  for (int k = 0; k < 100; ++k) {
    auto pk = s.packet(k);
    dec.feed(pk.bytes.data(), pk.bytes.size(), pk.sensor_utime + 20'000'000, &out);
  }
  dec.flush(&out);
  ASSERT_GE(out.size(), 1u);
  EXPECT_EQ(out[0].cloud.utime, s.start_utime);
  EXPECT_EQ(out[0].cloud.time_offset[16 * 24 * 10], std::llround(10 * s.packet_period_us()));
  EXPECT_EQ(counts.c["sensor_time_jumps"], 0);
}

TEST(LidarDecoder, DualReturnRevolutionHasBothEchoes) {
  SyntheticVlp16 s;
  s.return_mode = vlp16::kDual;
  s.start_azimuth_deg = 0.5;
  Counts counts;
  LidarDecoder dec(vlp_params(), counts.fn());
  auto revs = run(dec, s, 200);
  ASSERT_GE(revs.size(), 2u);
  const auto& c = revs[0].cloud;
  // The two echoes of a firing are never split by a cut.
  for (const auto& r : revs) {
    int strong = 0, last = 0;
    for (int i = 0; i < r.cloud.n; ++i) (r.cloud.intensity[i] == 200 ? strong : last)++;
    EXPECT_EQ(strong, last);
  }
  // The first revolution starts at 0.5 deg, the second at the firing just past 360.
  EXPECT_NEAR(static_cast<double>(revs[1].cloud.utime - c.utime), 1e5 * 359.5 / 360.0, 60.0);
  EXPECT_EQ(counts.c["dual_duplicates"], 0);
}

TEST(LidarDecoder, ForcedCutWhenTheAzimuthNeverWraps) {
  LidarDecoderParams p = vlp_params();
  p.max_packets_per_revolution = 10;
  Counts counts;
  LidarDecoder dec(p, counts.fn());
  vlp16::PacketEncoder enc;  // a stopped motor: constant azimuth
  for (auto& b : enc.blocks) b.distance_m[0][0] = 3.0;
  auto bytes = enc.encode();
  std::vector<Revolution> out;
  for (int k = 0; k < 35; ++k) dec.feed(bytes.data(), bytes.size(), 1'000'000 + k * 1327, &out);
  EXPECT_EQ(out.size(), 3u);
  EXPECT_EQ(counts.c["forced_cuts"], 3);
  for (const auto& r : out) EXPECT_EQ(r.cloud.packets, 10);
}

TEST(LidarDecoder, PacketsWithoutPointsDoNotPileUp) {
  LidarDecoderParams p = vlp_params();
  p.max_packets_per_revolution = 100;
  Counts counts;
  LidarDecoder dec(p, counts.fn());
  std::vector<Revolution> out;
  testing::SyntheticVlp16 s;
  s.range_m = 0.0;  // a covered sensor: every distance zero
  for (int k = 0; k < 5000; ++k) {
    auto pk = s.packet(k);
    dec.feed(pk.bytes.data(), pk.bytes.size(), pk.sensor_utime + 2000, &out);
  }
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(counts.c["data_packets"], 5000);
  EXPECT_GE(counts.c["empty_packets_dropped"], 4900);
  s.range_m = 10.0;  // uncovered: revolutions again, with bounded scans
  for (int k = 5000; k < 5300; ++k) {
    auto pk = s.packet(k);
    dec.feed(pk.bytes.data(), pk.bytes.size(), pk.sensor_utime + 2000, &out);
  }
  ASSERT_GE(out.size(), 2u);
  for (const auto& r : out) EXPECT_LE(r.scan.num_packets, 100);
  // Replay of the scans gives the same clouds.
  LidarDecoder again(p, nullptr);
  std::vector<Revolution> replayed;
  for (const auto& r : out) again.feed_scan(r.scan, &replayed);
  ASSERT_EQ(replayed.size(), out.size());
  for (size_t i = 0; i < out.size(); ++i) EXPECT_EQ(replayed[i].cloud.x, out[i].cloud.x);
}

TEST(LidarDecoder, MalformedAndForeignPacketsAreCountedNotDecoded) {
  Counts counts;
  LidarDecoder dec(vlp_params(), counts.fn());
  std::vector<Revolution> out;
  std::vector<uint8_t> position(512, 0), shortp(100, 0xFF), longp(1300, 0);
  dec.feed(position.data(), position.size(), 1, &out);
  dec.feed(shortp.data(), shortp.size(), 2, &out);
  dec.feed(longp.data(), longp.size(), 3, &out);
  std::vector<uint8_t> wrong_flag(vlp16::kPacketSize, 0);
  dec.feed(wrong_flag.data(), wrong_flag.size(), 4, &out);
  dec.feed(nullptr, 0, 5, &out);
  dec.flush(&out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(counts.c["position_packets"], 1);
  EXPECT_EQ(counts.c["malformed_wrong_size"], 3);
  EXPECT_EQ(counts.c["malformed_bad_flag"], 1);
  EXPECT_EQ(counts.c["data_packets"], 0);
}

TEST(LidarDecoder, RandomBytesNeverCrash) {
  std::mt19937 rng(1234);
  for (LidarModel m : {LidarModel::kVlp16, LidarModel::kRsHelios}) {
    LidarDecoderParams p = vlp_params();
    p.model = m;
    Counts counts;
    LidarDecoder dec(p, counts.fn());
    std::vector<Revolution> out;
    SyntheticVlp16 s;
    for (int i = 0; i < 3000; ++i) {
      std::vector<uint8_t> buf;
      if (i % 3 == 0) {  // a valid packet with random bytes flipped
        auto pk = s.packet(i);
        buf.assign(pk.bytes.begin(), pk.bytes.end());
        for (int f = 0; f < 8; ++f) buf[rng() % buf.size()] = static_cast<uint8_t>(rng());
      } else {
        buf.resize(rng() % 1400);
        for (auto& b : buf) b = static_cast<uint8_t>(rng());
      }
      dec.feed(buf.data(), buf.size(), i * 1000, &out);
    }
    dec.flush(&out);
    for (const auto& r : out) {
      ASSERT_EQ(r.cloud.n, static_cast<int>(r.cloud.x.size()));
      for (int j = 0; j < r.cloud.n; ++j) ASSERT_TRUE(std::isfinite(r.cloud.x[j]) && std::isfinite(r.cloud.z[j]));
    }
  }
}

// ---------------------------------------------------------- self-filter

// Sensor-frame coordinates of a base-frame point, for a mount pose (the
// inverse of R = Rz(yaw) Ry(pitch) Rx(roll) plus the mount offset).
void base_to_sensor(const evade::pose3d_t& m, double bx, double by, double bz, float* x, float* y, float* z) {
  const double cr = std::cos(m.roll), sr = std::sin(m.roll), cp = std::cos(m.pitch), sp = std::sin(m.pitch);
  const double cy = std::cos(m.yaw), sy = std::sin(m.yaw);
  const double r[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                          {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                          {-sp, cp * sr, cp * cr}};
  const double d[3] = {bx - m.x, by - m.y, bz - m.z};
  *x = static_cast<float>(r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2]);
  *y = static_cast<float>(r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2]);
  *z = static_cast<float>(r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2]);
}

TEST(SelfFilter, DropsTheFootprintColumnGrownByTheMarginWhateverTheMount) {
  evade::pose3d_t mount;
  mount.x = 0.2;
  mount.y = -0.1;
  mount.z = 0.9;
  mount.roll = 0.05;
  mount.pitch = 0.3;  // tilted forward, looking down
  mount.yaw = 0.4;
  SelfFilter f(scout_sized(true, mount));
  float x, y, z;
  for (double bz : {0.0, 0.3, 0.9, 1.5}) {
    for (double bx : {-0.5, 0.0, 0.3, 0.51}) {
      base_to_sensor(mount, bx, 0.39, bz, &x, &y, &z);
      EXPECT_TRUE(f.inside(x, y, z)) << bx << " " << bz;
      base_to_sensor(mount, bx, 0.41, bz, &x, &y, &z);
      EXPECT_FALSE(f.inside(x, y, z)) << bx << " " << bz;
    }
    base_to_sensor(mount, 0.53, 0.0, bz, &x, &y, &z);
    EXPECT_FALSE(f.inside(x, y, z));
    base_to_sensor(mount, -0.53, -0.2, bz, &x, &y, &z);
    EXPECT_FALSE(f.inside(x, y, z));
  }
  SelfFilter off(scout_sized(false, mount));
  EXPECT_FALSE(off.enabled());
}

// An RS-Helios mounted 0.9 m up on a Scout-sized robot: its -55 deg
// channel at 0.6 m lands on the robot (0.34 m out), its -22 deg channel at
// 2.4 m on the ground beyond; only the second is kept, and the first is counted.
TEST(SelfFilter, TheDecoderDropsReturnsOnTheRobotsBody) {
  rs_helios::DifopEncoder difop;
  for (int c = 0; c < rs_helios::kChannels; ++c) difop.vertical_deg[c] = 15.0 - 70.0 * c / 31.0;
  difop.vertical_deg[31] = -55.0;
  difop.vertical_deg[20] = -22.0;
  auto difop_bytes = difop.encode();
  auto run_once = [&](bool enabled, std::map<std::string, int64_t>* counts) {
    evade::pose3d_t mount{};
    mount.z = 0.9;
    LidarDecoderParams p = scout_sized(enabled, mount);
    p.model = LidarModel::kRsHelios;
    p.min_range_m = 0.0;
    LidarDecoder dec(p, [&](const std::string& n, int64_t k) { (*counts)[n] += k; });
    std::vector<Revolution> out;
    dec.feed(difop_bytes.data(), difop_bytes.size(), 1'000'000, &out);
    for (int k = 0; k < 3; ++k) {
      rs_helios::MsopEncoder m;
      for (int b = 0; b < rs_helios::kBlocksPerPacket; ++b) {
        m.blocks[b].azimuth_deg = std::fmod(350.0 + 0.2 * (12 * k + b), 360.0);
        m.blocks[b].distance_m[31] = 0.6;
        m.blocks[b].distance_m[20] = 2.4;
      }
      m.utc_us = 1'000'000 + k * 667;
      auto bytes = m.encode();
      dec.feed(bytes.data(), bytes.size(), 1'001'000 + k * 667, &out);
    }
    dec.flush(&out);
    std::vector<int> lasers;
    for (const auto& r : out)
      for (int i = 0; i < r.cloud.n; ++i) lasers.push_back(r.cloud.ring[i]);
    return lasers;
  };
  std::map<std::string, int64_t> with, without;
  auto kept = run_once(true, &with);
  auto all = run_once(false, &without);
  EXPECT_EQ(all.size(), 2u * 36u);  // 36 firings, two returns each
  ASSERT_EQ(kept.size(), 36u);
  rs_helios::Calibration cal;
  ASSERT_EQ(rs_helios::parse_difop(difop_bytes.data(), difop_bytes.size(), &cal), rs_helios::PacketStatus::kOk);
  for (int ring : kept) EXPECT_EQ(ring, cal.ring[20]);  // the -22 deg channel
  EXPECT_EQ(with["self_filtered_points"], 36);
  EXPECT_EQ(without["self_filtered_points"], 0);
}

// ---------------------------------------------------------------- the core

config::Node test_config(const std::string& model = "vlp16") {
  return config::load_string(R"(
lidar:
  model: )" + model + R"(
  mount: {x_m: 0.1, y_m: -0.05, z_m: 0.5, roll_rad: 0.0, pitch_rad: 0.01, yaw_rad: 0.02}
lidar_driver:
  bind_address: 127.0.0.1
  vlp16_data_port: 2368
  rs_helios_msop_port: 6699
  rs_helios_difop_port: 7788
  socket_receive_buffer_bytes: 1048576
  cut_azimuth_deg: 0.0
  min_range_m: 0.4
  max_range_m: 100.0
  vertical_offset_correction: true
  time_source: receive
  max_packets_per_revolution: 1000
  publish_scan: true
  self_filter: true
  self_filter_margin_m: 0.05
robot: {footprint_length_m: 0.42, footprint_width_m: 0.31, max_v_mps: 1.0, min_v_mps: 0.0, max_omega_radps: 0.5,
        max_accel_mps2: 1.0, max_decel_mps2: 1.5, max_alpha_radps2: 3.0}
)",
                             "test.yaml");
}

TEST(LidarDriverConfig, ReadsRobotYamlAndRejectsBadValues) {
  auto p = LidarDriverParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
  EXPECT_EQ(p.bind_address, "0.0.0.0");
  EXPECT_EQ(p.ports(), std::vector<int>{2368});
  auto q = LidarDriverParams::from_config(test_config("rs_helios"));
  EXPECT_EQ(q.ports(), (std::vector<int>{6699, 7788}));
  EXPECT_TRUE(q.self_filter);
  EXPECT_DOUBLE_EQ(q.self_filter_margin_m, 0.05);
  EXPECT_DOUBLE_EQ(q.footprint_length_m, 0.42);
  EXPECT_DOUBLE_EQ(q.mount.pitch, 0.01);
  std::string bad = R"(
lidar: {model: vlp16, mount: {x_m: 0, y_m: 0, z_m: 0.5, roll_rad: 0, pitch_rad: 0, yaw_rad: 0}}
lidar_driver: {bind_address: localhost}
)";
  EXPECT_THROW(LidarDriverParams::from_config(config::load_string(bad, "bad.yaml")), config::ConfigError);
}

TEST(LidarDriverCore, PublishesPointsAndScansAndReplayOfScansIsIdentical) {
  const auto params = LidarDriverParams::from_config(test_config());
  bus::MemoryBus live;
  LidarDriverCore core(params, LidarDriverCore::Source::kPackets);
  live.add(core);
  SyntheticVlp16 s;
  const int n = 300;
  for (int k = 0; k < n; ++k) {
    auto p = s.packet(k);
    int64_t recv = p.sensor_utime + 1500 + (k * 37) % 200;
    live.input(core, recv, [&] { core.on_packet(p.bytes.data(), p.bytes.size()); });
  }
  live.input(core, s.packet(n).sensor_utime, [&] { core.flush(); });
  auto points = live.decoded<evade::pointcloud_t>(kLidarPointsChannel);
  auto scans = live.decoded<evade::lidar_scan_t>(kLidarScanChannel);
  ASSERT_EQ(points.size(), 5u);
  ASSERT_EQ(scans.size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(points[i].utime, scans[i].utime);
    EXPECT_DOUBLE_EQ(points[i].mount.x, 0.1);
    EXPECT_DOUBLE_EQ(points[i].mount.yaw, 0.02);
  }
  EXPECT_EQ(core.counter("data_packets"), n);

  // Replay: a fresh core reading only the LIDAR_SCAN messages.
  bus::MemoryBus replay;
  LidarDriverCore again(params, LidarDriverCore::Source::kScans);
  replay.add(again);
  for (const auto& e : live.published())
    if (e.channel == kLidarScanChannel) replay.inject(e.channel, e.data, e.timestamp);
  std::vector<std::vector<uint8_t>> a, b;
  for (const auto& e : live.published())
    if (e.channel == kLidarPointsChannel) a.push_back(e.data);
  for (const auto& e : replay.published())
    if (e.channel == kLidarPointsChannel) b.push_back(e.data);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "revolution " << i;
  EXPECT_TRUE(replay.decoded<evade::lidar_scan_t>(kLidarScanChannel).empty());
}

TEST(LidarDriverCore, HealthReportsCounters) {
  const auto params = LidarDriverParams::from_config(test_config());
  bus::MemoryBus mb;
  LidarDriverCore core(params, LidarDriverCore::Source::kPackets);
  mb.add(core);
  std::vector<uint8_t> junk(77, 1);
  mb.input(core, 1'000'000, [&] { core.on_packet(junk.data(), junk.size()); });
  mb.advance_to(3'000'000);
  auto health = mb.decoded<evade::health_t>("HEALTH");
  ASSERT_FALSE(health.empty());
  const auto& h = health.back();
  EXPECT_EQ(h.name, "lidar_driver");
  bool found = false;
  for (const auto& c : h.counters)
    if (c.name == "malformed_wrong_size") found = (c.value == 1);
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace evade::sensing

namespace evade::sensing {
namespace {

// Scans recorded by a live core from synthetic packets (5 revolutions).
std::vector<bus::LogEvent> recorded_scans(const LidarDriverParams& params, std::vector<evade::pointcloud_t>* clouds) {
  bus::MemoryBus live;
  LidarDriverCore core(params, LidarDriverCore::Source::kPackets);
  live.add(core);
  SyntheticVlp16 s;
  for (int k = 0; k < 300; ++k) {
    auto p = s.packet(k);
    live.input(core, p.sensor_utime + 1500, [&] { core.on_packet(p.bytes.data(), p.bytes.size()); });
  }
  *clouds = live.decoded<evade::pointcloud_t>(kLidarPointsChannel);
  std::vector<bus::LogEvent> scans;
  for (const auto& e : live.published())
    if (e.channel == kLidarScanChannel) scans.push_back(e);
  return scans;
}

// lcm-logplayer-gui can jump back (or loop): LIDAR_SCAN time then goes
// backwards. The revolution being assembled belongs to the later time and
// is dropped, so the first revolution after the jump is not a mix of both.
TEST(LidarDriverCore, ScansThatJumpBackInTimeStartAFreshRevolution) {
  const auto params = LidarDriverParams::from_config(test_config());
  std::vector<evade::pointcloud_t> original;
  const auto scans = recorded_scans(params, &original);
  ASSERT_EQ(scans.size(), 4u);  // the fifth revolution is still being assembled

  bus::MemoryBus mb;
  LidarDriverCore core(params, LidarDriverCore::Source::kScans);
  mb.add(core);
  int64_t t = 0;
  for (size_t i = 0; i < 4; ++i) mb.inject(scans[i].channel, scans[i].data, t += 100'000);
  for (size_t i = 1; i < 4; ++i) mb.inject(scans[i].channel, scans[i].data, t += 100'000);  // back to scan 1
  const auto clouds = mb.decoded<evade::pointcloud_t>(kLidarPointsChannel);
  ASSERT_EQ(clouds.size(), 7u);
  EXPECT_EQ(core.counter("scan_discontinuities"), 1);
  // First pass as recorded.
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(bus::encode(clouds[i]), bus::encode(original[i])) << i;
  // Right after the jump: scan 1's own packets only, at scan 1's time, every
  // point within the revolution (a mix would carry times 0.3 s apart).
  const auto& after = clouds[4];
  EXPECT_GE(after.utime, original[1].utime);
  EXPECT_LE(after.utime, original[1].utime + 2000);
  EXPECT_GT(after.n, original[1].n * 9 / 10);
  EXPECT_LE(after.n, original[1].n);
  for (int32_t off : after.time_offset) {
    ASSERT_GE(off, 0);
    ASSERT_LE(off, 110'000);
  }
  // Then the stream is whole again.
  EXPECT_EQ(bus::encode(clouds[5]), bus::encode(original[2]));
  EXPECT_EQ(bus::encode(clouds[6]), bus::encode(original[3]));
}

}  // namespace
}  // namespace evade::sensing
