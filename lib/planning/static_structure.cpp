#include "planning/static_structure.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "planning/input_checks.h"
#include "planning/obstacles.h"

namespace evade::planning {

StructureDepth structure_depth(const Problem& pb, const std::vector<double>& states) {
  StructureDepth d;
  for (const ObstacleTrack& o : pb.obstacles) {
    if (!o.field) continue;
    const double h0 = barrier_at(pb, o, 0, &states[0]).h;
    const double margin_floor = std::min(0.0, h0), body_floor = std::min(-o.field->d_safe(), h0);
    for (int k = 1; k <= pb.N; ++k) {
      const double h = barrier_at(pb, o, k, &states[3 * k]).h;
      d.margin = std::max(d.margin, margin_floor - h);
      d.body = std::max(d.body, body_floor - h);
    }
  }
  return d;
}

double structure_intrusion(const Problem& pb, const std::vector<double>& states) {
  return structure_depth(pb, states).margin;
}

void StaticStructure::keep_map(const evade::grid_map_t& m) {
  maps_.push_back(m);
  while (maps_.size() > kMapsKept) maps_.pop_front();
}

void StaticStructure::clear() {
  maps_.clear();
  field_.reset();
  static_ids_.clear();
  remembered_.clear();
  seen_.clear();
  remembered_utime_ = -1;
}

bool StaticStructure::add_remembered(const evade::grid_map_t& map, evade::grid_map_t* with) const {
  if (p_.blind_radius_m <= 0 || remembered_.empty() || map.resolution != remembered_res_ ||
      !std::isfinite(map.robot_x) || !std::isfinite(map.robot_y) || !std::isfinite(map.origin[0]) ||
      !std::isfinite(map.origin[1]) || map.obstacle.size() != static_cast<size_t>(std::max(0, map.height)))
    return false;
  const double res = map.resolution;
  const StaticField::LatticeCell o = StaticField::lattice_origin(map.origin[0], map.origin[1], res);
  bool added = false;
  for (const StaticField::LatticeCell& cell : remembered_) {
    const int64_t c = cell.ix - o.ix, r = cell.iy - o.iy;
    if (c < 0 || r < 0 || r >= map.height || c >= static_cast<int64_t>(map.obstacle[r].size())) continue;
    if (!in_blind_disc(map, o, cell) || map.obstacle[r][c]) continue;
    if (!added) *with = map, added = true;
    with->obstacle[r][c] = 1;
  }
  return added;
}

const evade::grid_map_t* StaticStructure::nearest_map(int64_t utime) const {
  const evade::grid_map_t* map = nullptr;
  for (const auto& m : maps_)
    if (!map || std::llabs(m.utime - utime) < std::llabs(map->utime - utime)) map = &m;
  return map;
}

bool StaticStructure::observed(int64_t id, const Inputs& in) {
  return in.observed && std::any_of(in.observed->obstacles.begin(), in.observed->obstacles.end(),
                                    [&](const evade::obstacle_t& o) { return o.id == id; });
}

bool StaticStructure::in_blind_disc(const evade::grid_map_t& map, const StaticField::LatticeCell& o,
                                    const StaticField::LatticeCell& cell) const {
  // the cell's centre in this map (whose origin need not lie on the lattice)
  const double res = map.resolution;
  const double dx = map.origin[0] + (cell.ix - o.ix + 0.5) * res - map.robot_x;
  const double dy = map.origin[1] + (cell.iy - o.iy + 0.5) * res - map.robot_y;
  return dx * dx + dy * dy <= p_.blind_radius_m * p_.blind_radius_m;
}

void StaticStructure::remember(const evade::grid_map_t& map) {
  if (map.utime == remembered_utime_ && map.resolution == remembered_res_) return;
  remembered_utime_ = map.utime;
  // inside the disc, what was seen before it came into it, not refreshed
  // from the cells added for it (the map's cells flicker at an edge:
  // refreshed, the disc would keep every cell that was ever marked there);
  // outside it, what the map saw from this field, and how many maps in a
  // row it has (a cell enters the disc's memory only after
  // blind_memory_frames of them)
  const auto before = [](const StaticField::LatticeCell& a, const StaticField::LatticeCell& b) {
    return a.ix != b.ix ? a.ix < b.ix : a.iy < b.iy;
  };
  const StaticField::LatticeCell o = StaticField::lattice_origin(map.origin[0], map.origin[1], map.resolution);
  std::vector<StaticField::LatticeCell> kept;
  std::vector<std::pair<StaticField::LatticeCell, int>> seen;
  if (map.resolution == remembered_res_)
    for (const StaticField::LatticeCell& cell : remembered_)
      if (in_blind_disc(map, o, cell)) kept.push_back(cell);
  if (map.resolution != remembered_res_) seen_.clear();
  for (const StaticField::LatticeCell& cell : field_->structure_cells()) {
    if (in_blind_disc(map, o, cell)) continue;
    const auto it =
        std::lower_bound(seen_.begin(), seen_.end(), cell,
                         [&](const auto& e, const StaticField::LatticeCell& c) { return before(e.first, c); });
    const bool was = it != seen_.end() && !before(cell, it->first);
    seen.emplace_back(cell, was ? it->second + 1 : 1);
    if (seen.back().second >= p_.blind_memory_frames) kept.push_back(cell);
  }
  std::sort(seen.begin(), seen.end(), [&](const auto& x, const auto& y) { return before(x.first, y.first); });
  seen_ = std::move(seen);
  remembered_ = std::move(kept);
  remembered_res_ = map.resolution;
}

StaticStructure::Update StaticStructure::update(const Inputs& in) {
  field_.reset();
  static_ids_.clear();
  // the map of the scan the predictions come from (else the nearest in time)
  const evade::grid_map_t* map = nearest_map(in.predictions ? in.predictions->utime : in.odometry_utime);
  if (!map || age_us(in.odometry_utime, map->utime) > std::llround(p_.map_max_age_s * 1e6)) return Update::kStale;
  // Static by the map, not by the track: only a track that moves takes its
  // cells out of the map. A slow one's cells stay whatever its age (a wall's
  // tile listed under a new id is still wall); they are structure or not by
  // the patch they lie in.
  std::vector<Ellipse> movers, keep;
  std::vector<int64_t> ids;
  std::vector<double> ages;
  if (in.predictions) {
    const double shift_s = (map->utime - in.predictions->utime) * 1e-6;
    for (const auto& t : in.predictions->tracks) {
      if (!valid_track(t)) continue;
      if (!is_slow_track(t, p_)) {
        movers.push_back({t.x[0] + t.vx * shift_s, t.y[0] + t.vy * shift_s, t.a[0], t.b[0], t.theta[0]});
      } else if (observed(t.id, in)) {  // a coasting track's cells may be hidden
        keep.push_back({t.x[0], t.y[0], t.a[0], t.b[0], t.theta[0]});
        ids.push_back(t.id);
        ages.push_back(in.track_age_s ? in.track_age_s(t.id) : 0.0);
      }
    }
  }
  evade::grid_map_t with_remembered;
  if (add_remembered(*map, &with_remembered)) map = &with_remembered;
  field_ = StaticField::build(*map, movers, keep, p_, in.window);
  if (!field_) return Update::kInvalid;
  if (p_.blind_radius_m > 0) remember(*map);
  // A slow, observed track stands for its cells when its own cells are
  // structure: most of the obstacle cells in its ellipse (a wall's tile,
  // even the short piece at a door's edge). A person or a bin beside a
  // wall, whose ellipse takes in some of the wall's cells, keeps its
  // ellipse: most of its cells are its own, no structure. A new track
  // reads slow while its speed is unknown: it stands for its cells only
  // when they are structure by themselves (a wall's tile under a new id,
  // not a walker that has just come up beside a wall or another walker).
  for (size_t i = 0; i < ids.size(); ++i) {
    const StaticField::Own own = field_->own_cells(keep[i]);
    const bool known = ages[i] >= p_.min_track_age_s;
    if (own.structure_share >= p_.min_structure_share && (known || own.structure_extent_m >= p_.min_structure_m - 1e-6))
      static_ids_.push_back(ids[i]);
  }
  std::sort(static_ids_.begin(), static_ids_.end());
  return Update::kBuilt;
}

bool StaticStructure::stands_for(int64_t id) const {
  return std::binary_search(static_ids_.begin(), static_ids_.end(), id);
}

void StaticStructure::apply(double x0, double y0, double decay, Problem* pb) const {
  if (!field_) return;
  auto& obs = pb->obstacles;
  obs.erase(std::remove_if(obs.begin(), obs.end(), [&](const ObstacleTrack& o) { return stands_for(o.id); }),
            obs.end());
  double gx, gy;
  if (field_->distance(x0, y0, &gx, &gy) >= p_.max_distance_m - 1e-3) return;  // flat here
  obs.insert(obs.begin(), field_track(field_, x0, y0, pb->N, decay));
}

}  // namespace evade::planning
