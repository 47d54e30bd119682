// A ray-cast VLP-16 revolution over a simple world (ground plane z = 0,
// vertical cylinders, yawed boxes), for tests and benchmarks with known
// answers. Points come out in the sensor frame with per-point time offsets,
// exactly as the lidar_driver publishes them.
#pragma once

#include <cstdint>
#include <vector>

#include "mapping/elevation_map.h"
#include "mapping/pose_buffer.h"

namespace evade::mapping {

struct SynthCylinder {
  double x, y, radius, height;
};
struct SynthBox {
  double x, y, yaw, length, width, height;  // length along its yaw
};
struct SynthWorld {
  std::vector<SynthCylinder> cylinders;
  std::vector<SynthBox> boxes;
  double ground_slope_x = 0.0;  // ground z = slope * (x - ramp_start_x) for x > ramp_start_x, else 0
  double ramp_start_x = 0.0;
};

struct SynthScanOptions {
  Pose2 robot_start;            // robot pose at the first firing
  double v = 0.0, omega = 0.0;  // robot motion during the sweep
  double mount_height_m = 0.5;
  int azimuth_steps = 1800;  // 0.2 deg at 10 Hz, 16 rings -> 28,800 points
  int64_t sweep_us = 100000;
  double range_noise_std_m = 0.0;
  uint32_t seed = 1;
};

struct SynthCloud {
  std::vector<float> x, y, z;
  std::vector<int32_t> time_offset;
};

SynthCloud synth_vlp16(const SynthWorld& world, const SynthScanOptions& opt);

// The builder's view of a synthetic cloud (points and per-point times; it
// must outlive the view), sensor mount_z_m above the base.
CloudView view_of(const SynthCloud& cloud, int64_t utime, double mount_z_m);

}  // namespace evade::mapping
