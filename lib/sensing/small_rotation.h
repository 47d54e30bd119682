// Fast cos/sin for LiDAR azimuths, without calling libm per point.
//
// rotate_by_small_angle: cos and sin of (a + d) from cos a, sin a and a small
// angle d (|d| < 0.1 rad): the interpolated azimuths of one firing differ
// from the block azimuth by under a degree. Taylor series to d^4 (cos) and
// d^5 (sin): error below d^6/720, 1e-9 for d = 0.1 rad, far under the
// sensors' 0.01 deg resolution.
//
// azimuth_cos_sin: cos and sin of an azimuth given in the packets' 0.01 deg
// counts (0..35999), from a 0.1 deg table and one small rotation.
#pragma once

#include <array>
#include <cmath>

namespace evade::sensing {

inline void rotate_by_small_angle(double cos_a, double sin_a, double d, double* cos_out, double* sin_out) {
  const double d2 = d * d;
  const double cos_d = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0));
  const double sin_d = d * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0)));
  *cos_out = cos_a * cos_d - sin_a * sin_d;
  *sin_out = sin_a * cos_d + cos_a * sin_d;
}

namespace detail {
inline constexpr int kTableStepCounts = 10;  // 0.1 deg
inline constexpr int kTableSize = 36000 / kTableStepCounts;
struct AzimuthTable {
  std::array<double, kTableSize> cos_v, sin_v;
  AzimuthTable() {
    for (int i = 0; i < kTableSize; ++i) {
      const double a = i * kTableStepCounts * 0.01 * M_PI / 180.0;
      cos_v[i] = std::cos(a);
      sin_v[i] = std::sin(a);
    }
  }
};
inline const AzimuthTable& azimuth_table() {
  static const AzimuthTable t;
  return t;
}
}  // namespace detail

// count: azimuth in 0.01 deg, 0 <= count < 36000.
inline void azimuth_cos_sin(int count, double* cos_out, double* sin_out) {
  const auto& t = detail::azimuth_table();
  const int i = count / detail::kTableStepCounts;
  const int rem = count - i * detail::kTableStepCounts;
  rotate_by_small_angle(t.cos_v[i], t.sin_v[i], rem * (0.01 * M_PI / 180.0), cos_out, sin_out);
}

}  // namespace evade::sensing
