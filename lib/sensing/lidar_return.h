// One decoded LiDAR return, shared by every packet decoder (VLP-16,
// RS-Helios) and consumed by the revolution assembler.
#pragma once

#include <cstdint>

namespace evade::sensing {

struct LidarReturn {
  float x, y, z;             // m, evade sensor frame (x forward, y left, z up)
  float intensity;           // reflectivity 0..255
  float azimuth_deg;         // this laser's interpolated azimuth, [0, 360)
  float firing_azimuth_deg;  // azimuth of the firing (block / sequence) it belongs to:
                             // revolutions are cut between firings, never inside one
  float time_offset_us;      // after the packet's first firing
  uint8_t ring;              // rank by elevation, 0 = lowest
  uint8_t laser;             // channel index within a firing
};

}  // namespace evade::sensing
