// The footprint self-filter: a return whose point, put in the robot's base
// frame with the sensor's mount pose, lies over the robot's footprint
// grown by a margin (the whole column, at any height) is the robot's own
// body, not an obstacle. A LiDAR mounted high and looking far down (the
// RS-Helios-5515 to -55 deg) sees the base's top, bumpers and whatever is
// fitted on it; nothing else can be there without touching the robot.
//
// Base frame: x forward, y left, origin on the footprint's centre; the
// footprint is the rectangle |x| <= length / 2, |y| <= width / 2 (the
// robot configuration's footprint_length_m / footprint_width_m), grown by
// self_filter_margin_m.
#pragma once

#include "evade/pose3d_t.hpp"

namespace evade::sensing {

struct LidarDecoderParams;  // lidar_decoder.h

class SelfFilter {
 public:
  // self_filter, footprint_length_m, footprint_width_m,
  // self_filter_margin_m and mount of the decoder's parameters.
  explicit SelfFilter(const LidarDecoderParams& params);
  bool enabled() const { return enabled_; }
  // True when the sensor-frame point (x, y, z) lies over the grown footprint.
  bool inside(float x, float y, float z) const {
    const double bx = r_[0][0] * x + r_[0][1] * y + r_[0][2] * z + tx_;
    if (bx > half_length_ || bx < -half_length_) return false;
    const double by = r_[1][0] * x + r_[1][1] * y + r_[1][2] * z + ty_;
    return by <= half_width_ && by >= -half_width_;
  }

 private:
  bool enabled_;
  double half_length_, half_width_;
  double r_[2][3];  // the first two rows of the sensor -> base rotation
  double tx_, ty_;
};

}  // namespace evade::sensing
