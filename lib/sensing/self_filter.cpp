#include "sensing/self_filter.h"

#include <cmath>

#include "sensing/lidar_decoder.h"

namespace evade::sensing {

SelfFilter::SelfFilter(const LidarDecoderParams& params)
    : enabled_(params.self_filter),
      half_length_(params.footprint_length_m / 2 + params.self_filter_margin_m),
      half_width_(params.footprint_width_m / 2 + params.self_filter_margin_m),
      tx_(params.mount.x),
      ty_(params.mount.y) {
  const evade::pose3d_t& mount = params.mount;
  // R = Rz(yaw) Ry(pitch) Rx(roll), as the mount pose is defined (SPEC.md, pose3d_t).
  const double cr = std::cos(mount.roll), sr = std::sin(mount.roll);
  const double cp = std::cos(mount.pitch), sp = std::sin(mount.pitch);
  const double cy = std::cos(mount.yaw), sy = std::sin(mount.yaw);
  r_[0][0] = cy * cp;
  r_[0][1] = cy * sp * sr - sy * cr;
  r_[0][2] = cy * sp * cr + sy * sr;
  r_[1][0] = sy * cp;
  r_[1][1] = sy * sp * sr + cy * cr;
  r_[1][2] = sy * sp * cr - cy * sr;
}

}  // namespace evade::sensing
