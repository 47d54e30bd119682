#include "sensing/vlp16.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "sensing/small_rotation.h"

namespace evade::sensing::vlp16 {

namespace {
constexpr double kDegToRad = M_PI / 180.0;

inline uint16_t read_u16le(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
inline uint32_t read_u32le(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}
inline void write_u16le(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFF);
  p[1] = static_cast<uint8_t>(v >> 8);
}
inline void write_u32le(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}

// Elevation and vertical offset per laser id, from the VLP-16 user manual's
// laser table; ring = rank by elevation.
constexpr double kElevationDeg[kLasers] = {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15};
constexpr double kVerticalOffsetMm[kLasers] = {11.2, -0.7, 9.7, -2.2, 8.1, -3.7, 6.6, -5.1,
                                               5.1,  -6.6, 3.7, -8.1, 2.2, -9.7, 0.7, -11.2};

std::array<Laser, kLasers> make_laser_table() {
  std::array<Laser, kLasers> t{};
  for (int i = 0; i < kLasers; ++i) {
    int rank = 0;
    for (int j = 0; j < kLasers; ++j) rank += kElevationDeg[j] < kElevationDeg[i];
    t[i] = Laser{kElevationDeg[i], kVerticalOffsetMm[i] * 1e-3, rank};
  }
  return t;
}

struct Trig {
  float cos_el[kLasers], sin_el[kLasers], dz[kLasers];
};
const Trig& trig() {
  static const Trig t = [] {
    Trig r{};
    for (int i = 0; i < kLasers; ++i) {
      r.cos_el[i] = static_cast<float>(std::cos(kElevationDeg[i] * kDegToRad));
      r.sin_el[i] = static_cast<float>(std::sin(kElevationDeg[i] * kDegToRad));
      r.dz[i] = static_cast<float>(kVerticalOffsetMm[i] * 1e-3);
    }
    return r;
  }();
  return t;
}

}  // namespace

const std::array<Laser, kLasers> kLaserTable = make_laser_table();
const std::array<int, kLasers> kLaserOfRing = [] {
  std::array<int, kLasers> r{};
  for (int i = 0; i < kLasers; ++i) r[static_cast<size_t>(kLaserTable[i].ring)] = i;
  return r;
}();

uint16_t distance_to_count(double distance_m) {
  if (!(distance_m > 0.0)) return 0;
  double c = std::round(distance_m / kDistanceUnitM);
  return static_cast<uint16_t>(std::min(c, 65535.0));
}

uint16_t azimuth_to_count(double azimuth_deg) {
  if (!std::isfinite(azimuth_deg)) return 0;
  long c = std::lround(azimuth_deg / kAzimuthUnitDeg) % kAzimuthCount;
  if (c < 0) c += kAzimuthCount;
  return static_cast<uint16_t>(c);
}

void PacketEncoder::encode_into(uint8_t* out) const {
  for (int b = 0; b < kBlocksPerPacket; ++b) {
    uint8_t* p = out + b * kBlockSize;
    write_u16le(p, kBlockFlag);
    write_u16le(p + 2, azimuth_to_count(blocks[b].azimuth_deg));
    for (int s = 0; s < kSequencesPerBlock; ++s)
      for (int l = 0; l < kLasers; ++l) {
        uint8_t* r = p + 4 + 3 * (s * kLasers + l);
        write_u16le(r, distance_to_count(blocks[b].distance_m[s][l]));
        r[2] = blocks[b].reflectivity[s][l];
      }
  }
  write_u32le(out + kTimestampOffset, timestamp_us_past_hour % kMicrosPerHour);
  out[kReturnModeOffset] = return_mode;
  out[kFactoryOffset] = factory;
}

std::array<uint8_t, kPacketSize> PacketEncoder::encode() const {
  std::array<uint8_t, kPacketSize> out{};
  encode_into(out.data());
  return out;
}

const char* to_string(PacketStatus s) {
  switch (s) {
    case PacketStatus::kOk:
      return "ok";
    case PacketStatus::kWrongSize:
      return "wrong_size";
    case PacketStatus::kBadFlag:
      return "bad_flag";
    case PacketStatus::kBadAzimuth:
      return "bad_azimuth";
    case PacketStatus::kBadReturnMode:
      return "bad_return_mode";
  }
  return "unknown";
}

namespace {

// Checks every block's flag and azimuth; azimuth[b] in 0.01 deg counts.
PacketStatus read_azimuths(const uint8_t* data, int* azimuth) {
  for (int b = 0; b < kBlocksPerPacket; ++b) {
    const uint8_t* p = data + b * kBlockSize;
    if (read_u16le(p) != kBlockFlag) return PacketStatus::kBadFlag;
    azimuth[b] = read_u16le(p + 2);
    if (azimuth[b] >= kAzimuthCount) return PacketStatus::kBadAzimuth;
  }
  return PacketStatus::kOk;
}

// One firing sequence of one column: where it points and when.
struct Firing {
  int sequence;
  double block_az_deg, gap_deg, gap_rad, cos_block, sin_block;
  double seq_offset_us, firing_az_deg;
};

// The 16 returns of one echo of a firing; block is the echo's block, other
// the first echo's block in dual mode (nullptr otherwise).
void decode_echo(const uint8_t* block, const uint8_t* other, const Firing& f, const DecodeOptions& options,
                 std::vector<Return>* out, PacketInfo& pi) {
  const Trig& t = trig();
  const ReturnScreen<ByteOrder::kLittle> screen{kDistanceUnitM, static_cast<float>(options.min_range_m),
                                                static_cast<float>(options.max_range_m)};
  const int s = f.sequence;
  for (int l = 0; l < kLasers; ++l) {
    const uint8_t* r = block + 4 + 3 * (s * kLasers + l);
    float range;
    if (!screen.keep(r, other ? other + 4 + 3 * (s * kLasers + l) : nullptr, &pi, &range)) continue;
    // Azimuth interpolated by firing time within the block.
    const double frac = (s * kSequencePeriodUs + l * kFiringIntervalUs) / kBlockPeriodUs;
    double az = f.block_az_deg + f.gap_deg * frac;
    if (az >= 360.0) az -= 360.0;
    double ca, sa;
    rotate_by_small_angle(f.cos_block, f.sin_block, f.gap_rad * frac, &ca, &sa);
    const float horizontal = range * t.cos_el[l];
    Return ret;
    ret.x = horizontal * static_cast<float>(ca);
    ret.y = -horizontal * static_cast<float>(sa);
    ret.z = range * t.sin_el[l] + (options.vertical_offset_correction ? t.dz[l] : 0.0f);
    ret.intensity = r[2];
    ret.azimuth_deg = static_cast<float>(az);
    ret.firing_azimuth_deg = static_cast<float>(f.firing_az_deg);
    ret.time_offset_us = static_cast<float>(f.seq_offset_us + l * kFiringIntervalUs);
    ret.ring = static_cast<uint8_t>(kLaserTable[static_cast<size_t>(l)].ring);
    ret.laser = static_cast<uint8_t>(l);
    out->push_back(ret);
  }
}

}  // namespace

PacketStatus decode_packet(const uint8_t* data, size_t size, const DecodeOptions& options, std::vector<Return>* out,
                           PacketInfo* info) {
  if (size != kPacketSize || data == nullptr) return PacketStatus::kWrongSize;
  int azimuth[kBlocksPerPacket];
  if (PacketStatus st = read_azimuths(data, azimuth); st != PacketStatus::kOk) return st;
  const uint8_t mode = data[kReturnModeOffset];
  if (mode != kStrongest && mode != kLast && mode != kDual) return PacketStatus::kBadReturnMode;
  const bool dual = mode == kDual;

  PacketInfo local;
  PacketInfo& pi = info ? *info : local;
  pi = PacketInfo{};
  pi.timestamp_us_past_hour = read_u32le(data + kTimestampOffset);
  pi.return_mode = mode;
  pi.factory = data[kFactoryOffset];

  // Distinct firing times: every block (single) or every block pair (dual).
  const int step = dual ? 2 : 1;
  const int columns = kBlocksPerPacket / step;
  pi.firings = columns * kSequencesPerBlock;
  double gap_deg[kBlocksPerPacket] = {};
  column_gaps(azimuth, columns, step, gap_deg);

  // Firing order: column (block, or block pair in dual mode), sequence,
  // echo (dual: block 2k then 2k+1), laser; the two echoes of a firing stay
  // together, so a revolution cut never separates them.
  for (int column = 0; column < columns; ++column) {
    Firing f{};
    f.block_az_deg = azimuth[column * step] * kAzimuthUnitDeg;
    azimuth_cos_sin(azimuth[column * step], &f.cos_block, &f.sin_block);
    f.gap_deg = gap_deg[column];
    f.gap_rad = gap_deg[column] * kDegToRad;
    for (int s = 0; s < kSequencesPerBlock; ++s) {
      f.sequence = s;
      f.seq_offset_us = column * kBlockPeriodUs + s * kSequencePeriodUs;
      f.firing_az_deg = f.block_az_deg + f.gap_deg * s * kSequencePeriodUs / kBlockPeriodUs;
      if (f.firing_az_deg >= 360.0) f.firing_az_deg -= 360.0;
      for (int echo = 0; echo < step; ++echo) {
        const int b = column * step + echo;
        const uint8_t* other = echo == 1 ? data + (b - 1) * kBlockSize : nullptr;  // dual: the first echo
        decode_echo(data + b * kBlockSize, other, f, options, out, pi);
      }
    }
  }
  return PacketStatus::kOk;
}

}  // namespace evade::sensing::vlp16
