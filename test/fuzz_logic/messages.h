// Well-formed messages for the logic fuzzers (sequence.h), their fields
// drawn from the fuzzer's bytes. Array lengths always match their count
// fields; their sizes reach what a sender within the system's limits could
// produce (a 16 x 16 m map at 0.05 m, 300 obstacles, 64 predicted tracks, a revolution of points).
#pragma once

#include "bus/core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/estop_t.hpp"
#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "sequence.h"

namespace evade::fuzz {

inline std::vector<uint8_t> odometry(Bytes& in, int64_t now) {
  evade::odometry_t m{};
  m.utime = in.utime(now);
  m.x = in.value(-50, 50);
  m.y = in.value(-50, 50);
  m.yaw = in.value(-4, 4);
  m.v = in.value(-2, 2);
  m.omega = in.value(-2, 2);
  m.epoch = in.chance(16) ? in.u8() : 0;
  return bus::encode(m);
}

inline std::vector<uint8_t> cmd_vel(Bytes& in, int64_t now) {
  evade::cmd_vel_t m{};
  m.utime = in.utime(now);
  m.v = in.value(-3, 3);
  m.omega = in.value(-3, 3);
  return bus::encode(m);
}

inline std::vector<uint8_t> estop(Bytes& in, int64_t now) {
  evade::estop_t m{};
  m.utime = in.utime(now);
  m.engaged = in.chance(2);
  m.reason = "fuzz";
  return bus::encode(m);
}

inline std::vector<uint8_t> route(Bytes& in, int64_t now) {
  evade::path_t m{};
  m.utime = in.utime(now);
  m.n = in.size(in.chance(8) ? 4096 : 16);
  double x = in.range(-20, 20), y = in.range(-20, 20);
  for (int i = 0; i < m.n; ++i) {
    x += in.chance(8) ? 0.0 : in.value(-5, 5);  // repeated points too
    y += in.value(-5, 5);
    m.x.push_back(x);
    m.y.push_back(y);
  }
  return bus::encode(m);
}

inline std::vector<uint8_t> predictions(Bytes& in, int64_t now, int max_tracks) {
  evade::prediction_list_t m{};
  m.utime = in.utime(now);
  m.dt = in.chance(16) ? in.value(-1, 1) : 0.1;
  m.horizon = in.chance(8) ? in.size(64) : 26;
  m.num_tracks = in.size(in.chance(8) ? max_tracks : 4);
  for (int i = 0; i < m.num_tracks; ++i) {
    evade::track_prediction_t t{};
    t.id = in.chance(4) ? in.i64() : in.u8();
    t.vx = in.value(-3, 3);
    t.vy = in.value(-3, 3);
    t.ax = in.value(-3, 3);
    t.ay = in.value(-3, 3);
    t.horizon = m.horizon;
    const double x = in.value(-15, 15), y = in.value(-15, 15), r = in.value(0.05, 2.0);
    for (int k = 0; k < t.horizon; ++k) {
      const bool odd = in.chance(64);
      t.x.push_back(odd ? in.value(-1e3, 1e3) : x + t.vx * 0.1 * k);
      t.y.push_back(odd ? in.value(-1e3, 1e3) : y + t.vy * 0.1 * k);
      t.a.push_back(odd ? in.value(-1, 10) : r + 0.01 * k);
      t.b.push_back(odd ? in.value(-1, 10) : r);
      t.theta.push_back(odd ? in.value(-4, 4) : 0.0);
      t.sigma.push_back(odd ? in.value(-1, 1) : 0.01 * k);
    }
    m.tracks.push_back(t);
  }
  return bus::encode(m);
}

inline std::vector<uint8_t> obstacles(Bytes& in, int64_t now) {
  evade::obstacle_list_t m{};
  m.utime = in.utime(now);
  m.num_obstacles = in.size(in.chance(8) ? 300 : 6);
  for (int i = 0; i < m.num_obstacles; ++i) {
    evade::obstacle_t o{};
    o.id = in.chance(4) ? in.i64() : in.u8() % 16;
    o.x = in.value(-20, 20);
    o.y = in.value(-20, 20);
    o.a = in.value(0.0, 3.0);
    o.b = in.value(0.0, o.a > 0 ? o.a : 1.0);
    o.theta = in.value(-2, 2);
    o.shape_variation = in.value(0, 1);
    o.num_cells = static_cast<int32_t>(in.u16());
    o.age = static_cast<int32_t>(in.u16());
    m.obstacles.push_back(o);
  }
  return bus::encode(m);
}

inline std::vector<uint8_t> grid_map(Bytes& in, int64_t now) {
  evade::grid_map_t m{};
  m.utime = in.utime(now);
  m.resolution = in.chance(16) ? in.value(-1, 1) : 0.1;
  const bool big = in.chance(16);
  m.width = in.size(big ? 320 : 40);
  m.height = in.size(big ? 320 : 40);
  m.origin[0] = in.value(-30, 30);
  m.origin[1] = in.value(-30, 30);
  m.robot_x = in.value(-30, 30);
  m.robot_y = in.value(-30, 30);
  m.robot_yaw = in.value(-4, 4);
  const int density = 1 + in.u8() % 16;  // one cell in `density` is an obstacle
  m.elevation.assign(m.height, std::vector<float>(m.width, 0.0f));
  m.obstacle.assign(m.height, std::vector<int8_t>(m.width, 0));
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) {
      const uint8_t b = in.u8();
      m.obstacle[r][c] = (b % density == 0) ? 1 : 0;
      m.elevation[r][c] = b == 255 ? NAN : static_cast<float>(b) * 0.01f;
    }
  return bus::encode(m);
}

inline std::vector<uint8_t> pointcloud(Bytes& in, int64_t now) {
  evade::pointcloud_t m{};
  m.utime = in.utime(now);
  m.sensor_model = in.chance(2) ? "vlp16" : "rs_helios";
  m.mount.x = in.chance(16) ? in.value(-1, 1) : 0.0;
  m.mount.y = 0.0;
  m.mount.z = in.chance(16) ? in.value(-1, 2) : 0.5;
  m.mount.roll = m.mount.pitch = m.mount.yaw = in.chance(16) ? in.value(-1, 1) : 0.0;
  m.packets = static_cast<int32_t>(in.u16());
  m.n = in.size(in.chance(8) ? 30000 : 400);
  for (int i = 0; i < m.n; ++i) {
    const bool odd = in.chance(64);
    m.x.push_back(static_cast<float>(odd ? in.value(-200, 200) : in.range(-20, 20)));
    m.y.push_back(static_cast<float>(odd ? in.value(-200, 200) : in.range(-20, 20)));
    m.z.push_back(static_cast<float>(odd ? in.value(-10, 10) : in.range(-0.6, 1.5)));
    m.intensity.push_back(static_cast<float>(in.u8()));
    m.ring.push_back(static_cast<int8_t>(in.u8() % 16));
    m.time_offset.push_back(odd ? static_cast<int32_t>(in.u32()) : static_cast<int32_t>(in.range(0, 1e5)));
  }
  return bus::encode(m);
}

}  // namespace evade::fuzz
