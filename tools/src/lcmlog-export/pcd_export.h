// PCD export of a run log (lcmlog-export --pcd DIR): each revolution's
// motion-compensated point cloud in the world (odometry) frame, and each
// elevation map, as binary PCD files that pcl_viewer reads.
//
//   DIR/cloud_<utime>.pcd  PointXYZI: every finite point of the revolution,
//                          moved with the robot pose at its own firing time
//                          (mapping::SweepCompensator over the log's
//                          ODOMETRY), intensity = the sensor's reflectivity
//   DIR/map_<utime>.pcd    PointXYZI: one point per cell with data, at the
//                          cell's centre and elevation, intensity = 1 for an
//                          obstacle cell, 0 for free
//
// Clouds come from LIDAR_POINTS, or, when the log has none (run logs leave
// them out), from LIDAR_SCAN decoded again with the configured decoder.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>
#include <string>

#include "evade/grid_map_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "mapping/elevation_map.h"
#include "mapping/pose_buffer.h"
#include "sensing/lidar_driver_core.h"

namespace evade::pcd_export {

struct Options {
  mapping::ElevationMapParams map;   // sweep slicing and extrapolation (elevation_map section)
  sensing::LidarDriverParams lidar;  // the decoder for LIDAR_SCAN (lidar, lidar_driver sections)
  static Options from_config(const config::Node& root);
};

struct Stats {
  int64_t clouds_written = 0;
  int64_t clouds_without_pose = 0;  // no odometry near the revolution's time: not written
  int64_t maps_written = 0;
  int64_t points_written = 0;
  int64_t points_invalid = 0;     // non-finite, or a time offset outside the sweep
  int64_t malformed = 0;          // ODOMETRY, LIDAR_*, ELEVATION_MAP messages that failed to decode
  int64_t scans_other_model = 0;  // LIDAR_SCAN of another sensor model than the configured one
  bool from_scans = false;        // clouds decoded from LIDAR_SCAN
};

// The revolution in the world frame; false when the pose at its utime is unknown.
bool world_cloud(const evade::pointcloud_t& cloud, const mapping::PoseBuffer& poses,
                 const mapping::ElevationMapParams& p, pcl::PointCloud<pcl::PointXYZI>* out, int64_t* invalid);
// The cells with data of an elevation map.
pcl::PointCloud<pcl::PointXYZI> map_cloud(const evade::grid_map_t& map);

// Reads the log twice (odometry first, then clouds and maps) and writes the
// files into `dir` (created if missing). Throws std::runtime_error when the
// log cannot be read or holds no event, or a file cannot be written.
Stats export_log(const std::string& log_path, const std::string& dir, const Options& options);

}  // namespace evade::pcd_export
