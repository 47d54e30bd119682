#include "mapping/sweep.h"

#include <algorithm>
#include <cmath>

#include "mapping/elevation_map.h"

namespace evade::mapping {

namespace {

RigidTransform compose(const double mount_r[9], const double mount_t[3], const Pose2& robot) {
  const double cy = std::cos(robot.yaw), sy = std::sin(robot.yaw);
  RigidTransform out;
  for (int col = 0; col < 3; ++col) {
    out.r[0 * 3 + col] = cy * mount_r[0 * 3 + col] - sy * mount_r[1 * 3 + col];
    out.r[1 * 3 + col] = sy * mount_r[0 * 3 + col] + cy * mount_r[1 * 3 + col];
    out.r[2 * 3 + col] = mount_r[2 * 3 + col];
  }
  out.t[0] = cy * mount_t[0] - sy * mount_t[1] + robot.x;
  out.t[1] = sy * mount_t[0] + cy * mount_t[1] + robot.y;
  out.t[2] = mount_t[2];  // the base sits on the ground plane z = 0 of the 2D odometry
  return out;
}

}  // namespace

SweepCompensator::SweepCompensator(const CloudView& cloud, const PoseBuffer& poses, int64_t slice_us,
                                   int64_t max_sweep_us, int64_t max_extrapolation_us)
    : poses_(poses),
      utime_(cloud.utime),
      slice_us_(std::max<int64_t>(1, slice_us)),
      max_sweep_us_(max_sweep_us),
      max_extrapolation_us_(max_extrapolation_us) {
  // mount rotation R = Rz(yaw) Ry(pitch) Rx(roll)
  const double cr = std::cos(cloud.mount_roll), sr = std::sin(cloud.mount_roll);
  const double cp = std::cos(cloud.mount_pitch), sp = std::sin(cloud.mount_pitch);
  const double cyw = std::cos(cloud.mount_yaw), syw = std::sin(cloud.mount_yaw);
  const double r[9] = {cyw * cp,
                       cyw * sp * sr - syw * cr,
                       cyw * sp * cr + syw * sr,
                       syw * cp,
                       syw * sp * sr + cyw * cr,
                       syw * sp * cr - cyw * sr,
                       -sp,
                       cp * sr,
                       cp * cr};
  std::copy(r, r + 9, mount_r_);
  mount_t_[0] = cloud.mount_x;
  mount_t_[1] = cloud.mount_y;
  mount_t_[2] = cloud.mount_z;
  const auto pose0 = poses.at(cloud.utime, max_extrapolation_us);
  if (!pose0) return;
  valid_ = true;
  pose0_ = last_good_ = *pose0;
  at_utime_ = compose(mount_r_, mount_t_, pose0_);
  const size_t num_slices = size_t(std::max<int64_t>(0, max_sweep_us_) / slice_us_) + 1;
  slices_.resize(num_slices);
  ready_.assign(num_slices, 0);
}

const RigidTransform* SweepCompensator::at(int64_t off) {
  if (off < 0 || off > max_sweep_us_) return nullptr;
  const size_t k = size_t(off / slice_us_);
  if (!ready_[k]) {
    const int64_t t = utime_ + int64_t(k) * slice_us_ + slice_us_ / 2;
    const auto pose = poses_.at(t, max_extrapolation_us_);
    if (pose) {
      last_good_ = *pose;
    } else {
      ++held_;
    }
    slices_[k] = compose(mount_r_, mount_t_, last_good_);
    ready_[k] = 1;
  }
  return &slices_[k];
}

bool view_of_message(const evade::pointcloud_t& m, CloudView* v) {
  const size_t n = size_t(std::max(0, m.n));
  if (m.x.size() < n || m.y.size() < n || m.z.size() < n) return false;
  v->utime = m.utime;
  v->n = n;
  v->x = m.x.data();
  v->y = m.y.data();
  v->z = m.z.data();
  v->time_offset = m.time_offset.size() == n ? m.time_offset.data() : nullptr;
  v->mount_x = m.mount.x;
  v->mount_y = m.mount.y;
  v->mount_z = m.mount.z;
  v->mount_roll = m.mount.roll;
  v->mount_pitch = m.mount.pitch;
  v->mount_yaw = m.mount.yaw;
  return true;
}

bool compensate(const CloudView& cloud, const PoseBuffer& poses, const ElevationMapParams& p,
                std::vector<CompensatedPoint>* out, int64_t* dropped) {
  SweepCompensator sweep(cloud, poses, p.sweep_slice_us, p.max_sweep_us, p.max_extrapolation_us);
  out->clear();
  if (!sweep.valid()) return false;
  out->reserve(cloud.n);
  for (size_t i = 0; i < cloud.n; ++i) {
    const double px = cloud.x[i], py = cloud.y[i], pz = cloud.z[i];
    const RigidTransform* tf = cloud.time_offset ? sweep.at(cloud.time_offset[i]) : &sweep.at_utime();
    if (!tf || !std::isfinite(px) || !std::isfinite(py) || !std::isfinite(pz)) {
      ++*dropped;
      continue;
    }
    out->push_back({float(tf->r[0] * px + tf->r[1] * py + tf->r[2] * pz + tf->t[0]),
                    float(tf->r[3] * px + tf->r[4] * py + tf->r[5] * pz + tf->t[1]),
                    float(tf->r[6] * px + tf->r[7] * py + tf->r[8] * pz + tf->t[2]), uint32_t(i)});
  }
  return true;
}

}  // namespace evade::mapping
