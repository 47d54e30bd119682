// Static structure by its true shape (mode evade): a signed distance field
// of the elevation map's obstacle cells that belong to nothing moving, and
// the footprint's barrier against it.
//
// Walls, door frames and parked cars are wrapped by the tracker in minimum
// bounding ellipses (split into tiles when large); an ellipse round a
// door's edge, grown by d_safe, closes the gap. Here the planner reads
// ELEVATION_MAP and builds, each cycle, the Euclidean distance transform
// of the obstacle cells, less the cells of the moving tracks (faster than
// `max_speed_mps`): a cell inside a moving track's current ellipse grown
// by `mover_margin_m` is not static (unless it lies inside the ellipse of
// a slow track that holds structure without the movers' cells: a wall a
// walker passes keeps its cells), nor is a cell of an 8-connected patch
// shorter than `min_structure_m` (a person, a bin, a mover's stray cells:
// structure is walls, door frames, parked cars). A slow, observed track
// whose cells are mostly structure (`min_structure_share`; tracked less
// than `min_track_age_s`, they must also span `min_structure_m`) leaves
// the ellipse constraints (its cells are in the field), the others keep
// their predicted ellipses (static_structure.h). The field enters the MPC as one more
// obstacle (ObstacleTrack::field) with the mode's CBF decay: h is the
// smallest over the footprint's discs of the field at the disc's centre
// less the disc's radius and `d_safe_m`.
//
// The field is signed and measured to the cells' edges: a free cell's
// value is its centre's distance to the nearest obstacle cell's centre
// less half a cell, an obstacle cell's the negative of its distance to the
// nearest free cell less half a cell, so that the zero level lies on the
// boundary between them and the gradient points out of an obstacle too.
// Between cell centres it is interpolated bicubically (ceres::Grid2D and
// ceres::BiCubicInterpolator), with its gradient.
//
// The field is computed only over a window (FieldWindow: the points the
// horizon can reach and the route the detour grid checks ahead,
// planner_static.cpp) and, round it, every cell within max_distance_m.
// Within the window each value and gradient is the one the whole map's
// field gives, bit for bit (window_cells in static_field.cpp says why;
// test StaticField.WindowReadsWhatTheWholeMapReads); beyond it the field
// reads as far (max_distance_m, no gradient). Which cells are
// structure is decided over the whole map, so that a wall crossing the
// window's edge keeps its whole length.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "config/fields.h"
#include "evade/grid_map_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/ellipse.h"
#include "planning/problem.h"

namespace evade::planning {

struct StaticFieldParams {
  bool enabled = true;           // mode evade: static structure by the map's cells, not by ellipses
  double d_safe_m = 0.03;        // margin between the footprint's discs and static cells
  double max_speed_mps = 0.2;    // a track faster than this moves: its cells are not static
  double min_track_age_s = 1.0;  // a slow track younger than this stands for its cells only if they are structure alone
  double mover_margin_m = 0.2;   // cells within a moving track's current ellipse grown by this are not static
  double map_max_age_s = 0.3;    // a map older than this before the cycle's odometry is not used
  double max_distance_m = 3.0;   // the field is cut at this distance (beyond it the constraint is inactive)
  double min_structure_m = 1.0;  // static cells count only in a connected patch at least this long (structure)
  double min_structure_share = 0.5;  // a slow track with this share of structure among its cells stands for them
  double blind_radius_m = 0.45;      // structure stays in the field while within this of the robot (LiDAR blind)
  int blind_memory_frames = 2;       // ...if it was structure in this many maps in a row before it came within it
  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("d_safe_m", d_safe_m, config::between(0.0, 10.0));
    v.field("max_speed_mps", max_speed_mps, config::between(0.0, 100.0));
    v.field("min_track_age_s", min_track_age_s, config::between(0.0, 3600.0));
    v.field("mover_margin_m", mover_margin_m, config::between(0.0, 10.0));
    v.field("map_max_age_s", map_max_age_s, config::between(0.0, 60.0));
    v.field("max_distance_m", max_distance_m, config::between(0.1, 100.0));
    v.field("min_structure_m", min_structure_m, config::between(0.0, 100.0));
    v.field("min_structure_share", min_structure_share, config::between(0.0, 1.0));
    v.field("blind_radius_m", blind_radius_m, config::between(0.0, 10.0));
    v.field("blind_memory_frames", blind_memory_frames, config::between(1, 1000));
  }
};

// Where the field is read exactly: the points of the box [x0, x1] x
// [y0, y1] (m, the map's frame); a bound not finite: the whole map.
struct FieldWindow {
  double x0 = -std::numeric_limits<double>::infinity(), x1 = std::numeric_limits<double>::infinity();
  double y0 = -std::numeric_limits<double>::infinity(), y1 = std::numeric_limits<double>::infinity();
  // The square of points within reach_m of (x, y) along each axis.
  static FieldWindow around(double x, double y, double reach_m) {
    return {x - reach_m, x + reach_m, y - reach_m, y + reach_m};
  }
  // Grown to hold (x, y).
  void include(double x, double y) {
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  bool whole() const { return !std::isfinite(x0) || !std::isfinite(x1) || !std::isfinite(y0) || !std::isfinite(y1); }
};

class StaticField {
 public:
  // The field of `map`'s obstacle cells outside every `movers` ellipse
  // grown by mover_margin_m that lie in an 8-connected patch at least
  // min_structure_m long; a mover's cells inside a `keep` ellipse that
  // holds such a patch without them stay in; the distances computed
  // within `window`. Null when the map is malformed (sizes, resolution,
  // non-finite origin) or the window is (a bound NaN, x0 > x1 or y0 > y1).
  static std::shared_ptr<const StaticField> build(const evade::grid_map_t& map, const std::vector<Ellipse>& movers,
                                                  const std::vector<Ellipse>& keep, const StaticFieldParams& p,
                                                  const FieldWindow& window = {});

  // The signed distance (m) at (x, y) to the static cells' boundary and
  // its gradient; outside the map, the value at its border; beyond the
  // window, max_distance_m with gradient 0 (far).
  double distance(double x, double y, double* gx, double* gy) const;
  // The same within the window; beyond it the whole map's field (computed
  // on the first such call, once): for the detour grid, whose way round a
  // blocked stretch can reach beyond the window.
  double map_distance(double x, double y, double* gx, double* gy) const;
  // The footprint's h at pose (px, py, yaw): the smallest over the discs of
  // distance - radius - d_safe_m, with its derivatives in (x, y, yaw)
  // (second derivatives 0).
  BarrierValue footprint_barrier(double px, double py, double yaw, const Footprint& fp) const;
  // The longest side (m) of the bounding box of the largest 8-connected
  // patch of static cells that has a cell inside e (0 when none has: every
  // patch in the field is at least min_structure_m).
  double structure_extent(const Ellipse& e) const;
  // The map's obstacle cells whose centre is inside e (a track's own
  // cells): the share of them that are structure cells (0 when there are
  // none), and the longest side (m) of the bounding box of those structure
  // cells (0 when none).
  struct Own {
    double structure_share = 0;
    double structure_extent_m = 0;
  };
  Own own_cells(const Ellipse& e) const;
  int static_cells() const { return static_cells_; }
  double d_safe() const { return d_safe_; }
  // A cell of the odometry frame's lattice of the map's resolution: map
  // column c is ix = c + round(origin x / resolution), row r likewise.
  struct LatticeCell {
    int64_t ix = 0, iy = 0;
  };
  // The lattice cell of a map's cell (0, 0): origin / resolution, rounded.
  static LatticeCell lattice_origin(double origin_x, double origin_y, double resolution);
  // The structure cells (the static cells the field is the distance to).
  std::vector<LatticeCell> structure_cells() const;
  double resolution() const;

 private:
  struct Impl;
  std::shared_ptr<const Impl> impl_;
  int static_cells_ = 0;
  double d_safe_ = 0;
};

// The 1D squared Euclidean distance transform (Felzenszwalb and
// Huttenlocher): out[i] = min_j (i - j)^2 + f[j], f[j] = 0 at sites and a
// large value elsewhere. Exposed for tests.
void squared_distance_1d(const std::vector<double>& f, std::vector<double>* out);
// The exact 2D squared distance (in cells) of every cell of a height x
// width row-major grid to its nearest `site` cell (a large value when there
// is none).
std::vector<double> squared_distance_2d(const std::vector<char>& site, int width, int height);

// A track is slow (not moving) at most max_speed_mps: its cells stay in
// the map (StaticStructure adds, to stand for them: observed now, and
// min_structure_share of structure among the cells in its ellipse).
bool is_slow_track(const evade::track_prediction_t& t, const StaticFieldParams& p);

// The obstacle track that carries the field into the problem (id
// kStaticFieldId; its ellipse arrays hold the robot's start, axes 0).
inline constexpr int64_t kStaticFieldId = -1;
ObstacleTrack field_track(std::shared_ptr<const StaticField> field, double x0, double y0, int N, double decay);

}  // namespace evade::planning
