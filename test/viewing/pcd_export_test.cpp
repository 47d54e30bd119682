// lcmlog-export --pcd: the files read back with pcl::io, their point counts,
// and obstacles' points where the truth puts them.
#include "pcd_export.h"

#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "bus/core.h"
#include "bus/log.h"
#include "config/config.h"
#include "evade/grid_map_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "mapping/synthetic_scan.h"

namespace {

namespace fs = std::filesystem;
using evade::bus::LogEvent;
using Cloud = pcl::PointCloud<pcl::PointXYZI>;

std::string temp_dir(const std::string& stem) {
  const std::string d = ::testing::TempDir() + stem + "_" + std::to_string(::getpid());
  fs::remove_all(d);
  return d;
}

// Files of one kind ("cloud", "map") in dir, by utime.
std::map<int64_t, Cloud> read_back(const std::string& dir, const std::string& stem) {
  std::map<int64_t, Cloud> out;
  for (const auto& f : fs::directory_iterator(dir)) {
    const std::string name = f.path().filename().string();
    if (name.rfind(stem + "_", 0) != 0) continue;
    Cloud c;
    EXPECT_EQ(pcl::io::loadPCDFile(f.path().string(), c), 0) << name;
    out[std::stoll(name.substr(stem.size() + 1))] = c;
  }
  return out;
}

evade::pcd_export::Options default_options() {
  return evade::pcd_export::Options::from_config(
      evade::config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
}

// To the robot's right front: the synthetic sweep turns counter-clockwise from
// +x, so its points are fired about 80 ms into the sweep, 8 cm and 2 deg of
// robot motion after the revolution's utime.
constexpr double kCylX = 3.6, kCylY = -1.9, kCylR = 0.3;

// A robot driving an arc past one cylinder: odometry at 100 Hz and three
// ray-cast revolutions (points fired along the sweep as the robot moves),
// one elevation map with one obstacle cell.
std::vector<LogEvent> synthetic_log(std::vector<size_t>* points_per_cloud) {
  using namespace evade::mapping;
  const double v = 1.0, omega = 0.4;
  const Pose2 start{1.0, 0.5, 0.3};
  const int64_t t0 = 1'000'000'000;
  std::vector<LogEvent> log;
  for (int k = 0; k <= 40; ++k) {  // 0.4 s
    const Pose2 p = integrate_unicycle(start, v, omega, k * 0.01);
    evade::odometry_t o{};
    o.utime = t0 + k * 10'000;
    o.x = p.x;
    o.y = p.y;
    o.yaw = p.yaw;
    o.v = v;
    o.omega = omega;
    log.push_back({o.utime, "ODOMETRY", evade::bus::encode(o)});
  }
  SynthWorld world;
  world.cylinders.push_back({kCylX, kCylY, kCylR, 1.0});
  for (int r = 0; r < 3; ++r) {
    SynthScanOptions opt;
    opt.robot_start = integrate_unicycle(start, v, omega, r * 0.1);
    opt.v = v;
    opt.omega = omega;
    opt.azimuth_steps = 900;
    const SynthCloud s = synth_vlp16(world, opt);
    evade::pointcloud_t c{};
    c.utime = t0 + r * 100'000;
    c.sensor_model = "vlp16";
    c.mount.z = opt.mount_height_m;
    c.x = s.x;
    c.y = s.y;
    c.z = s.z;
    c.n = int32_t(s.x.size());
    c.intensity.assign(c.n, 7.0f);
    c.ring.assign(c.n, 0);
    c.time_offset = s.time_offset;
    points_per_cloud->push_back(s.x.size());
    log.push_back({c.utime + 100'000, "LIDAR_POINTS", evade::bus::encode(c)});
  }
  evade::grid_map_t m{};
  m.utime = t0;
  m.origin[0] = -2.0;
  m.origin[1] = -1.0;
  m.resolution = 0.5;
  m.width = 4;
  m.height = 3;
  m.elevation.assign(3, std::vector<float>(4, NAN));
  m.obstacle.assign(3, std::vector<int8_t>(4, 0));
  m.elevation[0][0] = 0.0f;
  m.elevation[1][2] = 0.4f;
  m.obstacle[1][2] = 1;
  m.elevation[2][3] = 0.01f;
  log.push_back({t0 + 150'000, "ELEVATION_MAP", evade::bus::encode(m)});
  std::sort(log.begin(), log.end(), [](const LogEvent& a, const LogEvent& b) { return a.timestamp < b.timestamp; });
  return log;
}

TEST(PcdExport, CompensatedCloudsPutTheObstacleWhereItIs) {
  std::vector<size_t> counts;
  const std::string dir = temp_dir("pcd_synth");
  const std::string log = dir + ".lcmlog";
  evade::bus::write_log(log, synthetic_log(&counts));
  const auto st = evade::pcd_export::export_log(log, dir, default_options());
  EXPECT_FALSE(st.from_scans);
  EXPECT_EQ(st.clouds_written, 3);
  EXPECT_EQ(st.maps_written, 1);
  const auto clouds = read_back(dir, "cloud");
  ASSERT_EQ(clouds.size(), 3u);
  size_t r = 0;
  for (const auto& [utime, c] : clouds) {
    EXPECT_EQ(c.size(), counts[r++]) << utime;  // every point kept
    int on_cylinder = 0;
    for (const auto& p : c) {
      const double d = std::hypot(p.x - kCylX, p.y - kCylY);
      if (p.z < 0.05 || d > 1.0) continue;  // the cylinder's points only
      EXPECT_NEAR(d, kCylR, 0.01) << "(" << p.x << ", " << p.y << ", " << p.z << ")";
      EXPECT_EQ(p.intensity, 7.0f);
      ++on_cylinder;
    }
    EXPECT_GT(on_cylinder, 50) << utime;
  }
}

TEST(PcdExport, ElevationMapCellsCarryTheObstacleFlag) {
  std::vector<size_t> counts;
  const std::string dir = temp_dir("pcd_map");
  const std::string log = dir + ".lcmlog";
  evade::bus::write_log(log, synthetic_log(&counts));
  evade::pcd_export::export_log(log, dir, default_options());
  const auto maps = read_back(dir, "map");
  ASSERT_EQ(maps.size(), 1u);
  const Cloud& m = maps.begin()->second;
  ASSERT_EQ(m.size(), 3u);  // the cells with data
  int obstacles = 0;
  for (const auto& p : m) {
    if (p.intensity == 1.0f) {
      ++obstacles;
      EXPECT_FLOAT_EQ(p.x, -2.0f + 2.5f * 0.5f);  // column 2's centre
      EXPECT_FLOAT_EQ(p.y, -1.0f + 1.5f * 0.5f);  // row 1's centre
      EXPECT_FLOAT_EQ(p.z, 0.4f);
    } else {
      EXPECT_EQ(p.intensity, 0.0f);
    }
  }
  EXPECT_EQ(obstacles, 1);
}

// The golden paper_sim window (raw LIDAR_SCAN, no LIDAR_POINTS): clouds are
// decoded again, and the static cylinder at (-1.2, 0.8), r 0.25, h 0.5, is
// where SIM_TRUTH says.
TEST(PcdExport, ARunLogsScansAreDecodedAndTheStaticObstacleIsAtItsTruePlace) {
  const std::string log = std::string(EVADE_SOURCE_DIR) + "/logs/paper_sim_crossing/input.lcmlog";
  double ox = 0, oy = 0, radius = 0;
  int64_t scans = 0, maps = 0;
  evade::bus::for_each_event(log, [&](const LogEvent& e) {
    scans += e.channel == "LIDAR_SCAN";
    maps += e.channel == "ELEVATION_MAP";
    evade::sim_truth_t t;
    if (e.channel != "SIM_TRUTH" || !evade::bus::decode(e.data.data(), e.data.size(), &t)) return;
    for (const auto& o : t.obstacles)
      if (std::abs(o.vx) + std::abs(o.vy) == 0.0 && std::hypot(o.x + 1.2, o.y - 0.8) < 0.01) {
        ox = o.x;
        oy = o.y;
        radius = o.radius;
      }
  });
  ASSERT_GT(radius, 0.0) << "the static obstacle at (-1.2, 0.8) is in SIM_TRUTH";
  const std::string dir = temp_dir("pcd_golden");
  const auto st = evade::pcd_export::export_log(log, dir, default_options());
  EXPECT_TRUE(st.from_scans);
  EXPECT_EQ(st.malformed, 0);
  EXPECT_EQ(st.maps_written, maps);
  EXPECT_GE(st.clouds_written, scans - 1);  // the first scan may start before the window's odometry
  const auto clouds = read_back(dir, "cloud");
  EXPECT_EQ(int64_t(clouds.size()), st.clouds_written);
  int64_t total = 0, on_obstacle = 0;
  for (const auto& [utime, c] : clouds) {
    EXPECT_GT(c.size(), 10000u) << utime;
    total += int64_t(c.size());
    for (const auto& p : c) {
      const double d = std::hypot(p.x - ox, p.y - oy);
      if (p.z < 0.1 || p.z > 0.5 || d > 0.6) continue;
      EXPECT_NEAR(d, radius, 0.06) << "(" << p.x << ", " << p.y << ", " << p.z << ") at " << utime;
      ++on_obstacle;
    }
  }
  EXPECT_EQ(total, st.points_written);
  EXPECT_GT(on_obstacle, 100);
  EXPECT_EQ(read_back(dir, "map").size(), size_t(maps));
}

}  // namespace

namespace {

TEST(PcdExport, AFileThatIsNotALogIsAnError) {
  const std::string bad = temp_dir("pcd_not_a_log") + ".lcmlog";
  std::FILE* f = std::fopen(bad.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("not an lcm log", f);
  std::fclose(f);
  EXPECT_THROW(evade::pcd_export::export_log(bad, temp_dir("pcd_not_a_log_out"), default_options()),
               std::runtime_error);
  EXPECT_THROW(evade::pcd_export::export_log("/no/such.lcmlog", temp_dir("pcd_none_out"), default_options()),
               std::runtime_error);
  fs::remove(bad);
}

}  // namespace
