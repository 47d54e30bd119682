// Velodyne VLP-16 ("Puck") data packets: layout, laser table, firing timing,
// an encoder (for the simulator and tests) and a stateless packet decoder.
//
// Packet (the 1206-byte UDP payload, port 2368, all fields little-endian):
//   12 data blocks of 100 bytes:
//     uint16 flag 0xFFEE (bytes FF EE), uint16 azimuth in 0.01 deg,
//     32 returns of {uint16 distance in 2 mm units, uint8 reflectivity}:
//     returns 0..15 are firing sequence A (lasers 0..15), returns 16..31
//     are firing sequence B (lasers 0..15), fired 55.296 us later.
//   uint32 timestamp: microseconds past the hour of the first firing of
//     the first block;
//   uint8 return mode: 0x37 strongest, 0x38 last, 0x39 dual;
//   uint8 factory byte (product id): 0x22 for a VLP-16 (reported, not trusted:
//     the configured model decides how a packet is decoded).
//
// Timing: the 16 lasers of a sequence fire 2.304 us apart; a sequence lasts
// 55.296 us (16 firings + recharge); a block holds two sequences (110.592 us).
// In dual-return mode, blocks come in pairs (2k: last, 2k+1: strongest or,
// when that equals the last, second strongest) that share one azimuth and
// one firing time, so a dual packet covers 6 block times instead of 12.
// A second echo equal to the first (a single target) is dropped.
//
// Azimuth of a firing: the block's azimuth plus the block-to-block azimuth
// change times (firing time within the block / 110.592 us), the change
// being taken to the next block (dual: next pair; the last block reuses the
// previous change; changes above 5 deg, impossible at 20 Hz, count as none).
// A simulator emitting packets for a sensor turning at w deg/us fires laser l
// of sequence s of block b at block_az + w * (s * 55.296 + l * 2.304).
//
// Azimuth: Velodyne measures azimuth clockwise seen from above, 0 deg
// along the sensor's forward (+Y in Velodyne's manual, where
// X = r cos(el) sin(az), Y = r cos(el) cos(az), Z = r sin(el)).
// evade's sensor frame is x forward, y left, z up, so
//   x = r cos(el) cos(az),  y = -r cos(el) sin(az),  z = r sin(el) + dz(laser)
// i.e. a return at azimuth 0 lies on +x, at azimuth 90 deg on -y (right).
// dz(laser) is the manual's per-laser vertical offset of the beam origin
// (at most 11.2 mm), applied when `vertical_offset_correction` is on. A
// simulator that wants exact agreement casts laser i's ray from (0, 0, dz(i)).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sensing/lidar_return.h"
#include "sensing/packet_returns.h"

namespace evade::sensing::vlp16 {

inline constexpr size_t kPacketSize = 1206;  // UDP payload of a data packet
inline constexpr int kDataPort = 2368;
inline constexpr int kPositionPort = 8308;
inline constexpr int kBlocksPerPacket = 12;
inline constexpr size_t kBlockSize = 100;
inline constexpr int kReturnsPerBlock = 32;
inline constexpr int kLasers = 16;
inline constexpr int kSequencesPerBlock = 2;
inline constexpr uint16_t kBlockFlag = 0xEEFF;  // bytes FF EE read little-endian
inline constexpr size_t kTimestampOffset = 1200;
inline constexpr size_t kReturnModeOffset = 1204;
inline constexpr size_t kFactoryOffset = 1205;
inline constexpr double kDistanceUnitM = 0.002;
inline constexpr double kAzimuthUnitDeg = 0.01;
inline constexpr uint16_t kAzimuthCount = 36000;     // azimuth values are 0..35999
inline constexpr double kFiringIntervalUs = 2.304;   // between lasers of a sequence
inline constexpr double kSequencePeriodUs = 55.296;  // between sequences
inline constexpr double kBlockPeriodUs = 2.0 * kSequencePeriodUs;
inline constexpr double kMaxRangeM = 100.0;  // datasheet range
inline constexpr double kMaxEncodableRangeM = 65535 * kDistanceUnitM;
inline constexpr uint32_t kMicrosPerHour = 3'600'000'000u;

enum ReturnMode : uint8_t { kStrongest = 0x37, kLast = 0x38, kDual = 0x39 };
inline constexpr uint8_t kFactoryVlp16 = 0x22;

// Laser table, indexed by laser id (the order within a firing sequence).
struct Laser {
  double elevation_deg;
  double vertical_offset_m;  // dz of the beam origin (manual's "vertical correction")
  int ring;                  // rank by elevation, 0 = lowest
};
// -15, 1, -13, 3, ... : the VLP-16 interleaves downward and upward lasers.
extern const std::array<Laser, kLasers> kLaserTable;
// Laser id of each ring (inverse of Laser::ring).
extern const std::array<int, kLasers> kLaserOfRing;

// Time of (block, sequence, laser) after the packet's first firing, us,
// for a single-return packet; in dual mode use block / 2 as the block.
inline double firing_offset_us(int block, int sequence, int laser) {
  return block * kBlockPeriodUs + sequence * kSequencePeriodUs + laser * kFiringIntervalUs;
}

// ---------------------------------------------------------------- encoder
// Builds a 1206-byte data packet. Fill `blocks`, then call encode().
// A block is one azimuth and two firing sequences of 16 lasers; distances
// in metres (0 = no return; clamped to what 16 bits of 2 mm hold),
// reflectivity 0..255. In dual mode fill blocks 2k (last) and 2k+1
// (strongest) with the same azimuth.
//
//   vlp16::PacketEncoder enc;
//   enc.timestamp_us_past_hour = 1234;
//   for (int b = 0; b < 12; ++b) {
//     enc.blocks[b].azimuth_deg = 10.0 + 0.4 * b;
//     enc.blocks[b].distance_m[0][laser] = 5.0;   // sequence A
//     enc.blocks[b].distance_m[1][laser] = 5.0;   // sequence B
//   }
//   std::array<uint8_t, vlp16::kPacketSize> bytes = enc.encode();
struct PacketEncoder {
  struct Block {
    double azimuth_deg = 0.0;  // of sequence A; wrapped into [0, 360)
    double distance_m[kSequencesPerBlock][kLasers] = {};
    uint8_t reflectivity[kSequencesPerBlock][kLasers] = {};
  };
  std::array<Block, kBlocksPerPacket> blocks;
  uint32_t timestamp_us_past_hour = 0;  // of the first firing; reduced mod one hour
  uint8_t return_mode = kStrongest;
  uint8_t factory = kFactoryVlp16;

  std::array<uint8_t, kPacketSize> encode() const;
  void encode_into(uint8_t* out) const;  // out holds kPacketSize bytes
};

// Distance in metres as the 16-bit count the sensor sends (rounded).
uint16_t distance_to_count(double distance_m);
// Azimuth in degrees as the 0.01-degree count the sensor sends (wrapped, rounded).
uint16_t azimuth_to_count(double azimuth_deg);

// ---------------------------------------------------------------- decoder
using Return = LidarReturn;

enum class PacketStatus {
  kOk,
  kWrongSize,      // not 1206 bytes (e.g. the truncated position packets)
  kBadFlag,        // a block without 0xFFEE
  kBadAzimuth,     // azimuth >= 360.00 deg
  kBadReturnMode,  // neither 0x37, 0x38 nor 0x39
};
const char* to_string(PacketStatus s);

struct DecodeOptions {
  double min_range_m = 0.0;  // returns closer are dropped (0 = keep all but zero)
  double max_range_m = kMaxEncodableRangeM;
  bool vertical_offset_correction = true;
};

struct PacketInfo : ScreenCounts {  // + the returns dropped (dual duplicates, out of range)
  uint32_t timestamp_us_past_hour = 0;
  uint8_t return_mode = 0;
  uint8_t factory = 0;
  int firings = 0;  // distinct firing sequences (24 single, 12 dual)
};

// Decodes one data packet and appends its returns (zero distance dropped)
// to `out`, in firing order (dual mode: for each firing sequence, block 2k's
// echoes then block 2k+1's). Validates the whole packet before appending
// anything, so a bad packet leaves `out` untouched.
PacketStatus decode_packet(const uint8_t* data, size_t size, const DecodeOptions& options, std::vector<Return>* out,
                           PacketInfo* info);

}  // namespace evade::sensing::vlp16
