// The paper's local map (section III-B "Local map"): a robot-centred 2.5D
// elevation grid built from one LiDAR revolution, and its obstacle layer
//   G_S = sqrt((S_x*M)^2 + (S_y*M)^2),  G_L = |L*M|,
//   obs = G_S > S_max  or  G_L > L_max  or  h_step > h_max.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/config.h"
#include "config/fields.h"
#include "mapping/hidden_region_params.h"
#include "mapping/pose_buffer.h"

namespace evade::mapping {

struct ElevationMapParams {
  // grid (robot-centred, axis-aligned with the odometry frame)
  double size_x_m = 24.0;  // lib/mapping/README.md says why (the paper: 10 x 10 m)
  double size_y_m = 24.0;
  double resolution_m = 0.1;
  // crop (exact box test fused with the binning pass, see elevation_map.cpp)
  double min_z_m = -1.0;  // elevation band kept, above the ground plane of the base
  double max_z_m = 2.0;
  double min_range_m = 0.4;  // sensor-frame range below which a return is the robot itself
  double max_range_m = 100.0;
  // motion compensation and odometry
  int64_t sweep_slice_us = 1000;  // points fired within one slice share one interpolated pose
  int64_t max_sweep_us = 200000;  // time offsets beyond this are malformed
  int64_t odometry_history_us = 2000000;
  int64_t max_extrapolation_us = 150000;
  // hole filling: an empty cell with at least this many of its 8 neighbours
  // holding data, all within step_max_m of each other, takes their mean
  // (one pass, so only small holes close)
  int hole_fill_min_neighbors = 5;
  // obstacle layer limits (the robot's operating limits)
  double sobel_max = 0.6;                 // S_max, m/m (slope; Sobel normalised by 8 * resolution)
  double laplace_max_per_m = 15.0;        // L_max, 1/m (Laplacian normalised by resolution^2)
  double step_max_m = 0.10;               // h_max
  bool step_includes_cell_extent = true;  // h_step also counts max - min z inside the cell
  // Within this horizontal distance of the robot no beam reaches the ground
  // (mount height / tan(lowest beam)); there an empty neighbour in the
  // obstacle test is the robot's own ground plane (z = 0) instead of the
  // centre's value, so an object beside the robot, of which the LiDAR sees
  // only the object itself, is still an obstacle. 0 = off.
  double blind_ground_radius_m = 1.9;
  // The step limit against that assumed ground plane: the plane is a guess
  // (a 25 % ramp starting 1 m away is 0.11 m up where the lowest ring first
  // meets it), so it keeps a margin above step_max_m.
  double blind_ground_step_max_m = 0.15;
  HiddenRegionParams hidden_regions;  // OCCLUSIONS (hidden_regions.h)

  int width() const;
  int height() const;

  template <class V>
  void fields(V& v) {
    v.field("size_x_m", size_x_m, config::between(1.0, 200.0));
    v.field("size_y_m", size_y_m, config::between(1.0, 200.0));
    v.field("resolution_m", resolution_m, config::between(0.01, 2.0));
    v.rule(width() >= 3 && height() >= 3, "resolution_m", "the grid needs at least 3 x 3 cells");
    v.rule(width() <= 4000 && height() <= 4000, "resolution_m", "more than 4000 cells along a side");
    v.field("min_z_m", min_z_m);
    v.field("max_z_m", max_z_m);
    v.rule(max_z_m > min_z_m, "max_z_m", "must be above min_z_m");
    v.field("min_range_m", min_range_m, config::between(0.0, 1000.0));
    v.field("max_range_m", max_range_m, config::between(0.0, 1000.0));
    v.rule(max_range_m > min_range_m, "max_range_m", "must be above min_range_m");
    v.convert("sweep_slice_s", sweep_slice_us, config::seconds_as_us_truncated(config::between(1e-5, 0.1)));
    v.convert("max_sweep_s", max_sweep_us, config::seconds_as_us_truncated(config::between(0.01, 1.0)));
    v.convert("odometry_history_s", odometry_history_us, config::seconds_as_us_truncated(config::between(0.1, 60.0)));
    v.convert("max_extrapolation_s", max_extrapolation_us, config::seconds_as_us_truncated(config::between(0.0, 1.0)));
    v.field("hole_fill_min_neighbors", hole_fill_min_neighbors, config::between(1, 9));
    v.field("sobel_max", sobel_max, config::positive());
    v.field("laplace_max_per_m", laplace_max_per_m, config::positive());
    v.field("step_max_m", step_max_m, config::positive());
    v.field("step_includes_cell_extent", step_includes_cell_extent);
    v.field("blind_ground_radius_m", blind_ground_radius_m, config::between(0.0, 100.0));
    v.field("blind_ground_step_max_m", blind_ground_step_max_m, config::positive());
    v.section("hidden_regions", hidden_regions);
  }
  static ElevationMapParams from_config(const config::Node& section);
};

// Cells row-major, row r = y index, column c = x index; NaN = no data.
struct ElevationLayers {
  double origin_x = 0.0;  // odometry-frame corner of cell (0, 0)
  double origin_y = 0.0;
  double resolution = 0.1;
  int width = 0;
  int height = 0;
  std::vector<float> z_max;     // the elevation layer (max elevation per cell)
  std::vector<float> z_min;     // lowest return per cell (for the in-cell step)
  std::vector<uint8_t> filled;  // 1 = value came from hole filling
  std::vector<int8_t> obstacle;

  void reset(double ox, double oy, double res, int w, int h);
  size_t index(int r, int c) const { return size_t(r) * size_t(width) + size_t(c); }
  bool known(int r, int c) const;
};

// Per-cell intermediate values of the obstacle test (tests and debugging).
struct ObstacleTerms {
  std::vector<float> sobel;    // G_S, m/m
  std::vector<float> laplace;  // G_L, 1/m
  std::vector<float> step;     // h_step, m
};

struct CloudStats {
  int64_t points_in = 0;
  int64_t points_binned = 0;
  int64_t points_cropped = 0;
  int64_t points_invalid = 0;    // NaN / inf coordinates, bad time offsets
  int64_t slices_pose_held = 0;  // sweep slices with no odometry (previous pose reused)
  int64_t cells_filled = 0;
};

// A point cloud as plain arrays (the LCM message or synthetic data).
struct CloudView {
  int64_t utime = 0;
  size_t n = 0;
  const float* x = nullptr;
  const float* y = nullptr;
  const float* z = nullptr;
  const int32_t* time_offset = nullptr;  // may be null: all points at utime
  // sensor mount on the base
  double mount_x = 0, mount_y = 0, mount_z = 0, mount_roll = 0, mount_pitch = 0, mount_yaw = 0;
};

class ElevationMapBuilder {
 public:
  explicit ElevationMapBuilder(const ElevationMapParams& p) : p_(p) {}

  // Builds the grid centred on `robot_at_utime` (cells snapped to the
  // odometry frame's lattice), transforming each point with the robot pose
  // at its own firing time from `poses`. False when the pose at cloud.utime
  // is unknown (no odometry near that time).
  bool build(const CloudView& cloud, const PoseBuffer& poses, ElevationLayers* out, Pose2* robot_at_utime,
             CloudStats* stats) const;

  const ElevationMapParams& params() const { return p_; }

 private:
  ElevationMapParams p_;
};

// Fills small holes in place (see ElevationMapParams::hole_fill_min_neighbors)
// whose known neighbours lie within max_spread_m of each other (the builder
// passes h_max: a hole on a step stays unknown); returns the cells filled.
int64_t fill_holes(ElevationLayers* layers, int min_neighbors, double max_spread_m);

// The paper's obstacle layer, written into layers->obstacle. Cells without
// data are never obstacles; inside the 3x3 window an empty neighbour takes
// the centre cell's value, so it adds neither slope nor curvature nor step
// (the edge of the data is not an edge of the terrain), except within
// p.blind_ground_radius_m of `robot` (when given), where it is the ground
// plane the robot stands on.
void compute_obstacle_layer(const ElevationMapParams& p, ElevationLayers* layers, ObstacleTerms* terms = nullptr,
                            const Pose2* robot = nullptr);

}  // namespace evade::mapping
