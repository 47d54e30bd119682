#include "world_state.h"

#include <cmath>

#include "bus/core.h"
#include "config/robot_params.h"
#include "evade/lidar_scan_t.hpp"
#include "mapping/sweep.h"

namespace evade::viz {

VizParams VizParams::from_config(const config::Node& root) {
  VizParams p = config::load<VizParams>(root.section("viz"));
  const config::RobotParams robot = config::load<config::RobotParams>(root.section("robot"));
  p.footprint_length_m = robot.footprint_length_m;
  p.footprint_width_m = robot.footprint_width_m;
  return p;
}

WorldState::WorldState(const sensing::LidarDriverParams& lidar, const mapping::ElevationMapParams& map)
    : lidar_(lidar), map_params_(map), poses_(map.odometry_history_us) {
  reset();
}

void WorldState::reset() {
  decoder_ = std::make_unique<sensing::LidarDecoder>(lidar_, [](const std::string&, int64_t) {});
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
    ok = bus::decode(data, size, &s) && s.sensor_model == sensing::model_name(lidar_.model);
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
