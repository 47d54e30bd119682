#include "sensing/rs_helios.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "sensing/small_rotation.h"

namespace evade::sensing::rs_helios {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
constexpr int kAzimuthCount = 36000;
constexpr double kMaxCalibrationDeg = 90.0;
constexpr size_t kMsopIndexOffset = kHeaderSize + kBlocksPerPacket * kBlockSize;

inline uint16_t read_u16be(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }
inline void write_u16be(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v & 0xFF);
}
inline uint64_t read_be(const uint8_t* p, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v = (v << 8) | p[i];
  return v;
}
inline void write_be(uint8_t* p, uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) {
    p[i] = static_cast<uint8_t>(v & 0xFF);
    v >>= 8;
  }
}
uint16_t distance_count(double m) {
  if (!(m > 0.0)) return 0;
  return static_cast<uint16_t>(std::min(std::round(m / kDistanceUnitM), 65535.0));
}
uint16_t azimuth_count(double deg) {
  if (!std::isfinite(deg)) return 0;
  long c = std::lround(deg / kAzimuthUnitDeg) % kAzimuthCount;
  if (c < 0) c += kAzimuthCount;
  return static_cast<uint16_t>(c);
}
// {sign, uint16 0.01 deg}: sign byte 0 = positive.
double read_angle(const uint8_t* p) {
  double v = read_u16be(p + 1) * kAzimuthUnitDeg;
  return p[0] == 0 ? v : -v;
}
void write_angle(uint8_t* p, double deg) {
  p[0] = deg < 0.0 ? 1 : 0;
  write_u16be(p + 1, static_cast<uint16_t>(std::min(std::lround(std::fabs(deg) / kAzimuthUnitDeg), 65535L)));
}
}  // namespace

void Calibration::update_trig() {
  for (int c = 0; c < kChannels; ++c) {
    cos_vertical[c] = std::cos(vertical_deg[c] * kDegToRad);
    sin_vertical[c] = std::sin(vertical_deg[c] * kDegToRad);
    cos_horizontal[c] = std::cos(horizontal_deg[c] * kDegToRad);
    sin_horizontal[c] = std::sin(horizontal_deg[c] * kDegToRad);
  }
}

const char* to_string(PacketStatus s) {
  switch (s) {
    case PacketStatus::kOk:
      return "ok";
    case PacketStatus::kWrongSize:
      return "wrong_size";
    case PacketStatus::kBadHeader:
      return "bad_header";
    case PacketStatus::kBadFlag:
      return "bad_flag";
    case PacketStatus::kBadAzimuth:
      return "bad_azimuth";
    case PacketStatus::kNoCalibration:
      return "no_calibration";
  }
  return "unknown";
}

PacketKind classify(const uint8_t* data, size_t size) {
  if (data == nullptr || size != kPacketSize) return PacketKind::kUnknown;
  if (std::equal(kMsopId.begin(), kMsopId.end(), data)) return PacketKind::kMsop;
  if (std::equal(kDifopId.begin(), kDifopId.end(), data)) return PacketKind::kDifop;
  return PacketKind::kUnknown;
}

PacketStatus parse_difop(const uint8_t* data, size_t size, Calibration* out) {
  if (data == nullptr || size != kPacketSize) return PacketStatus::kWrongSize;
  if (classify(data, size) != PacketKind::kDifop) return PacketStatus::kBadHeader;
  const uint8_t* vert = data + kDifopVerticalOffset;
  // An unprogrammed calibration area reads 00 or FF.
  bool blank = true;
  for (size_t i = 0; i < 3 * kChannels && blank; ++i) blank = (vert[i] == 0x00 || vert[i] == 0xFF);
  if (blank) return PacketStatus::kNoCalibration;
  Calibration cal;
  for (int c = 0; c < kChannels; ++c) {
    cal.vertical_deg[c] = read_angle(vert + 3 * c);
    cal.horizontal_deg[c] = read_angle(data + kDifopHorizontalOffset + 3 * c);
    if (std::fabs(cal.vertical_deg[c]) > kMaxCalibrationDeg || std::fabs(cal.horizontal_deg[c]) > kMaxCalibrationDeg)
      return PacketStatus::kNoCalibration;
  }
  std::array<int, kChannels> order;
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cal.vertical_deg[a] < cal.vertical_deg[b]; });
  for (int r = 0; r < kChannels; ++r) cal.ring[order[r]] = r;
  cal.update_trig();
  cal.return_mode = data[kDifopReturnModeOffset];
  cal.rpm = read_u16be(data + kDifopRpmOffset);
  *out = cal;
  return PacketStatus::kOk;
}

namespace {

// Checks every block's flag and azimuth; azimuth[b] in 0.01 deg counts.
PacketStatus read_azimuths(const uint8_t* data, int* azimuth) {
  for (int b = 0; b < kBlocksPerPacket; ++b) {
    const uint8_t* p = data + kHeaderSize + b * kBlockSize;
    if (p[0] != 0xFF || p[1] != 0xEE) return PacketStatus::kBadFlag;
    azimuth[b] = read_u16be(p + 2);
    if (azimuth[b] >= kAzimuthCount) return PacketStatus::kBadAzimuth;
  }
  return PacketStatus::kOk;
}

// The packet's UTC time (us), or -1: a 6-byte second count could overflow
// microseconds in 64 bits; anything past kMaxUtcSeconds or with micros >=
// 1e6 is not a time.
int64_t read_utc_us(const uint8_t* data) {
  const uint8_t* ts = data + kMsopTimestampOffset;
  const uint64_t seconds = read_be(ts, 6), micros = read_be(ts + 6, 4);
  return (seconds <= kMaxUtcSeconds && micros < 1'000'000u) ? static_cast<int64_t>(seconds * 1'000'000ull + micros)
                                                            : -1;
}

// One block's column: where it points and when.
struct Column {
  int index;
  double block_az_deg, gap_deg, gap_rad, cos_block, sin_block;
};

// The returns of one block; other is the first echo's block in dual mode
// (nullptr otherwise).
void decode_block(const uint8_t* p, const uint8_t* other, const Column& col, const Calibration& cal,
                  const DecodeOptions& options, std::vector<LidarReturn>* out, PacketInfo& pi) {
  const ReturnScreen<ByteOrder::kBig> screen{kDistanceUnitM, static_cast<float>(options.min_range_m),
                                             static_cast<float>(options.max_range_m)};
  for (int c = 0; c < kChannels; ++c) {
    const uint8_t* r = p + 4 + 3 * c;
    float range;
    if (!screen.keep(r, other ? other + 4 + 3 * c : nullptr, &pi, &range)) continue;
    // az0: block azimuth interpolated by the channel's firing time;
    // az = az0 + the channel's horizontal calibration.
    const double t_us = c * kChannelIntervalUs;
    const double frac = t_us / kBlockPeriodUs;
    double cos_az0, sin_az0;
    rotate_by_small_angle(col.cos_block, col.sin_block, col.gap_rad * frac, &cos_az0, &sin_az0);
    const double cos_az = cos_az0 * cal.cos_horizontal[c] - sin_az0 * cal.sin_horizontal[c];
    const double sin_az = sin_az0 * cal.cos_horizontal[c] + cos_az0 * cal.sin_horizontal[c];
    const double horizontal = range * cal.cos_vertical[c];
    LidarReturn ret;
    ret.x = static_cast<float>(horizontal * cos_az + kOpticalCentreOffsetM * cos_az0);
    ret.y = static_cast<float>(-horizontal * sin_az - kOpticalCentreOffsetM * sin_az0);
    ret.z = static_cast<float>(range * cal.sin_vertical[c]);
    ret.intensity = r[2];
    double az = col.block_az_deg + col.gap_deg * frac + cal.horizontal_deg[c];
    if (az >= 360.0) az -= 360.0;
    if (az < 0.0) az += 360.0;
    ret.azimuth_deg = static_cast<float>(az);
    ret.firing_azimuth_deg = static_cast<float>(col.block_az_deg);
    ret.time_offset_us = static_cast<float>(col.index * kBlockPeriodUs + t_us);
    ret.ring = static_cast<uint8_t>(cal.ring[c]);
    ret.laser = static_cast<uint8_t>(c);
    out->push_back(ret);
  }
}

}  // namespace

PacketStatus decode_msop(const uint8_t* data, size_t size, const Calibration& cal, const DecodeOptions& options,
                         std::vector<LidarReturn>* out, PacketInfo* info) {
  if (data == nullptr || size != kPacketSize) return PacketStatus::kWrongSize;
  if (classify(data, size) != PacketKind::kMsop) return PacketStatus::kBadHeader;
  int azimuth[kBlocksPerPacket];
  if (PacketStatus st = read_azimuths(data, azimuth); st != PacketStatus::kOk) return st;
  PacketInfo local;
  PacketInfo& pi = info ? *info : local;
  pi = PacketInfo{};
  pi.utc_us = read_utc_us(data);

  const bool dual = cal.return_mode == kDual;
  const int step = dual ? 2 : 1;
  const int columns = kBlocksPerPacket / step;
  pi.firings = columns;
  double gap_deg[kBlocksPerPacket] = {};
  column_gaps(azimuth, columns, step, gap_deg);
  for (int b = 0; b < kBlocksPerPacket; ++b) {
    Column col{};
    col.index = b / step;
    const uint8_t* p = data + kHeaderSize + b * kBlockSize;
    const uint8_t* other = (dual && b % 2 == 1) ? data + kHeaderSize + (b - 1) * kBlockSize : nullptr;
    col.block_az_deg = azimuth[col.index * step] * kAzimuthUnitDeg;
    azimuth_cos_sin(azimuth[col.index * step], &col.cos_block, &col.sin_block);
    col.gap_deg = gap_deg[col.index];
    col.gap_rad = gap_deg[col.index] * kDegToRad;
    decode_block(p, other, col, cal, options, out, pi);
  }
  return PacketStatus::kOk;
}

std::array<uint8_t, kPacketSize> MsopEncoder::encode() const {
  std::array<uint8_t, kPacketSize> out{};
  std::copy(kMsopId.begin(), kMsopId.end(), out.begin());
  const int64_t t = std::max<int64_t>(utc_us, 0);
  write_be(out.data() + kMsopTimestampOffset, static_cast<uint64_t>(t / 1'000'000), 6);
  write_be(out.data() + kMsopTimestampOffset + 6, static_cast<uint64_t>(t % 1'000'000), 4);
  for (int b = 0; b < kBlocksPerPacket; ++b) {
    uint8_t* p = out.data() + kHeaderSize + b * kBlockSize;
    p[0] = 0xFF;
    p[1] = 0xEE;
    write_u16be(p + 2, azimuth_count(blocks[b].azimuth_deg));
    for (int c = 0; c < kChannels; ++c) {
      write_u16be(p + 4 + 3 * c, distance_count(blocks[b].distance_m[c]));
      p[4 + 3 * c + 2] = blocks[b].intensity[c];
    }
  }
  write_be(out.data() + kMsopIndexOffset, index, 4);
  out[kPacketSize - 2] = 0x00;
  out[kPacketSize - 1] = 0xFF;
  return out;
}

std::array<uint8_t, kPacketSize> DifopEncoder::encode() const {
  std::array<uint8_t, kPacketSize> out{};
  std::copy(kDifopId.begin(), kDifopId.end(), out.begin());
  write_u16be(out.data() + kDifopRpmOffset, rpm);
  out[kDifopReturnModeOffset] = return_mode;
  for (int c = 0; c < kChannels; ++c) {
    write_angle(out.data() + kDifopVerticalOffset + 3 * c, vertical_deg[c]);
    write_angle(out.data() + kDifopHorizontalOffset + 3 * c, horizontal_deg[c]);
  }
  out[kPacketSize - 2] = 0x0F;
  out[kPacketSize - 1] = 0xF0;
  return out;
}

}  // namespace evade::sensing::rs_helios
