// RoboSense RS-Helios (32 lasers, the paper's robot): MSOP point packets
// and DIFOP device-information packets, both 1248-byte UDP payloads with
// big-endian fields.
//
// MSOP (port 6699):
//   42-byte header: bytes 0..3 = 55 AA 05 5A; bytes 20..29 = UTC time of
//     the first firing (6-byte seconds, 4-byte microseconds);
//   12 blocks of 100 bytes: FF EE, uint16 azimuth in 0.01 deg, 32 channels
//     of {uint16 distance in 2.5 mm units, uint8 intensity};
//   4-byte packet index, 2-byte tail.
// DIFOP (port 7788), one a second:
//   bytes 0..7 = A5 FF 00 5A 11 11 55 55; uint16 rpm at 8; return mode at
//   300 (0x00 dual, 0x04 strongest, 0x05 last, 0x06 nearest);
//   32 vertical then 32 horizontal angle calibrations at 468 and 564, each
//   {uint8 sign (0 = positive), uint16 value in 0.01 deg}.
// Without a DIFOP the laser elevations are unknown: nothing is decoded
// before the first one.
//
// Timing: a block (one firing of the 32 channels) lasts 55.56 us; channel
// c fires c * 1.73 us after the block starts. In dual-return mode blocks
// 2k and 2k+1 are the two echoes of one firing.
//
// Geometry (same clockwise azimuth convention as the VLP-16, see vlp16.h):
//   az_c = block azimuth + block gap * t_c / 55.56 us + horizontal_cal[c]
//   x =  r cos(el_c) cos(az_c) + d cos(az0),  y = -r cos(el_c) sin(az_c) - d sin(az0),
//   z =  r sin(el_c)
// where az0 is the azimuth before the horizontal calibration and d = 34.98 mm
// is the offset of the optical centre from the rotation axis.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sensing/lidar_return.h"
#include "sensing/packet_returns.h"

namespace evade::sensing::rs_helios {

inline constexpr size_t kPacketSize = 1248;
inline constexpr int kMsopPort = 6699;
inline constexpr int kDifopPort = 7788;
inline constexpr size_t kHeaderSize = 42;
inline constexpr int kBlocksPerPacket = 12;
inline constexpr size_t kBlockSize = 100;
inline constexpr int kChannels = 32;
inline constexpr std::array<uint8_t, 4> kMsopId = {0x55, 0xAA, 0x05, 0x5A};
inline constexpr std::array<uint8_t, 8> kDifopId = {0xA5, 0xFF, 0x00, 0x5A, 0x11, 0x11, 0x55, 0x55};
inline constexpr size_t kMsopTimestampOffset = 20;
inline constexpr size_t kDifopRpmOffset = 8;
inline constexpr size_t kDifopReturnModeOffset = 300;
inline constexpr size_t kDifopVerticalOffset = 468;
inline constexpr size_t kDifopHorizontalOffset = 564;
inline constexpr double kDistanceUnitM = 0.0025;
inline constexpr double kAzimuthUnitDeg = 0.01;
inline constexpr double kBlockPeriodUs = 55.56;
inline constexpr double kChannelIntervalUs = 1.73;
inline constexpr double kOpticalCentreOffsetM = 0.03498;
inline constexpr double kMaxRangeM = 150.0;  // datasheet range
inline constexpr double kMaxEncodableRangeM = 65535 * kDistanceUnitM;

enum ReturnMode : uint8_t { kDual = 0x00, kStrongest = 0x04, kLast = 0x05, kNearest = 0x06 };

// Time of (block, channel) after the packet's first firing, us (single
// return; in dual mode use block / 2).
inline double firing_offset_us(int block, int channel) { return block * kBlockPeriodUs + channel * kChannelIntervalUs; }

// What a DIFOP packet tells the decoder.
struct Calibration {
  std::array<double, kChannels> vertical_deg{};    // elevation per channel
  std::array<double, kChannels> horizontal_deg{};  // azimuth correction per channel
  std::array<int, kChannels> ring{};               // rank by elevation, 0 = lowest
  uint8_t return_mode = kStrongest;
  int rpm = 0;
  // cos/sin of the angles above, used per point; parse_difop fills them,
  // whoever edits the angles calls update_trig().
  std::array<double, kChannels> cos_vertical{}, sin_vertical{}, cos_horizontal{}, sin_horizontal{};
  void update_trig();
};

enum class PacketStatus {
  kOk,
  kWrongSize,      // not 1248 bytes
  kBadHeader,      // neither MSOP nor DIFOP identifier
  kBadFlag,        // a block without FF EE
  kBadAzimuth,     // azimuth >= 360.00 deg
  kNoCalibration,  // DIFOP with blank (all 00 / FF) calibration, or angles beyond +-90 deg
};
const char* to_string(PacketStatus s);

enum class PacketKind { kMsop, kDifop, kUnknown };
// By size and identifier only.
PacketKind classify(const uint8_t* data, size_t size);

// Parses a DIFOP packet's return mode, rpm and angle calibration.
PacketStatus parse_difop(const uint8_t* data, size_t size, Calibration* out);

struct DecodeOptions {
  double min_range_m = 0.0;
  double max_range_m = kMaxEncodableRangeM;
};

// Header times beyond this (year 2286) are not times.
inline constexpr uint64_t kMaxUtcSeconds = 9'999'999'999ull;

struct PacketInfo : ScreenCounts {  // + the returns dropped (dual duplicates, out of range)
  int64_t utc_us = 0;               // header time of the first firing, us since the epoch; -1 = invalid
  int firings = 0;                  // distinct firings (12 single, 6 dual)
};

// Decodes an MSOP packet with the DIFOP calibration; appends its returns
// (zero distance dropped) to `out` in firing order. A bad packet leaves
// `out` untouched.
PacketStatus decode_msop(const uint8_t* data, size_t size, const Calibration& cal, const DecodeOptions& options,
                         std::vector<LidarReturn>* out, PacketInfo* info);

// ---------------------------------------------------------------- encoders
// For tests and simulation: fill the fields, call encode().
struct MsopEncoder {
  struct Block {
    double azimuth_deg = 0.0;
    double distance_m[kChannels] = {};
    uint8_t intensity[kChannels] = {};
  };
  std::array<Block, kBlocksPerPacket> blocks;
  int64_t utc_us = 0;  // time of the first firing, us since the epoch
  uint32_t index = 0;  // packet counter
  std::array<uint8_t, kPacketSize> encode() const;
};

struct DifopEncoder {
  std::array<double, kChannels> vertical_deg{};
  std::array<double, kChannels> horizontal_deg{};
  uint8_t return_mode = kStrongest;
  uint16_t rpm = 600;
  std::array<uint8_t, kPacketSize> encode() const;
};

}  // namespace evade::sensing::rs_helios
