#include "sensing/self_filter.h"

#include <cmath>

namespace evade::sensing {

SelfFilter::SelfFilter(const SelfFilterParams& params, const evade::pose3d_t& mount)
    : enabled_(params.enabled),
      half_length_(params.footprint_length_m / 2 + params.margin_m),
      half_width_(params.footprint_width_m / 2 + params.margin_m),
      tx_(mount.x),
      ty_(mount.y) {
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
