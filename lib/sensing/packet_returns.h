// What the VLP-16 and RS-Helios packet decoders (vlp16.h, rs_helios.h)
// share. Both send a block's azimuth in 0.01 deg counts and each return as
// a 16-bit distance count followed by a reflectivity byte; in dual-return
// mode blocks come in pairs, the second echo of a firing in the second
// block. Only the byte order and the distance unit differ.
#pragma once

#include <cstdint>

namespace evade::sensing {

enum class ByteOrder { kLittle, kBig };

template <ByteOrder kOrder>
inline uint16_t read_u16(const uint8_t* p) {
  if constexpr (kOrder == ByteOrder::kLittle) return static_cast<uint16_t>(p[0] | (p[1] << 8));
  return static_cast<uint16_t>((p[0] << 8) | p[1]);
}

// The returns of one packet that the screen dropped.
struct ScreenCounts {
  int dual_duplicates = 0;  // dual-mode second echoes equal to the first, dropped
  int out_of_range = 0;     // non-zero returns outside [min, max] range
};

// Which returns are points: a zero count is no return; a dual-mode second
// echo with the first echo's count and reflectivity is a duplicate; a range
// outside [min_m, max_m] is dropped. The range is count x distance_unit_m,
// as a float.
template <ByteOrder kOrder>
struct ReturnScreen {
  double distance_unit_m;
  float min_m, max_m;

  // r: the return's 3 bytes; first: the same channel's return in the first
  // echo's block when r is a dual-mode second echo, else nullptr. True with
  // *range_m for a point; a duplicate or out-of-range return is counted.
  bool keep(const uint8_t* r, const uint8_t* first, ScreenCounts* counts, float* range_m) const {
    const uint16_t count = read_u16<kOrder>(r);
    if (count == 0) return false;
    if (first && read_u16<kOrder>(first) == count && first[2] == r[2]) {
      ++counts->dual_duplicates;
      return false;
    }
    const float range = static_cast<float>(count * distance_unit_m);
    if (range < min_m || range > max_m) {
      ++counts->out_of_range;
      return false;
    }
    *range_m = range;
    return true;
  }
};

// Azimuths in 0.01 deg counts, 0..35999.
inline constexpr int kAzimuthCounts = 36000;

// Signed smallest difference b - a in 0.01 deg counts, in (-18000, 18000].
inline int azimuth_diff(int a, int b) {
  int d = (b - a) % kAzimuthCounts;
  if (d > kAzimuthCounts / 2) d -= kAzimuthCounts;
  if (d <= -kAzimuthCounts / 2) d += kAzimuthCounts;
  return d;
}

// Azimuth change over one block time per firing column (deg), from the
// block azimuths (counts; a column is every `step`-th block: 2 in dual
// mode). Gaps beyond 5 deg are not rotation (20 Hz, the fastest setting of
// either sensor, turns under 1 deg per block): such a gap is the previous
// column's; the last column reuses the one before it (the manuals' rule);
// an implausible first gap borrows the next plausible one.
inline void column_gaps(const int* azimuth, int columns, int step, double* gap_deg) {
  constexpr double kMaxBlockGapDeg = 5.0;
  constexpr double kAzimuthUnitDeg = 0.01;
  for (int c = 0; c + 1 < columns; ++c) {
    const double g = azimuth_diff(azimuth[c * step], azimuth[(c + 1) * step]) * kAzimuthUnitDeg;
    gap_deg[c] = (g >= 0.0 && g <= kMaxBlockGapDeg) ? g : (c > 0 ? gap_deg[c - 1] : 0.0);
  }
  if (columns > 1) gap_deg[columns - 1] = gap_deg[columns - 2];
  if (columns > 1 && gap_deg[0] == 0.0)
    for (int c = 1; c < columns; ++c)
      if (gap_deg[c] > 0.0) {
        gap_deg[0] = gap_deg[c];
        break;
      }
}

}  // namespace evade::sensing
