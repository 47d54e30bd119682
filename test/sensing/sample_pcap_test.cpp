// The real VLP-16 capture test/data/vlp16_sample.pcap (test/data/README.md):
// 84 data packets (factory byte 0x21, VLP-16 data), 16 position packets on
// port 8308, azimuth 250.35 deg -> wrap after packet 23 -> 286.4 deg.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "bus/memory_bus.h"
#include "config/config.h"
#include "sensing/lidar_driver_core.h"
#include "sensing/packet_sources.h"
#include "sensing/vlp16.h"

namespace evade::sensing {
namespace {

std::string sample_path() { return std::string(EVADE_SOURCE_DIR) + "/test/data/vlp16_sample.pcap"; }

bool exists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

struct Decoded {
  std::vector<evade::pointcloud_t> clouds;
  std::vector<evade::lidar_scan_t> scans;
  int64_t datagrams = 0, port_2368 = 0, port_8308 = 0, truncated = 0;
  int64_t first_capture_utime = -1;
  std::map<std::string, int64_t> counters;
};

Decoded decode_sample(double max_range_m) {
  auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  auto params = LidarDriverParams::from_config(root);
  params.max_range_m = max_range_m;
  params.min_range_m = 0.0;
  bus::MemoryBus mb;
  LidarDriverCore core(params, LidarDriverCore::Source::kPackets);
  mb.add(core);
  PcapUdpReader reader(sample_path());
  UdpDatagram d;
  Decoded out;
  while (reader.next(&d)) {
    ++out.datagrams;
    if (out.first_capture_utime < 0) out.first_capture_utime = d.utime;
    out.port_2368 += d.dst_port == 2368;
    out.port_8308 += d.dst_port == 8308;
    out.truncated += d.truncated;
    // Everything goes to the decoder, as if all arrived on one socket: the
    // decoder itself must recognise and skip the position packets.
    mb.input(core, d.utime, [&] { core.on_packet(d.payload.data(), d.payload.size()); });
  }
  EXPECT_TRUE(reader.error().empty()) << reader.error();
  mb.input(core, d.utime, [&] { core.flush(); });
  out.clouds = mb.decoded<evade::pointcloud_t>(kLidarPointsChannel);
  out.scans = mb.decoded<evade::lidar_scan_t>(kLidarScanChannel);
  for (const char* name :
       {"data_packets", "position_packets", "factory_byte_0x21", "revolutions", "out_of_range", "malformed_wrong_size"})
    out.counters[name] = core.counter(name);
  return out;
}

TEST(Vlp16SamplePcap, DecodesTheRealCapture) {
  ASSERT_TRUE(exists(sample_path())) << "missing " << sample_path();
  Decoded s = decode_sample(vlp16::kMaxEncodableRangeM);

  EXPECT_EQ(s.datagrams, 100);
  EXPECT_EQ(s.port_2368, 84);
  EXPECT_EQ(s.port_8308, 16);
  EXPECT_EQ(s.truncated, 0);
  EXPECT_EQ(s.counters["data_packets"], 84);
  EXPECT_EQ(s.counters["position_packets"], 16);
  EXPECT_EQ(s.counters["factory_byte_0x21"], 84);  // reported, decoded as a VLP-16 anyway
  EXPECT_EQ(s.counters["malformed_wrong_size"], 0);

  // Two partial revolutions: packet 23 (0-based) starts at azimuth 0.17 deg,
  // so the cut falls before its first firing: its points all belong to the
  // second revolution, its bytes to the first one's LIDAR_SCAN (the scan of
  // the revolution it completed). The second is flushed at the end of the file.
  ASSERT_EQ(s.clouds.size(), 2u);
  ASSERT_EQ(s.scans.size(), 2u);
  EXPECT_EQ(s.clouds[0].packets, 23);
  EXPECT_EQ(s.clouds[1].packets, 61);
  EXPECT_EQ(s.scans[0].num_packets, 24);
  EXPECT_EQ(s.scans[1].num_packets, 60);

  // Receive-time stamping: the first cloud starts with the first packet's
  // first return, one packet span before that packet was captured.
  const double span = vlp16::firing_offset_us(11, 1, 15);
  EXPECT_NEAR(static_cast<double>(s.clouds[0].utime - s.first_capture_utime), -span, 60.0);
  // 10 Hz: the 250.35 deg -> 360 deg stretch (about 30 ms) precedes the second.
  EXPECT_NEAR(static_cast<double>(s.clouds[1].utime - s.clouds[0].utime), 1e5 * (360.0 - 250.35) / 360.0, 1500.0);

  std::array<int64_t, 16> per_ring{};
  for (size_t r = 0; r < s.clouds.size(); ++r) {
    const auto& c = s.clouds[r];
    ASSERT_EQ(static_cast<size_t>(c.n), c.x.size());
    ASSERT_EQ(static_cast<size_t>(c.n), c.time_offset.size());
    // Each revolution holds at most 24 firings x 16 lasers per packet.
    EXPECT_LE(c.n, c.packets * 384);
    EXPECT_GT(c.n, c.packets * 384 / 4) << "revolution " << r;
    for (int i = 0; i < c.n; ++i) {
      ASSERT_TRUE(std::isfinite(c.x[i]) && std::isfinite(c.y[i]) && std::isfinite(c.z[i]));
      const double range = std::sqrt(c.x[i] * c.x[i] + c.y[i] * c.y[i] + c.z[i] * c.z[i]);
      ASSERT_GT(range, 0.0);
      ASSERT_LE(range, vlp16::kMaxEncodableRangeM + 0.02);
      ASSERT_GE(c.ring[i], 0);
      ASSERT_LT(c.ring[i], 16);
      ASSERT_GE(c.time_offset[i], 0);
      ASSERT_LT(c.time_offset[i], c.packets * 1400);
      ++per_ring[static_cast<size_t>(c.ring[i])];
    }
  }
  // Every laser returned something; the downward half (rings 0..7, -15..-1 deg)
  // sees the ground everywhere, the upward half partly sky, so it has fewer.
  int64_t down = 0, up = 0;
  for (int r = 0; r < 16; ++r) {
    EXPECT_GT(per_ring[r], 0) << "ring " << r;
    (r < 8 ? down : up) += per_ring[r];
  }
  EXPECT_GT(down, up);
  // The lowest ring hits the ground in nearly every firing: 84 packets x 24 firings.
  EXPECT_GT(per_ring[0], 84 * 24 * 8 / 10);
  std::printf("sample: clouds %d + %d points; rings:", s.clouds[0].n, s.clouds[1].n);
  for (int r = 0; r < 16; ++r) std::printf(" %lld", static_cast<long long>(per_ring[r]));
  std::printf("; beyond 100 m: %lld\n", static_cast<long long>(s.counters["out_of_range"]));
}

TEST(Vlp16SamplePcap, RangeLimitFromConfigDropsAndCounts) {
  ASSERT_TRUE(exists(sample_path())) << "missing " << sample_path();
  Decoded all = decode_sample(vlp16::kMaxEncodableRangeM);
  Decoded near = decode_sample(10.0);
  int64_t all_n = 0, near_n = 0, all_within = 0;
  for (const auto& c : all.clouds) {
    all_n += c.n;
    for (int i = 0; i < c.n; ++i) {
      // The decoder's range, undoing the per-laser vertical offset.
      const auto& c0 = c;
      double r2 = c0.x[i] * c0.x[i] + c0.y[i] * c0.y[i];
      double dz = vlp16::kLaserTable[vlp16::kLaserOfRing[c0.ring[i]]].vertical_offset_m;
      double z = c0.z[i] - dz;
      all_within += std::sqrt(r2 + z * z) <= 10.0 + 1e-4;
    }
  }
  for (const auto& c : near.clouds) {
    near_n += c.n;
    for (int i = 0; i < c.n; ++i) ASSERT_LE(std::hypot(c.x[i], c.y[i]), 10.0 + 1e-3);
  }
  EXPECT_EQ(near_n, all_within);
  EXPECT_EQ(near.counters["out_of_range"], all_n - near_n);
  EXPECT_LT(near_n, all_n);
}

}  // namespace
}  // namespace evade::sensing
