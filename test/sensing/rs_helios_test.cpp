// RS-Helios MSOP/DIFOP: byte layout, calibration, known geometry per
// channel, dual return, and no output before the first DIFOP.
#include "sensing/rs_helios.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "sensing/lidar_decoder.h"

namespace h = evade::sensing::rs_helios;

namespace {
constexpr double kDeg = M_PI / 180.0;

// An arbitrary, non-monotonic elevation table spanning -55..+15 deg, and
// small per-channel azimuth corrections, as a DIFOP would carry them.
h::DifopEncoder test_difop(uint8_t mode = h::kStrongest) {
  h::DifopEncoder d;
  for (int c = 0; c < h::kChannels; ++c) {
    d.vertical_deg[c] = (c % 2 == 0) ? -55.0 + 2.2 * c : 15.0 - 1.1 * c;  // two interleaved fans
    d.horizontal_deg[c] = 0.01 * ((c * 7) % 11) - 0.05;
  }
  d.return_mode = mode;
  return d;
}

h::Calibration calibration(uint8_t mode = h::kStrongest) {
  auto bytes = test_difop(mode).encode();
  h::Calibration cal;
  EXPECT_EQ(h::parse_difop(bytes.data(), bytes.size(), &cal), h::PacketStatus::kOk);
  return cal;
}
}  // namespace

TEST(RsHeliosDifop, RoundTripAndRings) {
  auto enc = test_difop(h::kLast);
  enc.rpm = 1200;
  auto bytes = enc.encode();
  EXPECT_EQ(h::classify(bytes.data(), bytes.size()), h::PacketKind::kDifop);
  // Big-endian angle: channel 0 = -55.00 deg -> sign 1, 5500 = 0x157C.
  EXPECT_EQ(bytes[468], 1);
  EXPECT_EQ(bytes[469], 0x15);
  EXPECT_EQ(bytes[470], 0x7C);
  EXPECT_EQ(bytes[8], 0x04);  // 1200 rpm = 0x04B0
  EXPECT_EQ(bytes[9], 0xB0);
  h::Calibration cal;
  ASSERT_EQ(h::parse_difop(bytes.data(), bytes.size(), &cal), h::PacketStatus::kOk);
  EXPECT_EQ(cal.rpm, 1200);
  EXPECT_EQ(cal.return_mode, h::kLast);
  for (int c = 0; c < h::kChannels; ++c) {
    EXPECT_NEAR(cal.vertical_deg[c], enc.vertical_deg[c], 0.005);
    EXPECT_NEAR(cal.horizontal_deg[c], enc.horizontal_deg[c], 0.005);
  }
  for (int a = 0; a < h::kChannels; ++a)
    for (int b = 0; b < h::kChannels; ++b)
      if (cal.vertical_deg[a] < cal.vertical_deg[b]) {
        EXPECT_LT(cal.ring[a], cal.ring[b]);
      }
  EXPECT_EQ(cal.ring[0], 0);  // -55 deg is the lowest

  std::array<uint8_t, h::kPacketSize> blank{};
  std::copy(h::kDifopId.begin(), h::kDifopId.end(), blank.begin());
  EXPECT_EQ(h::parse_difop(blank.data(), blank.size(), &cal), h::PacketStatus::kNoCalibration);
  EXPECT_EQ(h::parse_difop(bytes.data(), 1000, &cal), h::PacketStatus::kWrongSize);
}

TEST(RsHeliosMsop, ByteLayoutIsBigEndianAfterA42ByteHeader) {
  h::MsopEncoder m;
  m.blocks[0].azimuth_deg = 123.45;  // 12345 = 0x3039
  m.blocks[0].distance_m[1] = 10.0;  // 4000 = 0x0FA0 in 2.5 mm units
  m.blocks[0].intensity[1] = 99;
  m.utc_us = 1'700'000'000'123'456LL;
  auto b = m.encode();
  EXPECT_EQ(b.size(), 1248u);
  EXPECT_EQ(b[0], 0x55);
  EXPECT_EQ(b[3], 0x5A);
  EXPECT_EQ(b[42], 0xFF);
  EXPECT_EQ(b[43], 0xEE);
  EXPECT_EQ(b[44], 0x30);
  EXPECT_EQ(b[45], 0x39);
  EXPECT_EQ(b[46 + 3], 0x0F);
  EXPECT_EQ(b[46 + 4], 0xA0);
  EXPECT_EQ(b[46 + 5], 99);
  EXPECT_EQ(b[142], 0xFF);  // block 1
  h::PacketInfo info;
  std::vector<evade::sensing::LidarReturn> out;
  ASSERT_EQ(h::decode_msop(b.data(), b.size(), calibration(), {}, &out, &info), h::PacketStatus::kOk);
  EXPECT_EQ(info.utc_us, m.utc_us);
  ASSERT_EQ(out.size(), 1u);
}

class RsHeliosPerChannel : public ::testing::TestWithParam<int> {};

TEST_P(RsHeliosPerChannel, KnownGeometry) {
  const int ch = GetParam();
  const h::Calibration cal = calibration();
  for (double az : {0.0, 90.0, 200.0, 315.5}) {
    h::MsopEncoder m;
    for (auto& blk : m.blocks) blk.azimuth_deg = az;  // no rotation: no interpolation
    const double range = 4.0 + 0.5 * ch;              // exact in 2.5 mm units
    m.blocks[7].distance_m[ch] = range;
    m.blocks[7].intensity[ch] = static_cast<uint8_t>(ch);
    auto b = m.encode();
    std::vector<evade::sensing::LidarReturn> out;
    ASSERT_EQ(h::decode_msop(b.data(), b.size(), cal, {}, &out, nullptr), h::PacketStatus::kOk);
    ASSERT_EQ(out.size(), 1u);
    const double el = cal.vertical_deg[ch] * kDeg;
    const double a = (az + cal.horizontal_deg[ch]) * kDeg;
    const double d = h::kOpticalCentreOffsetM;
    EXPECT_NEAR(out[0].x, range * std::cos(el) * std::cos(a) + d * std::cos(az * kDeg), 1e-5);
    EXPECT_NEAR(out[0].y, -range * std::cos(el) * std::sin(a) - d * std::sin(az * kDeg), 1e-5);
    EXPECT_NEAR(out[0].z, range * std::sin(el), 1e-5);
    EXPECT_EQ(out[0].ring, cal.ring[ch]);
    EXPECT_EQ(out[0].intensity, ch);
    EXPECT_NEAR(out[0].time_offset_us, 7 * 55.56 + ch * 1.73, 1e-3);
  }
}
INSTANTIATE_TEST_SUITE_P(AllChannels, RsHeliosPerChannel, ::testing::Range(0, 32));

TEST(RsHeliosMsop, AzimuthInterpolatedWithChannelTiming) {
  h::Calibration cal = calibration();
  cal.horizontal_deg.fill(0.0);
  cal.update_trig();
  h::MsopEncoder m;
  for (int b = 0; b < 12; ++b) {
    m.blocks[b].azimuth_deg = 10.0 + 0.2 * b;
    for (int c = 0; c < 32; ++c) m.blocks[b].distance_m[c] = 20.0;
  }
  auto bytes = m.encode();
  std::vector<evade::sensing::LidarReturn> out;
  ASSERT_EQ(h::decode_msop(bytes.data(), bytes.size(), cal, {}, &out, nullptr), h::PacketStatus::kOk);
  ASSERT_EQ(out.size(), 12u * 32u);
  for (int b = 0; b < 12; ++b)
    for (int c = 0; c < 32; ++c)
      EXPECT_NEAR(out[static_cast<size_t>(b * 32 + c)].azimuth_deg, 10.0 + 0.2 * b + 0.2 * c * 1.73 / 55.56, 1e-3);
}

TEST(RsHeliosMsop, DualReturnPairsShareAFiring) {
  const h::Calibration cal = calibration(h::kDual);
  h::MsopEncoder m;
  for (int k = 0; k < 6; ++k)
    for (int e = 0; e < 2; ++e) {
      m.blocks[2 * k + e].azimuth_deg = 50.0 + 0.2 * k;
      for (int c = 0; c < 32; ++c) m.blocks[2 * k + e].distance_m[c] = (c < 16 || e == 0) ? 9.0 : 30.0;
    }
  auto bytes = m.encode();
  std::vector<evade::sensing::LidarReturn> out;
  h::PacketInfo info;
  ASSERT_EQ(h::decode_msop(bytes.data(), bytes.size(), cal, {}, &out, &info), h::PacketStatus::kOk);
  EXPECT_EQ(info.firings, 6);
  EXPECT_EQ(info.dual_duplicates, 6 * 16);  // channels 0..15: both echoes equal
  ASSERT_EQ(out.size(), 6u * 48u);
  // Second echo of pair 3, channel 20: same time as the first echo.
  EXPECT_NEAR(out[3 * 48 + 32 + 4].time_offset_us, 3 * 55.56 + 20 * 1.73, 1e-3);
}

// The same screen as the VLP-16's (packet_returns.h), in big-endian bytes:
// zero counts are no return, ranges outside [min, max] are counted.
TEST(RsHeliosMsop, ZeroDistanceAndRangeLimitsDropped) {
  const h::Calibration cal = calibration();
  h::MsopEncoder m;
  for (int b = 0; b < 12; ++b) m.blocks[b].azimuth_deg = 10.0 + 0.2 * b;
  m.blocks[0].distance_m[0] = 0.5;
  m.blocks[0].distance_m[1] = 50.0;
  m.blocks[0].distance_m[2] = 120.0;
  m.blocks[5].distance_m[31] = 99.9;
  auto bytes = m.encode();
  std::vector<evade::sensing::LidarReturn> out;
  h::PacketInfo info;
  ASSERT_EQ(h::decode_msop(bytes.data(), bytes.size(), cal, h::DecodeOptions{1.0, 100.0}, &out, &info),
            h::PacketStatus::kOk);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].laser, 1);
  EXPECT_EQ(out[1].laser, 31);
  EXPECT_EQ(info.out_of_range, 2);
  EXPECT_EQ(info.dual_duplicates, 0);
}

TEST(RsHeliosMsop, RejectsMalformed) {
  const h::Calibration cal = calibration();
  h::MsopEncoder m;
  auto good = m.encode();
  std::vector<evade::sensing::LidarReturn> out;
  EXPECT_EQ(h::decode_msop(good.data(), 1247, cal, {}, &out, nullptr), h::PacketStatus::kWrongSize);
  auto bad = good;
  bad[1] = 0;
  EXPECT_EQ(h::decode_msop(bad.data(), bad.size(), cal, {}, &out, nullptr), h::PacketStatus::kBadHeader);
  bad = good;
  bad[42 + 5 * 100 + 1] = 0xEF;
  EXPECT_EQ(h::decode_msop(bad.data(), bad.size(), cal, {}, &out, nullptr), h::PacketStatus::kBadFlag);
  bad = good;
  bad[44] = 0xFF;
  EXPECT_EQ(h::decode_msop(bad.data(), bad.size(), cal, {}, &out, nullptr), h::PacketStatus::kBadAzimuth);
}

TEST(RsHeliosDecoder, NothingBeforeTheFirstDifopThenRevolutions) {
  std::map<std::string, int64_t> counts;
  evade::sensing::LidarDecoderParams p;
  p.model = evade::sensing::LidarModel::kRsHelios;
  p.time_source = evade::sensing::TimeSource::kSensor;
  p.min_range_m = 0.0;
  p.max_range_m = 200.0;
  p.self_filter = false;
  evade::sensing::LidarDecoder dec(p, [&](const std::string& n, int64_t k) { counts[n] += k; });
  const int64_t t0 = 1'700'000'000'000'000LL;
  // 10 Hz: 0.2 deg per 55.56 us block
  const double deg_per_block = 360.0 * 10.0 * 55.56e-6;
  auto msop = [&](int k) {
    h::MsopEncoder m;
    for (int b = 0; b < 12; ++b) {
      m.blocks[b].azimuth_deg = std::fmod(320.0 + (k * 12 + b) * deg_per_block, 360.0);
      for (int c = 0; c < 32; ++c) m.blocks[b].distance_m[c] = 5.0;
    }
    m.utc_us = t0 + std::llround(k * 12 * 55.56);
    return m.encode();
  };
  std::vector<evade::sensing::Revolution> out;
  for (int k = 0; k < 10; ++k) {
    auto b = msop(k);
    dec.feed(b.data(), b.size(), t0 + k * 700, &out);
  }
  EXPECT_EQ(counts["msop_before_difop"], 10);
  EXPECT_FALSE(dec.calibrated());
  auto difop = test_difop().encode();
  dec.feed(difop.data(), difop.size(), t0 + 7000, &out);
  EXPECT_TRUE(dec.calibrated());
  for (int k = 10; k < 400; ++k) {
    auto b = msop(k);
    dec.feed(b.data(), b.size(), t0 + k * 700, &out);
  }
  dec.flush(&out);
  EXPECT_EQ(counts["difop_packets"], 1);
  EXPECT_EQ(counts["data_packets"], 390);
  // 2.4 deg per packet: decoding starts at 344 deg (packet 10), cuts near
  // packets 17, 167 and 317, and the rest is flushed.
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].scan.packets.front().size, 1248);
  EXPECT_EQ(out[0].cloud.sensor_model, "rs_helios");
  // Full revolution: 1800 firings (0.2 deg) x 32 channels.
  EXPECT_NEAR(out[1].cloud.n, 1800 * 32, 64);
  EXPECT_NEAR(static_cast<double>(out[2].cloud.utime - out[1].cloud.utime), 1e5, 60.0);
}

TEST(RsHeliosMsop, ImpossibleHeaderTimeIsInvalidNotOverflowed) {
  h::MsopEncoder m;
  m.blocks[0].distance_m[0] = 5.0;
  auto b = m.encode();
  for (int i = 20; i < 26; ++i) b[i] = 0xFF;  // 2^48 - 1 seconds
  h::PacketInfo info;
  std::vector<evade::sensing::LidarReturn> out;
  ASSERT_EQ(h::decode_msop(b.data(), b.size(), calibration(), {}, &out, &info), h::PacketStatus::kOk);
  EXPECT_EQ(info.utc_us, -1);

  std::map<std::string, int64_t> counts;
  evade::sensing::LidarDecoderParams p;
  p.model = evade::sensing::LidarModel::kRsHelios;
  p.time_source = evade::sensing::TimeSource::kSensor;
  p.min_range_m = 0.0;
  p.max_range_m = 200.0;
  p.self_filter = false;
  evade::sensing::LidarDecoder dec(p, [&](const std::string& n, int64_t k) { counts[n] += k; });
  std::vector<evade::sensing::Revolution> revs;
  auto difop = test_difop().encode();
  dec.feed(difop.data(), difop.size(), 1'000'000, &revs);
  dec.feed(b.data(), b.size(), 2'000'000, &revs);
  dec.feed(b.data(), b.size(), -1, &revs);  // a corrupt LIDAR_SCAN receive time
  dec.flush(&revs);
  EXPECT_EQ(counts["timestamp_invalid"], 1);
  EXPECT_EQ(counts["malformed_receive_time"], 1);
  ASSERT_EQ(revs.size(), 1u);
  // Placed by its receive time: 2 s minus the packet's span.
  EXPECT_NEAR(static_cast<double>(revs[0].cloud.utime), 2e6 - (11 * 55.56 + 31 * 1.73), 1.0);
}
