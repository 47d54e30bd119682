// The two processes chained on the in-memory bus: ray-cast VLP-16
// revolutions of a world with a static and a moving cylinder -> ODOMETRY +
// LIDAR_POINTS -> elevation_map -> ELEVATION_MAP -> tracker -> OBSTACLES.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bus/memory_bus.h"
#include "mapping/elevation_map_core.h"
#include "mapping/synthetic_scan.h"
#include "tracking/tracker_core.h"

namespace evade {
namespace {

pointcloud_t to_msg(int64_t utime, const mapping::SynthCloud& c, double mount_z) {
  pointcloud_t m;
  m.utime = utime;
  m.sensor_model = "vlp16";
  m.mount = {};
  m.mount.z = mount_z;
  m.packets = 0;
  m.n = int32_t(c.x.size());
  m.x = c.x;
  m.y = c.y;
  m.z = c.z;
  m.intensity.assign(c.x.size(), 0.0f);
  m.ring.assign(c.x.size(), 0);
  m.time_offset = c.time_offset;
  return m;
}

struct Truth {
  double x, y;
};

// The elevation map around the static cylinder as text ('#' obstacle,
// 'h' high, '.' ground, ' ' unseen), for reading a failure.
void print_map_window(const grid_map_t& gm) {
  for (int row = gm.height - 1; row >= 0; --row) {
    const double y = gm.origin[1] + (row + 0.5) * gm.resolution;
    if (y < 0.8 || y > 2.6) continue;
    for (int c = 0; c < gm.width; ++c) {
      const double x = gm.origin[0] + (c + 0.5) * gm.resolution;
      if (x < 1.8 || x > 3.6) continue;
      const float z = gm.elevation[row][c];
      std::printf("%c", gm.obstacle[row][c] ? '#' : std::isnan(z) ? ' ' : (z > 0.1 ? 'h' : '.'));
    }
    std::printf("\n");
  }
}

const obstacle_t* nearest(const obstacle_list_t& list, const Truth& t) {
  const obstacle_t* best = nullptr;
  for (const auto& o : list.obstacles)
    if (!best || std::hypot(o.x - t.x, o.y - t.y) < std::hypot(best->x - t.x, best->y - t.y)) best = &o;
  return best;
}

// The robot drives +x at 0.5 m/s; a static cylinder stands ahead-left, a
// moving one crosses from right to left in front at 1.5 m/s, passing 1 m
// behind the static one (surfaces 0.5 m apart: obstacles closer than about
// 0.35 m merge into one cluster, since each marks a cell of ground in front).
TEST(Pipeline, CylindersGetStableIdsAndEllipsesOnTheirSurface) {
  bus::MemoryBus bus;
  mapping::ElevationMapCore map_core{mapping::ElevationMapParams{}};
  tracking::TrackerCore tracker_core{tracking::TrackerParams{}};
  bus.add(map_core);
  bus.add(tracker_core);
  const double v = 0.5, r = 0.25;
  const int64_t t0 = 1'000'000;
  auto robot_at = [&](int64_t t) { return mapping::Pose2{v * (t - t0) * 1e-6, 0.0, 0.0}; };
  auto mover_at = [&](int64_t t) { return Truth{3.5, -2.5 + 1.5 * (t - t0) * 1e-6}; };
  const Truth fixed{2.5, 2.0};
  int64_t next_odom = t0 - 200'000;
  std::map<int, int64_t> id_of;  // 0 = static, 1 = mover
  double worst_static = 0, worst_mover = 0;
  int frames = 0;
  for (int f = 0; f < 30; ++f) {
    const int64_t utime = t0 + f * 100'000;
    // odometry up to the end of this revolution (50 Hz)
    for (; next_odom <= utime + 100'000; next_odom += 20'000) {
      odometry_t o{};
      o.utime = next_odom;
      o.x = robot_at(next_odom).x;
      o.v = v;
      bus.inject("ODOMETRY", o, next_odom);
    }
    // the mover during the sweep: use its mid-sweep position (moves 0.15 m per revolution)
    const Truth m = mover_at(utime + 50'000);
    mapping::SynthWorld w;
    w.cylinders.push_back({fixed.x, fixed.y, r, 1.0});
    w.cylinders.push_back({m.x, m.y, r, 1.7});
    mapping::SynthScanOptions opt;
    opt.robot_start = robot_at(utime);
    opt.v = v;
    opt.range_noise_std_m = 0.01;
    opt.seed = uint32_t(f + 1);
    bus.inject("LIDAR_POINTS", to_msg(utime, mapping::synth_vlp16(w, opt), 0.5), utime + 100'000);
    const auto lists = bus.decoded<obstacle_list_t>("OBSTACLES");
    ASSERT_EQ(int(lists.size()), f + 1);
    const auto& list = lists.back();
    EXPECT_EQ(list.utime, utime);
    if (list.num_obstacles != 2) {
      ADD_FAILURE() << "frame " << f << ": " << list.num_obstacles << " obstacles";
      for (const auto& o : list.obstacles)
        std::printf("  id %lld at %.2f %.2f a %.2f b %.2f cells %d\n", (long long)o.id, o.x, o.y, o.a, o.b,
                    o.num_cells);
      continue;
    }
    ++frames;
    for (int k = 0; k < 2; ++k) {
      const Truth t = k == 0 ? fixed : m;
      if (f == 25) print_map_window(bus.decoded<grid_map_t>("ELEVATION_MAP").back());
      const obstacle_t* best = nearest(list, t);
      const double err = std::hypot(best->x - t.x, best->y - t.y);
      (k == 0 ? worst_static : worst_mover) = std::max(k == 0 ? worst_static : worst_mover, err);
      if (!id_of.count(k)) id_of[k] = best->id;
      EXPECT_EQ(best->id, id_of[k]) << "frame " << f << " obstacle " << k;
      EXPECT_GE(best->a, best->b);
    }
  }
  // LiDAR sees the near half of a cylinder: the ellipse encloses that arc
  // and the ground cells in front of it, so its centre sits nearer the robot
  // than the axis, by at most about one radius.
  std::printf("worst centre error: static %.3f m, mover %.3f m\n", worst_static, worst_mover);
  EXPECT_LT(worst_static, r);
  EXPECT_LT(worst_mover, r + 0.1);
  EXPECT_EQ(frames, 30);
}

}  // namespace
}  // namespace evade
