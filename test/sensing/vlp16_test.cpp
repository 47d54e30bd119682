// VLP-16 packet encoder/decoder: hand-built packets with known geometry.
#include "sensing/vlp16.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace v = evade::sensing::vlp16;

namespace {
constexpr double kDeg = M_PI / 180.0;

v::PacketEncoder constant_azimuth_packet(double azimuth_deg, uint8_t mode) {
  v::PacketEncoder enc;
  enc.return_mode = mode;
  for (auto& b : enc.blocks) b.azimuth_deg = azimuth_deg;
  return enc;
}

std::vector<v::Return> decode_ok(const std::array<uint8_t, v::kPacketSize>& bytes, v::PacketInfo* info = nullptr,
                                 v::DecodeOptions opt = {}) {
  std::vector<v::Return> out;
  EXPECT_EQ(v::decode_packet(bytes.data(), bytes.size(), opt, &out, info), v::PacketStatus::kOk);
  return out;
}
}  // namespace

TEST(Vlp16Table, RingsOrderElevationAndTimingConstants) {
  std::set<int> rings;
  for (int l = 0; l < v::kLasers; ++l) rings.insert(v::kLaserTable[l].ring);
  EXPECT_EQ(rings.size(), 16u);
  for (int r = 1; r < v::kLasers; ++r)
    EXPECT_LT(v::kLaserTable[v::kLaserOfRing[r - 1]].elevation_deg, v::kLaserTable[v::kLaserOfRing[r]].elevation_deg);
  EXPECT_EQ(v::kLaserTable[0].elevation_deg, -15.0);
  EXPECT_EQ(v::kLaserTable[0].ring, 0);
  EXPECT_EQ(v::kLaserTable[15].elevation_deg, 15.0);
  EXPECT_EQ(v::kLaserTable[15].ring, 15);
  EXPECT_EQ(v::kLaserTable[1].ring, 8);  // +1 deg
  EXPECT_DOUBLE_EQ(v::kSequencePeriodUs, 24 * v::kFiringIntervalUs);
  EXPECT_DOUBLE_EQ(v::firing_offset_us(11, 1, 15), 11 * 110.592 + 55.296 + 15 * 2.304);
}

TEST(Vlp16Encoder, ByteLayout) {
  v::PacketEncoder enc = constant_azimuth_packet(123.45, v::kLast);
  enc.blocks[3].distance_m[1][2] = 10.0;  // 5000 counts = 0x1388
  enc.blocks[3].reflectivity[1][2] = 77;
  enc.timestamp_us_past_hour = 0x01020304;
  enc.factory = 0x21;
  auto b = enc.encode();
  EXPECT_EQ(b[0], 0xFF);
  EXPECT_EQ(b[1], 0xEE);
  EXPECT_EQ(b[2] | (b[3] << 8), 12345);
  const size_t r = 3 * 100 + 4 + 3 * (16 + 2);
  EXPECT_EQ(b[r], 0x88);
  EXPECT_EQ(b[r + 1], 0x13);
  EXPECT_EQ(b[r + 2], 77);
  EXPECT_EQ(b[1200], 0x04);
  EXPECT_EQ(b[1203], 0x01);
  EXPECT_EQ(b[1204], 0x38);
  EXPECT_EQ(b[1205], 0x21);
  EXPECT_EQ(v::azimuth_to_count(-0.01), 35999);
  EXPECT_EQ(v::azimuth_to_count(360.0), 0);
  EXPECT_EQ(v::distance_to_count(1e6), 65535);
  EXPECT_EQ(v::distance_to_count(-1.0), 0);
}

// One return per laser at a constant azimuth: x, y, z follow the documented
// convention exactly (azimuth 0 = +x, clockwise seen from above).
class Vlp16PerLaser : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(Vlp16PerLaser, KnownGeometry) {
  const int laser = std::get<0>(GetParam());
  const uint8_t mode = std::get<1>(GetParam()) == 0 ? v::kStrongest : v::kLast;
  for (double az : {0.0, 90.0, 180.0, 270.0, 33.33}) {
    v::PacketEncoder enc = constant_azimuth_packet(az, mode);
    const double range = 7.5 + 0.25 * laser;  // exact in 2 mm units
    enc.blocks[5].distance_m[1][laser] = range;
    enc.blocks[5].reflectivity[1][laser] = static_cast<uint8_t>(10 + laser);
    v::PacketInfo info;
    auto ret = decode_ok(enc.encode(), &info);
    ASSERT_EQ(ret.size(), 1u);
    const auto& L = v::kLaserTable[laser];
    const double el = L.elevation_deg * kDeg;
    EXPECT_NEAR(ret[0].x, range * std::cos(el) * std::cos(az * kDeg), 1e-5);
    EXPECT_NEAR(ret[0].y, -range * std::cos(el) * std::sin(az * kDeg), 1e-5);
    EXPECT_NEAR(ret[0].z, range * std::sin(el) + L.vertical_offset_m, 1e-5);
    EXPECT_EQ(ret[0].ring, L.ring);
    EXPECT_EQ(ret[0].laser, laser);
    EXPECT_EQ(ret[0].intensity, 10 + laser);
    EXPECT_NEAR(ret[0].time_offset_us, 5 * 110.592 + 55.296 + laser * 2.304, 1e-3);
    EXPECT_EQ(info.return_mode, mode);
    EXPECT_EQ(info.firings, 24);
  }
}
INSTANTIATE_TEST_SUITE_P(AllLasersSingleModes, Vlp16PerLaser,
                         ::testing::Combine(::testing::Range(0, 16), ::testing::Values(0, 1)));

TEST(Vlp16Decoder, AzimuthZeroIsForwardNinetyIsRight) {
  v::PacketEncoder enc = constant_azimuth_packet(0.0, v::kStrongest);
  enc.blocks[0].distance_m[0][1] = 10.0;  // laser 1: +1 deg
  auto r = decode_ok(enc.encode(), nullptr, v::DecodeOptions{0.0, 200.0, false});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_GT(r[0].x, 9.9);
  EXPECT_NEAR(r[0].y, 0.0, 1e-6);
  EXPECT_NEAR(r[0].z, 10.0 * std::sin(1.0 * kDeg), 1e-5);
  enc = constant_azimuth_packet(90.0, v::kStrongest);
  enc.blocks[0].distance_m[0][1] = 10.0;
  r = decode_ok(enc.encode(), nullptr, v::DecodeOptions{0.0, 200.0, false});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NEAR(r[0].x, 0.0, 1e-5);
  EXPECT_LT(r[0].y, -9.9);
}

TEST(Vlp16Decoder, AzimuthInterpolatedWithFiringTiming) {
  v::PacketEncoder enc;
  const double gap = 0.40;  // deg per block (about 10 Hz)
  for (int b = 0; b < 12; ++b) {
    enc.blocks[b].azimuth_deg = 359.0 + gap * b;  // wraps through 0
    for (int s = 0; s < 2; ++s)
      for (int l = 0; l < 16; ++l) enc.blocks[b].distance_m[s][l] = 20.0;
  }
  auto r = decode_ok(enc.encode());
  ASSERT_EQ(r.size(), 12u * 32u);
  for (int b = 0; b < 12; ++b)
    for (int s = 0; s < 2; ++s)
      for (int l = 0; l < 16; ++l) {
        const auto& p = r[static_cast<size_t>(b * 32 + s * 16 + l)];
        double expect = 359.0 + gap * b + gap * (s * 55.296 + l * 2.304) / 110.592;
        expect = std::fmod(expect, 360.0);
        EXPECT_NEAR(p.azimuth_deg, expect, 1e-3) << b << " " << s << " " << l;
        const double h = 20.0 * std::cos(v::kLaserTable[l].elevation_deg * kDeg);
        EXPECT_NEAR(p.x, h * std::cos(expect * kDeg), 2e-4);
        EXPECT_NEAR(p.y, -h * std::sin(expect * kDeg), 2e-4);
        EXPECT_NEAR(p.time_offset_us, b * 110.592 + s * 55.296 + l * 2.304, 1e-3);
      }
}

TEST(Vlp16Decoder, DualReturnPairsShareFiringAndDropDuplicates) {
  v::PacketEncoder enc;
  enc.return_mode = v::kDual;
  for (int k = 0; k < 6; ++k) {
    enc.blocks[2 * k].azimuth_deg = 100.0 + 0.4 * k;
    enc.blocks[2 * k + 1].azimuth_deg = 100.0 + 0.4 * k;
    for (int l = 0; l < 16; ++l) {
      enc.blocks[2 * k].distance_m[0][l] = 30.0;  // last return
      enc.blocks[2 * k].reflectivity[0][l] = 5;
      enc.blocks[2 * k + 1].distance_m[0][l] = 12.0;  // strongest, nearer
      enc.blocks[2 * k + 1].reflectivity[0][l] = 200;
      enc.blocks[2 * k].distance_m[1][l] = 8.0;  // single echo: both equal
      enc.blocks[2 * k].reflectivity[1][l] = 50;
      enc.blocks[2 * k + 1].distance_m[1][l] = 8.0;
      enc.blocks[2 * k + 1].reflectivity[1][l] = 50;
    }
  }
  v::PacketInfo info;
  auto r = decode_ok(enc.encode(), &info);
  EXPECT_EQ(info.firings, 12);
  EXPECT_EQ(info.dual_duplicates, 6 * 16);
  // Per pair, in firing order: sequence A's last (16) and strongest (16)
  // echoes, then sequence B's single echo (its duplicate dropped).
  ASSERT_EQ(r.size(), 6u * 48u);
  for (int k = 0; k < 6; ++k) {
    for (int l = 0; l < 16; ++l) {
      const auto& last = r[static_cast<size_t>(k * 48 + l)];
      const auto& strongest = r[static_cast<size_t>(k * 48 + 16 + l)];
      const auto& single = r[static_cast<size_t>(k * 48 + 32 + l)];
      EXPECT_EQ(last.intensity, 5);
      EXPECT_EQ(single.intensity, 50);
      EXPECT_EQ(strongest.intensity, 200);
      EXPECT_FLOAT_EQ(last.azimuth_deg, strongest.azimuth_deg);
      EXPECT_FLOAT_EQ(last.firing_azimuth_deg, strongest.firing_azimuth_deg);
      EXPECT_FLOAT_EQ(last.time_offset_us, strongest.time_offset_us);
      EXPECT_NEAR(last.time_offset_us, k * 110.592 + l * 2.304, 1e-3);
      EXPECT_NEAR(single.time_offset_us, k * 110.592 + 55.296 + l * 2.304, 1e-3);
      const double el = v::kLaserTable[l].elevation_deg * kDeg;
      const double az = (100.0 + 0.4 * k + 0.4 * l * 2.304 / 110.592) * kDeg;
      EXPECT_NEAR(last.x, 30.0 * std::cos(el) * std::cos(az), 3e-4);
      EXPECT_NEAR(strongest.x, 12.0 * std::cos(el) * std::cos(az), 2e-4);
      EXPECT_NEAR(strongest.y, -12.0 * std::cos(el) * std::sin(az), 2e-4);
      EXPECT_NEAR(strongest.z, 12.0 * std::sin(el) + v::kLaserTable[l].vertical_offset_m, 1e-5);
    }
  }
}

TEST(Vlp16Decoder, ZeroDistanceAndRangeLimitsDropped) {
  v::PacketEncoder enc = constant_azimuth_packet(10.0, v::kStrongest);
  enc.blocks[0].distance_m[0][0] = 0.5;
  enc.blocks[0].distance_m[0][1] = 50.0;
  enc.blocks[0].distance_m[0][2] = 120.0;
  v::PacketInfo info;
  auto r = decode_ok(enc.encode(), &info, v::DecodeOptions{1.0, 100.0, true});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].laser, 1);
  EXPECT_EQ(info.out_of_range, 2);
}

TEST(Vlp16Decoder, RejectsMalformedWithoutOutput) {
  v::PacketEncoder enc = constant_azimuth_packet(10.0, v::kStrongest);
  enc.blocks[0].distance_m[0][0] = 5.0;
  auto good = enc.encode();
  std::vector<v::Return> out;
  EXPECT_EQ(v::decode_packet(good.data(), 1205, {}, &out, nullptr), v::PacketStatus::kWrongSize);
  std::vector<uint8_t> longer(good.begin(), good.end());
  longer.push_back(0);
  EXPECT_EQ(v::decode_packet(longer.data(), longer.size(), {}, &out, nullptr), v::PacketStatus::kWrongSize);
  auto bad_flag = good;
  bad_flag[1100] = 0x00;  // block 11 flag
  EXPECT_EQ(v::decode_packet(bad_flag.data(), bad_flag.size(), {}, &out, nullptr), v::PacketStatus::kBadFlag);
  auto bad_az = good;
  bad_az[2] = 0xA0;  // 36000 = 0x8CA0
  bad_az[3] = 0x8C;
  EXPECT_EQ(v::decode_packet(bad_az.data(), bad_az.size(), {}, &out, nullptr), v::PacketStatus::kBadAzimuth);
  auto bad_mode = good;
  bad_mode[1204] = 0x10;
  EXPECT_EQ(v::decode_packet(bad_mode.data(), bad_mode.size(), {}, &out, nullptr), v::PacketStatus::kBadReturnMode);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(v::decode_packet(good.data(), good.size(), {}, &out, nullptr), v::PacketStatus::kOk);
  EXPECT_EQ(out.size(), 1u);
}
