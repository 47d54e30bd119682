#include "mapping/elevation_map_core.h"

#include <cmath>

#include "mapping/hidden_regions.h"

namespace evade::mapping {
namespace {

// A stamp farther from the bus time than the odometry history (either way)
// comes from another clock or was made up: its poses could never be used,
// and arithmetic near INT64_MIN/MAX would overflow.
bool near_now(int64_t now, int64_t utime, int64_t window_us) {
  int64_t d;
  if (__builtin_sub_overflow(now, utime, &d)) return false;
  return d <= window_us && d >= -window_us;
}

}  // namespace

ElevationMapCore::ElevationMapCore(const ElevationMapParams& params)
    : bus::Core("elevation_map"), builder_(params), poses_(params.odometry_history_us) {
  subscribe<evade::odometry_t>("ODOMETRY", [this](const evade::odometry_t& m) { on_odometry(m); });
  subscribe<evade::pointcloud_t>("LIDAR_POINTS", [this](const evade::pointcloud_t& m) { on_cloud(m); });
}

std::unique_ptr<ElevationMapCore> ElevationMapCore::from_config(const config::Node& root) {
  return std::make_unique<ElevationMapCore>(ElevationMapParams::from_config(root.section("elevation_map")));
}

void ElevationMapCore::on_odometry(const evade::odometry_t& m) {
  if (!std::isfinite(m.x) || !std::isfinite(m.y) || !std::isfinite(m.yaw) || !std::isfinite(m.v) ||
      !std::isfinite(m.omega)) {
    count("odometry_invalid");
    return;
  }
  if (!near_now(now(), m.utime, builder_.params().odometry_history_us)) {
    count("odometry_implausible_time");
    return;
  }
  if (have_epoch_ && m.epoch != epoch_) {
    // A new odometry frame (base_driver restarted, pose reset): poses of
    // the old one would place the next clouds in the wrong frame, and the
    // cells settled in it are elsewhere in the new one.
    poses_ = PoseBuffer(builder_.params().odometry_history_us);
    settled_.clear();
    count("odometry_epoch_changed");
  }
  epoch_ = m.epoch;
  have_epoch_ = true;
  OdometrySample s;
  s.utime = m.utime;
  s.pose = {m.x, m.y, m.yaw};
  s.v = m.v;
  s.omega = m.omega;
  switch (poses_.add(s)) {
    case PoseBuffer::AddResult::kAdded:
      break;
    case PoseBuffer::AddResult::kOutOfOrder:
      count("odometry_out_of_order");
      break;
    case PoseBuffer::AddResult::kReset:
      count("odometry_reset");
      break;
  }
}

void ElevationMapCore::on_cloud(const evade::pointcloud_t& m) {
  const auto& mp = m.mount;
  if (m.n < 0 || !std::isfinite(mp.x) || !std::isfinite(mp.y) || !std::isfinite(mp.z) || !std::isfinite(mp.roll) ||
      !std::isfinite(mp.pitch) || !std::isfinite(mp.yaw)) {
    count("cloud_invalid");
    return;
  }
  if (!near_now(now(), m.utime, builder_.params().odometry_history_us)) {
    count("cloud_implausible_time");
    return;
  }
  CloudView view;
  view.utime = m.utime;
  view.n = size_t(m.n);
  view.x = m.x.data();
  view.y = m.y.data();
  view.z = m.z.data();
  view.time_offset = m.time_offset.data();
  view.mount_x = mp.x;
  view.mount_y = mp.y;
  view.mount_z = mp.z;
  view.mount_roll = mp.roll;
  view.mount_pitch = mp.pitch;
  view.mount_yaw = mp.yaw;
  Pose2 robot;
  CloudStats st;
  if (!builder_.build(view, poses_, &layers_, &robot, &st)) {
    count(poses_.empty() ? "cloud_skipped_no_odometry" : "cloud_skipped_outside_odometry");
    return;
  }
  count("points_in", st.points_in);
  count("points_binned", st.points_binned);
  if (st.points_invalid) count("points_invalid", st.points_invalid);
  if (st.slices_pose_held) count("sweep_slices_pose_held", st.slices_pose_held);

  msg_.utime = m.utime;
  msg_.origin[0] = layers_.origin_x;
  msg_.origin[1] = layers_.origin_y;
  msg_.resolution = layers_.resolution;
  msg_.width = layers_.width;
  msg_.height = layers_.height;
  msg_.robot_x = robot.x;
  msg_.robot_y = robot.y;
  msg_.robot_yaw = robot.yaw;
  msg_.elevation.resize(size_t(layers_.height));
  msg_.obstacle.resize(size_t(layers_.height));
  for (int r = 0; r < layers_.height; ++r) {
    const size_t row = layers_.index(r, 0);
    msg_.elevation[r].assign(layers_.z_max.begin() + row, layers_.z_max.begin() + row + layers_.width);
    msg_.obstacle[r].assign(layers_.obstacle.begin() + row, layers_.obstacle.begin() + row + layers_.width);
  }
  publish("ELEVATION_MAP", msg_);
  if (builder_.params().hidden_regions.enabled) publish_hidden_regions(m, robot);
}

void ElevationMapCore::publish_hidden_regions(const evade::pointcloud_t& m, const Pose2& robot) {
  const double c = std::cos(robot.yaw), s = std::sin(robot.yaw);
  hidden_.utime = m.utime;
  hidden_.sensor_x = robot.x + c * m.mount.x - s * m.mount.y;
  hidden_.sensor_y = robot.y + s * m.mount.x + c * m.mount.y;
  hidden_.regions.clear();
  const HiddenRegionParams& p = builder_.params().hidden_regions;
  settled_.update(layers_, m.utime, p.settle_s, p.gap_s, &settled_mask_);
  for (const HiddenRegion& h : hidden_regions(p, layers_, hidden_.sensor_x, hidden_.sensor_y, &settled_mask_)) {
    evade::hidden_region_t r{};
    for (int i = 0; i < 2; ++i) {
      r.near_x[i] = h.near_x[i];
      r.near_y[i] = h.near_y[i];
      r.far_x[i] = h.far_x[i];
      r.far_y[i] = h.far_y[i];
    }
    r.occluder_height_m = h.occluder_height_m;
    r.occluder_cells = h.occluder_cells;
    hidden_.regions.push_back(r);
  }
  hidden_.num_regions = int32_t(hidden_.regions.size());
  publish("OCCLUSIONS", hidden_);
}

}  // namespace evade::mapping
