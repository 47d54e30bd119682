#include "pcd_export.h"

#include <pcl/io/pcd_io.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "bus/core.h"
#include "bus/log.h"
#include "evade/lidar_scan_t.hpp"
#include "evade/odometry_t.hpp"
#include "mapping/sweep.h"
#include "sensing/lidar_decoder.h"

namespace evade::pcd_export {

namespace {

constexpr const char* kOdometry = "ODOMETRY";
constexpr const char* kElevationMap = "ELEVATION_MAP";
// The whole log's odometry is kept: the buffer forgets nothing.
constexpr int64_t kKeepEverything = std::numeric_limits<int64_t>::max() / 4;

void save(const std::string& path, const pcl::PointCloud<pcl::PointXYZI>& cloud) {
  if (pcl::io::savePCDFileBinary(path, cloud) != 0) throw std::runtime_error("cannot write " + path);
}

std::string name(const std::string& dir, const char* stem, int64_t utime) {
  return dir + "/" + stem + "_" + std::to_string(utime) + ".pcd";
}

}  // namespace

Options Options::from_config(const config::Node& root) {
  Options o;
  o.map = mapping::ElevationMapParams::from_config(root.section("elevation_map"));
  o.lidar = sensing::LidarDriverParams::from_config(root);
  return o;
}

bool world_cloud(const evade::pointcloud_t& cloud, const mapping::PoseBuffer& poses,
                 const mapping::ElevationMapParams& p, pcl::PointCloud<pcl::PointXYZI>* out, int64_t* invalid) {
  out->clear();
  mapping::CloudView v;
  std::vector<mapping::CompensatedPoint> pts;
  if (!mapping::view_of_message(cloud, &v)) {
    *invalid += cloud.n;
    return true;  // a cloud with nothing usable: written as nothing
  }
  if (!mapping::compensate(v, poses, p, &pts, invalid)) return false;
  const bool have_intensity = cloud.intensity.size() == v.n;
  out->reserve(pts.size());
  for (const auto& q : pts) {
    pcl::PointXYZI o;
    o.x = q.x;
    o.y = q.y;
    o.z = q.z;
    o.intensity = have_intensity ? cloud.intensity[q.index] : 0.0f;
    out->push_back(o);
  }
  return true;
}

pcl::PointCloud<pcl::PointXYZI> map_cloud(const evade::grid_map_t& m) {
  pcl::PointCloud<pcl::PointXYZI> out;
  for (int r = 0; r < m.height && r < int(m.elevation.size()); ++r) {
    for (int c = 0; c < m.width && c < int(m.elevation[r].size()); ++c) {
      const float z = m.elevation[r][c];
      if (!std::isfinite(z)) continue;
      pcl::PointXYZI q;
      q.x = float(m.origin[0] + (c + 0.5) * m.resolution);
      q.y = float(m.origin[1] + (r + 0.5) * m.resolution);
      q.z = z;
      const bool obstacle = r < int(m.obstacle.size()) && c < int(m.obstacle[r].size()) && m.obstacle[r][c];
      q.intensity = obstacle ? 1.0f : 0.0f;
      out.push_back(q);
    }
  }
  return out;
}

Stats export_log(const std::string& log_path, const std::string& dir, const Options& o) {
  Stats st;
  mapping::PoseBuffer poses(kKeepEverything);
  bool have_points = false;
  int64_t events = 0;
  bus::for_each_event(log_path, [&](const bus::LogEvent& e) {
    ++events;
    if (e.channel == sensing::kLidarPointsChannel) have_points = true;
    evade::odometry_t m;
    if (e.channel != kOdometry) return;
    if (!bus::decode(e.data.data(), e.data.size(), &m)) {
      ++st.malformed;
      return;
    }
    poses.add(mapping::OdometrySample{m.utime, {m.x, m.y, m.yaw}, m.v, m.omega});
  });
  if (events == 0) throw std::runtime_error(log_path + " holds no events (not an lcm-logger log?)");
  st.from_scans = !have_points;
  std::filesystem::create_directories(dir);

  sensing::LidarDecoder decoder(o.lidar, [](const std::string&, int64_t) {});
  pcl::PointCloud<pcl::PointXYZI> pcl_cloud;
  auto write_cloud = [&](const evade::pointcloud_t& c) {
    if (!world_cloud(c, poses, o.map, &pcl_cloud, &st.points_invalid)) {
      ++st.clouds_without_pose;
      return;
    }
    if (pcl_cloud.empty()) return;
    save(name(dir, "cloud", c.utime), pcl_cloud);
    ++st.clouds_written;
    st.points_written += int64_t(pcl_cloud.size());
  };
  bus::for_each_event(log_path, [&](const bus::LogEvent& e) {
    if (e.channel == kElevationMap) {
      evade::grid_map_t m;
      if (!bus::decode(e.data.data(), e.data.size(), &m)) {
        ++st.malformed;
        return;
      }
      const auto cells = map_cloud(m);
      if (cells.empty()) return;
      save(name(dir, "map", m.utime), cells);
      ++st.maps_written;
    } else if (have_points && e.channel == sensing::kLidarPointsChannel) {
      evade::pointcloud_t c;
      if (bus::decode(e.data.data(), e.data.size(), &c)) {
        write_cloud(c);
      } else {
        ++st.malformed;
      }
    } else if (!have_points && e.channel == sensing::kLidarScanChannel) {
      evade::lidar_scan_t s;
      if (!bus::decode(e.data.data(), e.data.size(), &s)) {
        ++st.malformed;
        return;
      }
      if (s.sensor_model != sensing::model_name(o.lidar.model)) {
        ++st.scans_other_model;
        return;
      }
      std::vector<sensing::Revolution> revs;
      decoder.feed_scan(s, &revs);
      for (const auto& r : revs) write_cloud(r.cloud);
    }
  });
  return st;
}

}  // namespace evade::pcd_export
