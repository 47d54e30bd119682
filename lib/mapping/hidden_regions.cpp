#include "mapping/hidden_regions.h"

#include <cmath>
#include <utility>

namespace evade::mapping {
namespace {

// One occluder's extent as seen from the sensor.
struct Silhouette {
  double min_rel = 0, max_rel = 0;  // bearing of its extreme points, relative to its first cell's
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  double nearest = INFINITY;  // m, its nearest cell centre from the sensor
  double height = -INFINITY;  // m, its highest cell
  int cells = 0;
};

struct View {
  const ElevationLayers& l;
  const std::vector<uint8_t>* cells;  // the cells an occluder may use; null: every obstacle cell
  double sx, sy;
  double ref = 0;  // bearing of the occluder's first cell
};

bool usable(const View& v, size_t i) { return v.l.obstacle[i] == 1 && (!v.cells || (*v.cells)[i] == 1); }

// Adds cell (r, c) to the silhouette: its four corners and its height.
void add_cell(const View& v, int r, int c, Silhouette* s) {
  const ElevationLayers& l = v.l;
  const double x0 = l.origin_x + c * l.resolution, y0 = l.origin_y + r * l.resolution;
  const double cx = x0 + 0.5 * l.resolution, cy = y0 + 0.5 * l.resolution;
  s->nearest = std::min(s->nearest, std::hypot(cx - v.sx, cy - v.sy));
  const float z = l.z_max[l.index(r, c)];
  if (std::isfinite(z)) s->height = std::max(s->height, double(z));
  for (int k = 0; k < 4; ++k) {
    const double x = x0 + (k & 1) * l.resolution, y = y0 + (k >> 1) * l.resolution;
    const double rel = std::remainder(std::atan2(y - v.sy, x - v.sx) - v.ref, 2 * M_PI);
    if (s->cells == 0 && k == 0) {
      s->min_rel = s->max_rel = rel;
      s->min_x = s->max_x = x;
      s->min_y = s->max_y = y;
    }
    if (rel < s->min_rel) s->min_rel = rel, s->min_x = x, s->min_y = y;
    if (rel > s->max_rel) s->max_rel = rel, s->max_x = x, s->max_y = y;
  }
  ++s->cells;
}

// The obstacle cells linked to (r0, c0) that are not yet `seen`, flood-filled
// within `offsets`, added to a silhouette.
Silhouette flood(View v, int r0, int c0, const std::vector<std::pair<int, int>>& offsets, std::vector<uint8_t>* seen) {
  const ElevationLayers& l = v.l;
  const double cx = l.origin_x + (c0 + 0.5) * l.resolution, cy = l.origin_y + (r0 + 0.5) * l.resolution;
  v.ref = std::atan2(cy - v.sy, cx - v.sx);
  Silhouette s;
  std::vector<std::pair<int, int>> stack{{r0, c0}};
  (*seen)[l.index(r0, c0)] = 1;
  while (!stack.empty()) {
    const auto [r, c] = stack.back();
    stack.pop_back();
    add_cell(v, r, c, &s);
    for (const auto& [dr, dc] : offsets) {
      const int rr = r + dr, cc = c + dc;
      if (rr < 0 || cc < 0 || rr >= l.height || cc >= l.width) continue;
      const size_t i = l.index(rr, cc);
      if ((*seen)[i] || !usable(v, i)) continue;
      (*seen)[i] = 1;
      stack.emplace_back(rr, cc);
    }
  }
  return s;
}

std::vector<std::pair<int, int>> link_offsets(double link_radius_m, double resolution) {
  const double reach = std::max(1.0, link_radius_m / resolution);
  const int n = int(std::floor(reach + 1e-9));
  std::vector<std::pair<int, int>> out;
  for (int dr = -n; dr <= n; ++dr)
    for (int dc = -n; dc <= n; ++dc)
      if ((dr || dc) && dr * dr + dc * dc <= reach * reach + 1e-9) out.emplace_back(dr, dc);
  return out;
}

// The region behind a silhouette, if its occluder is one that can hide a person.
bool region_of(const HiddenRegionParams& p, const Silhouette& s, double sx, double sy, HiddenRegion* out) {
  if (s.height < p.min_height_m || s.nearest > p.max_range_m) return false;
  if (s.max_rel - s.min_rel >= M_PI * 0.9) return false;  // round the sensor: no one side is hidden
  if (std::hypot(s.max_x - s.min_x, s.max_y - s.min_y) < p.min_width_m) return false;
  const double px[2] = {s.min_x, s.max_x}, py[2] = {s.min_y, s.max_y};
  for (int i = 0; i < 2; ++i) {
    const double dx = px[i] - sx, dy = py[i] - sy, d = std::max(1e-6, std::hypot(dx, dy));
    out->near_x[i] = px[i];
    out->near_y[i] = py[i];
    out->far_x[i] = px[i] + p.depth_m * dx / d;
    out->far_y[i] = py[i] + p.depth_m * dy / d;
  }
  out->occluder_height_m = s.height;
  out->occluder_cells = s.cells;
  return true;
}

}  // namespace

std::vector<HiddenRegion> hidden_regions(const HiddenRegionParams& p, const ElevationLayers& layers, double sensor_x,
                                         double sensor_y, const std::vector<uint8_t>* occluder_cells) {
  std::vector<HiddenRegion> out;
  if (layers.width <= 0 || layers.height <= 0 || layers.obstacle.size() != layers.index(layers.height, 0)) return out;
  if (occluder_cells && occluder_cells->size() != layers.obstacle.size()) return out;
  const auto offsets = link_offsets(p.link_radius_m, layers.resolution);
  std::vector<uint8_t> seen(layers.obstacle.size(), 0);
  const View view{layers, occluder_cells, sensor_x, sensor_y};
  for (int r = 0; r < layers.height; ++r)
    for (int c = 0; c < layers.width; ++c) {
      const size_t i = layers.index(r, c);
      if (seen[i] || !usable(view, i)) continue;
      const Silhouette s = flood(view, r, c, offsets, &seen);
      HiddenRegion h;
      if (region_of(p, s, sensor_x, sensor_y, &h)) out.push_back(h);
    }
  return out;
}

}  // namespace evade::mapping
