// A synthetic spinning VLP-16 for tests: consecutive data packets of a
// sensor turning at `rate_hz`, every laser hitting a cylinder of radius
// `range_m` around it.
#pragma once

#include <cmath>
#include <vector>

#include "sensing/vlp16.h"

namespace evade::sensing::testing {

struct SyntheticPacket {
  std::array<uint8_t, vlp16::kPacketSize> bytes;
  int64_t sensor_utime;  // absolute time of the packet's first firing
};

struct SyntheticVlp16 {
  double rate_hz = 10.0;
  double start_azimuth_deg = 300.0;
  double range_m = 10.0;
  int64_t start_utime = 3'600'000'000LL * 500'000 + 1'234'567;  // some hour + 1.23 s
  uint8_t return_mode = vlp16::kStrongest;

  double degrees_per_block() const { return 360.0 * rate_hz * vlp16::kBlockPeriodUs * 1e-6; }
  double packet_period_us() const { return vlp16::kBlockPeriodUs * (return_mode == vlp16::kDual ? 6 : 12); }

  SyntheticPacket packet(int k) const {
    vlp16::PacketEncoder enc;
    enc.return_mode = return_mode;
    const bool dual = return_mode == vlp16::kDual;
    const int columns = dual ? 6 : 12;
    for (int b = 0; b < 12; ++b) {
      const int column = dual ? b / 2 : b;
      const double az = start_azimuth_deg + (static_cast<double>(k) * columns + column) * degrees_per_block();
      enc.blocks[b].azimuth_deg = std::fmod(az, 360.0);
      for (int s = 0; s < 2; ++s)
        for (int l = 0; l < 16; ++l) {
          const double el = vlp16::kLaserTable[l].elevation_deg * M_PI / 180.0;
          enc.blocks[b].distance_m[s][l] = range_m / std::cos(el);
          enc.blocks[b].reflectivity[s][l] = static_cast<uint8_t>(dual && b % 2 == 1 ? 200 : 20 + l);
          if (dual && b % 2 == 1) enc.blocks[b].distance_m[s][l] += 1.0;  // a distinct strongest echo
        }
    }
    const int64_t t = start_utime + std::llround(k * packet_period_us());
    enc.timestamp_us_past_hour = static_cast<uint32_t>(t % vlp16::kMicrosPerHour);
    return SyntheticPacket{enc.encode(), t};
  }
};

}  // namespace evade::sensing::testing
