// The elevation_map process core: LIDAR_POINTS + ODOMETRY -> ELEVATION_MAP.
#pragma once

#include "bus/core.h"
#include "config/config.h"
#include "evade/grid_map_t.hpp"
#include "evade/hidden_region_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "mapping/elevation_map.h"
#include "mapping/settled_cells.h"

namespace evade::mapping {

class ElevationMapCore : public bus::Core {
 public:
  explicit ElevationMapCore(const ElevationMapParams& params);
  static std::unique_ptr<ElevationMapCore> from_config(const config::Node& root);

 private:
  void on_odometry(const evade::odometry_t& m);
  void on_cloud(const evade::pointcloud_t& m);
  // OCCLUSIONS of the map just built, seen from the sensor at `robot`.
  void publish_hidden_regions(const evade::pointcloud_t& m, const Pose2& robot);

  ElevationMapBuilder builder_;
  PoseBuffer poses_;  // emptied when ODOMETRY.epoch changes (issue 20)
  int64_t epoch_ = 0;
  bool have_epoch_ = false;
  ElevationLayers layers_;
  evade::grid_map_t msg_;
  evade::hidden_region_list_t hidden_;
  SettledCells settled_;  // the cells occluders are built from (settled_cells.h)
  std::vector<uint8_t> settled_mask_;
};

}  // namespace evade::mapping
