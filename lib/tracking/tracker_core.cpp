#include "tracking/tracker_core.h"

#include <cmath>

namespace evade::tracking {

TrackerCore::TrackerCore(const TrackerParams& params) : bus::Core("tracker"), tracker_(params) {
  subscribe<evade::grid_map_t>("ELEVATION_MAP", [this](const evade::grid_map_t& m) { on_map(m); });
}

std::unique_ptr<TrackerCore> TrackerCore::from_config(const config::Node& root) {
  return std::make_unique<TrackerCore>(TrackerParams::from_config(root.section("tracker")));
}

void TrackerCore::on_map(const evade::grid_map_t& m) {
  if (m.width <= 0 || m.height <= 0 || !(m.resolution > 0.0) || !std::isfinite(m.resolution) ||
      !std::isfinite(m.origin[0]) || !std::isfinite(m.origin[1]) || int64_t(m.obstacle.size()) != m.height) {
    count("map_invalid");
    return;
  }
  // Cells beyond kMaxCoordinateM of the odometry origin are not a map any
  // robot builds; their coordinates would overflow the split lattice.
  constexpr double kMaxCoordinateM = 1e6;
  if (std::fabs(m.origin[0]) + std::fabs(m.origin[1]) + (double(m.width) + double(m.height) + 2.0) * m.resolution >
      kMaxCoordinateM) {
    count("map_invalid");
    return;
  }
  // A map whose cells are so small that eps spans more than kMaxEpsCells
  // cells would make the neighbourhood list (and DBSCAN) quadratic in eps:
  // not a map this tracker was configured for.
  if (tracker_.params().eps_cells(m.resolution).max_cells > kMaxEpsCells) {
    count("map_resolution_unsupported");
    return;
  }
  obstacle_.resize(size_t(m.width) * size_t(m.height));
  for (int r = 0; r < m.height; ++r) {
    if (int64_t(m.obstacle[size_t(r)].size()) != m.width) {
      count("map_invalid");
      return;
    }
    std::copy(m.obstacle[size_t(r)].begin(), m.obstacle[size_t(r)].end(), obstacle_.begin() + size_t(r) * m.width);
  }
  GridView g;
  g.utime = m.utime;
  g.origin_x = m.origin[0];
  g.origin_y = m.origin[1];
  g.resolution = m.resolution;
  g.width = m.width;
  g.height = m.height;
  g.obstacle = obstacle_.data();
  g.has_robot = std::isfinite(m.robot_x) && std::isfinite(m.robot_y);
  g.robot_x = m.robot_x;
  g.robot_y = m.robot_y;
  const auto& obstacles = tracker_.update(g);

  evade::obstacle_list_t out;
  out.utime = m.utime;
  out.num_obstacles = int32_t(obstacles.size());
  out.obstacles.reserve(obstacles.size());
  for (const auto& o : obstacles) {
    evade::obstacle_t msg;
    msg.id = o.id;
    msg.x = o.ellipse.cx;
    msg.y = o.ellipse.cy;
    msg.a = o.ellipse.a;
    msg.b = o.ellipse.b;
    msg.theta = o.ellipse.theta;
    msg.shape_variation = o.shape_variation;
    msg.num_cells = o.num_cells;
    msg.age = o.age;
    out.obstacles.push_back(msg);
  }
  publish("OBSTACLES", out);

  // counters for HEALTH: report what changed since the last map
  const TrackerStats& s = tracker_.stats();
  auto delta = [&](const char* name, int64_t now_v, int64_t& before) {
    if (now_v != before) count(name, now_v - before);
    before = now_v;
  };
  delta("tracks_born", s.tracks_born, reported_.tracks_born);
  delta("tracks_dropped", s.tracks_dropped, reported_.tracks_dropped);
  delta("large_clusters", s.large_clusters, reported_.large_clusters);
  delta("large_clusters_dropped", s.large_dropped, reported_.large_dropped);
  delta("tracks_over_limit", s.over_track_limit, reported_.over_track_limit);
  delta("time_reset", s.time_reset, reported_.time_reset);
}

}  // namespace evade::tracking
