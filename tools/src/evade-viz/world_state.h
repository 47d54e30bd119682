// What evade-viz knows of the robot's world: the newest message of each
// channel it draws, decoded, with the point cloud already in the world
// (odometry) frame. Fed by the live bus or a log, one message at a time; no
// socket, no clock, no window.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config/config.h"
#include "config/fields.h"
#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "mapping/elevation_map.h"
#include "mapping/pose_buffer.h"
#include "sensing/lidar_decoder.h"
#include "sensing/lidar_driver_core.h"

namespace evade::viz {

struct VizParams {
  int window_width_px = 1280;
  int window_height_px = 800;
  double refresh_period_s = 0.1;
  double cloud_min_z_m = -0.2;  // colour scale by height: blue at min, red at max
  double cloud_max_z_m = 1.5;
  double point_size_px = 2.0;
  double cell_size_px = 6.0;
  int ellipse_segments = 32;
  double prediction_min_opacity = 0.15;  // of the last predicted ellipse; the first is opaque
  double velocity_arrow_s = 1.0;         // a track's arrow ends where it will be in this long
  double camera_distance_m = 9.0;        // follow camera: this far behind the robot
  double camera_height_m = 7.0;          // and this high
  double seek_step_s = 5.0;
  double footprint_length_m = 0.42;  // robot.footprint_length_m
  double footprint_width_m = 0.31;   // robot.footprint_width_m

  // The `viz:` section (the footprint is robot:'s, from_config).
  template <class V>
  void fields(V& v) {
    v.field("window_width_px", window_width_px, config::between(160, 8192));
    v.field("window_height_px", window_height_px, config::between(120, 8192));
    v.field("refresh_period_s", refresh_period_s, config::between(0.01, 10.0));
    v.field("cloud_min_z_m", cloud_min_z_m, config::between(-10.0, 10.0));
    v.field("cloud_max_z_m", cloud_max_z_m, config::between(-10.0, 20.0));
    v.rule(cloud_max_z_m > cloud_min_z_m, "cloud_max_z_m", "must exceed cloud_min_z_m");
    v.field("point_size_px", point_size_px, config::between(1.0, 20.0));
    v.field("cell_size_px", cell_size_px, config::between(1.0, 50.0));
    v.field("ellipse_segments", ellipse_segments, config::between(8, 256));
    v.field("prediction_min_opacity", prediction_min_opacity, config::between(0.0, 1.0));
    v.field("velocity_arrow_s", velocity_arrow_s, config::between(0.0, 10.0));
    v.field("camera_distance_m", camera_distance_m, config::between(0.0, 200.0));
    v.field("camera_height_m", camera_height_m, config::between(0.1, 200.0));
    v.field("seek_step_s", seek_step_s, config::between(0.1, 3600.0));
  }
  // The `viz:` section and the robot's footprint from `robot:`.
  static VizParams from_config(const config::Node& root);
};

struct WorldPoint {
  float x, y, z;
};

class WorldState {
 public:
  // LiDAR decoding (for LIDAR_SCAN) and motion compensation from the robot configuration.
  WorldState(const sensing::LidarDriverParams& lidar, const mapping::ElevationMapParams& map);

  // Decodes and keeps one message heard at bus time `utime`; false when it
  // is malformed (counted). Channels it does not draw are ignored (true).
  bool apply(const std::string& channel, const uint8_t* data, size_t size, int64_t utime);
  // Forgets everything (a log seek starts again from its beginning).
  void reset();

  int64_t now() const { return now_; }
  int64_t malformed() const { return malformed_; }
  bool heard_points() const { return heard_points_; }

  std::optional<evade::odometry_t> odometry;
  std::optional<evade::grid_map_t> map;
  std::optional<evade::obstacle_list_t> obstacles;
  std::optional<evade::prediction_list_t> predictions;
  std::optional<evade::plan_t> plan;
  std::optional<evade::path_t> route;
  std::optional<evade::sim_truth_t> truth;
  std::vector<WorldPoint> cloud;  // the newest revolution, world frame
  int64_t cloud_utime = -1;

 private:
  void take_cloud(const evade::pointcloud_t& c);

  sensing::LidarDriverParams lidar_;
  mapping::ElevationMapParams map_params_;
  std::unique_ptr<sensing::LidarDecoder> decoder_;
  mapping::PoseBuffer poses_;
  bool heard_points_ = false;  // LIDAR_POINTS on the bus: LIDAR_SCAN is not decoded
  int64_t now_ = 0;
  int64_t malformed_ = 0;
};

}  // namespace evade::viz
