// Motion compensation of one LiDAR revolution: each point goes from the
// sensor frame into the odometry frame with the robot pose at its own firing
// time (the mount, then that pose). Points are grouped in slices of
// `slice_us` of their time offset; each slice gets one pose from the
// PoseBuffer, computed on first use. What the elevation map builds from, and
// what tools (PCD export, the viewer) draw, so both see the same cloud.
#pragma once

#include <cstdint>
#include <vector>

#include "evade/pointcloud_t.hpp"
#include "mapping/pose_buffer.h"

namespace evade::mapping {

struct CloudView;
struct ElevationMapParams;

// world = r * p_sensor + t
struct RigidTransform {
  double r[9];
  double t[3];
};

class SweepCompensator {
 public:
  SweepCompensator(const CloudView& cloud, const PoseBuffer& poses, int64_t slice_us, int64_t max_sweep_us,
                   int64_t max_extrapolation_us);

  // False when the robot pose at cloud.utime is unknown (no odometry near it).
  bool valid() const { return valid_; }
  const Pose2& pose_at_utime() const { return pose0_; }
  // The transform at cloud.utime (points without a time offset).
  const RigidTransform& at_utime() const { return at_utime_; }
  // The transform for a point fired offset_us after cloud.utime; nullptr
  // when the offset lies outside [0, max_sweep_us] (a malformed offset). A
  // slice with no odometry keeps the previous slice's pose (counted).
  const RigidTransform* at(int64_t offset_us);
  int64_t slices_pose_held() const { return held_; }

 private:
  const PoseBuffer& poses_;
  int64_t utime_, slice_us_, max_sweep_us_, max_extrapolation_us_;
  double mount_r_[9], mount_t_[3];
  bool valid_ = false;
  Pose2 pose0_, last_good_;
  RigidTransform at_utime_{};
  std::vector<RigidTransform> slices_;
  std::vector<uint8_t> ready_;
  int64_t held_ = 0;
};

// The builder's view of a decoded LIDAR_POINTS message (which must outlive
// it); false when its arrays are shorter than n. Time offsets are used when
// there is one per point.
bool view_of_message(const evade::pointcloud_t& m, CloudView* out);

struct CompensatedPoint {
  float x, y, z;   // m, odometry frame
  uint32_t index;  // the point's index in the cloud
};

// Every finite point with a valid time offset, in the odometry frame, with
// the slicing and extrapolation of `p` (the elevation map's); false (and
// nothing written) when the pose at cloud.utime is unknown. `dropped`
// counts the points left out.
bool compensate(const CloudView& cloud, const PoseBuffer& poses, const ElevationMapParams& p,
                std::vector<CompensatedPoint>* out, int64_t* dropped);

}  // namespace evade::mapping
