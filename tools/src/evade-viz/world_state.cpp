#include "world_state.h"

#include <cmath>

#include "bus/core.h"
#include "evade/lidar_scan_t.hpp"
#include "mapping/sweep.h"

namespace evade::viz {

VizParams VizParams::from_config(const config::Node& root) {
  VizParams p;
  const config::Node s = root.section("viz");
  p.window_width_px = s.get_int("window_width_px", 160, 8192);
  p.window_height_px = s.get_int("window_height_px", 120, 8192);
  p.refresh_period_s = s.get_double("refresh_period_s", 0.01, 10.0);
  p.cloud_min_z_m = s.get_double("cloud_min_z_m", -10.0, 10.0);
  p.cloud_max_z_m = s.get_double("cloud_max_z_m", -10.0, 20.0);
  if (p.cloud_max_z_m <= p.cloud_min_z_m) s.fail("cloud_max_z_m", "must exceed cloud_min_z_m");
  p.point_size_px = s.get_double("point_size_px", 1.0, 20.0);
  p.cell_size_px = s.get_double("cell_size_px", 1.0, 50.0);
  p.ellipse_segments = s.get_int("ellipse_segments", 8, 256);
  p.prediction_min_opacity = s.get_double("prediction_min_opacity", 0.0, 1.0);
  p.velocity_arrow_s = s.get_double("velocity_arrow_s", 0.0, 10.0);
  p.camera_distance_m = s.get_double("camera_distance_m", 0.0, 200.0);
  p.camera_height_m = s.get_double("camera_height_m", 0.1, 200.0);
  p.seek_step_s = s.get_double("seek_step_s", 0.1, 3600.0);
  s.close();
  const config::Node robot = root.section("robot");
  p.footprint_length_m = robot.get_positive("footprint_length_m");
  p.footprint_width_m = robot.get_positive("footprint_width_m");
  return p;
}

WorldState::WorldState(const sensing::LidarDriverParams& lidar, const mapping::ElevationMapParams& map)
    : lidar_(lidar), map_params_(map), poses_(map.odometry_history_us) {
  reset();
}

void WorldState::reset() {
  decoder_ = std::make_unique<sensing::LidarDecoder>(lidar_.decoder, [](const std::string&, int64_t) {});
  poses_ = mapping::PoseBuffer(map_params_.odometry_history_us);
  odometry.reset();
  map.reset();
  obstacles.reset();
  predictions.reset();
  plan.reset();
  route.reset();
  truth.reset();
  cloud.clear();
  cloud_utime = -1;
  heard_points_ = false;
  now_ = 0;
}

namespace {

template <class Msg>
bool take(const uint8_t* data, size_t size, std::optional<Msg>* slot) {
  Msg m{};
  if (!bus::decode(data, size, &m)) return false;
  *slot = std::move(m);
  return true;
}

}  // namespace

bool WorldState::apply(const std::string& ch, const uint8_t* data, size_t size, int64_t utime) {
  now_ = utime;
  bool ok = true;
  if (ch == "ODOMETRY") {
    ok = take(data, size, &odometry);
    if (ok) poses_.add({odometry->utime, {odometry->x, odometry->y, odometry->yaw}, odometry->v, odometry->omega});
  } else if (ch == "ELEVATION_MAP") {
    ok = take(data, size, &map);
  } else if (ch == "OBSTACLES") {
    ok = take(data, size, &obstacles);
  } else if (ch == "OBSTACLE_PREDICTIONS") {
    ok = take(data, size, &predictions);
  } else if (ch == "PLAN") {
    ok = take(data, size, &plan);
  } else if (ch == "ROUTE") {
    ok = take(data, size, &route);
  } else if (ch == "SIM_TRUTH") {
    ok = take(data, size, &truth);
  } else if (ch == sensing::kLidarPointsChannel) {
    evade::pointcloud_t c;
    ok = bus::decode(data, size, &c);
    if (ok) {
      heard_points_ = true;
      take_cloud(c);
    }
  } else if (ch == sensing::kLidarScanChannel && !heard_points_) {
    evade::lidar_scan_t s;
    ok = bus::decode(data, size, &s) && s.sensor_model == sensing::model_name(lidar_.decoder.model);
    if (ok) {
      std::vector<sensing::Revolution> revs;
      decoder_->feed_scan(s, &revs);
      for (const auto& r : revs) take_cloud(r.cloud);
    }
  }
  if (!ok) ++malformed_;
  return ok;
}

void WorldState::take_cloud(const evade::pointcloud_t& c) {
  mapping::CloudView v;
  std::vector<mapping::CompensatedPoint> pts;
  int64_t dropped = 0;
  // No odometry near the revolution (or a malformed one): keep the last cloud.
  if (!mapping::view_of_message(c, &v) || !mapping::compensate(v, poses_, map_params_, &pts, &dropped)) return;
  cloud.clear();
  cloud.reserve(pts.size());
  for (const auto& q : pts) cloud.push_back({q.x, q.y, q.z});
  cloud_utime = c.utime;
}

}  // namespace evade::viz
