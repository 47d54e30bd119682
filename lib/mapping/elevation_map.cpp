#include "mapping/elevation_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/sweep.h"

namespace evade::mapping {

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
}

int ElevationMapParams::width() const { return int(std::lround(size_x_m / resolution_m)); }
int ElevationMapParams::height() const { return int(std::lround(size_y_m / resolution_m)); }

ElevationMapParams ElevationMapParams::from_config(const config::Node& s) {
  return config::load<ElevationMapParams>(s);
}

void ElevationLayers::reset(double ox, double oy, double res, int w, int h) {
  origin_x = ox;
  origin_y = oy;
  resolution = res;
  width = w;
  height = h;
  const size_t n = size_t(w) * size_t(h);
  z_max.assign(n, kNaN);
  z_min.assign(n, kNaN);
  filled.assign(n, 0);
  obstacle.assign(n, 0);
}

bool ElevationLayers::known(int r, int c) const {
  return r >= 0 && c >= 0 && r < height && c < width && !std::isnan(z_max[index(r, c)]);
}

bool ElevationMapBuilder::build(const CloudView& cloud, const PoseBuffer& poses, ElevationLayers* out,
                                Pose2* robot_at_utime, CloudStats* stats) const {
  SweepCompensator sweep(cloud, poses, p_.sweep_slice_us, p_.max_sweep_us, p_.max_extrapolation_us);
  if (!sweep.valid()) return false;
  const Pose2* pose0 = &sweep.pose_at_utime();
  *robot_at_utime = *pose0;

  const double res = p_.resolution_m;
  const int w = p_.width(), h = p_.height();
  // Snap the grid to the odometry frame's lattice so a static obstacle falls
  // into the same cells from frame to frame (no re-sampling jitter).
  const double ox = std::floor(pose0->x / res) * res - (w / 2) * res;
  const double oy = std::floor(pose0->y / res) * res - (h / 2) * res;
  out->reset(ox, oy, res, w, h);

  const double min_r2 = p_.min_range_m * p_.min_range_m;
  const double max_r2 = p_.max_range_m * p_.max_range_m;
  const double inv_res = 1.0 / res;
  CloudStats st;
  st.points_in = int64_t(cloud.n);
  float* zmax = out->z_max.data();
  float* zmin = out->z_min.data();

  // The crop is the exact box test PCL's PassThrough/CropBox would do
  // (range band in the sensor frame, z band and the grid's x/y extent in the
  // odometry frame), fused with the transform and binning pass: one read of
  // each point, no copy into a pcl::PointCloud. A VoxelGrid would not pay:
  // keeping the maximum per cell already is a 2D voxel reduction.
  for (size_t i = 0; i < cloud.n; ++i) {
    const double px = cloud.x[i], py = cloud.y[i], pz = cloud.z[i];
    if (!std::isfinite(px) || !std::isfinite(py) || !std::isfinite(pz)) {
      ++st.points_invalid;
      continue;
    }
    const double r2 = px * px + py * py + pz * pz;
    if (r2 < min_r2 || r2 > max_r2) {
      ++st.points_cropped;
      continue;
    }
    const RigidTransform* tf = &sweep.at_utime();
    if (cloud.time_offset) {
      tf = sweep.at(cloud.time_offset[i]);
      if (!tf) {
        ++st.points_invalid;
        continue;
      }
    }
    const double wz = tf->r[6] * px + tf->r[7] * py + tf->r[8] * pz + tf->t[2];
    if (wz < p_.min_z_m || wz > p_.max_z_m) {
      ++st.points_cropped;
      continue;
    }
    const double wx = tf->r[0] * px + tf->r[1] * py + tf->r[2] * pz + tf->t[0];
    const double wy = tf->r[3] * px + tf->r[4] * py + tf->r[5] * pz + tf->t[1];
    const double fc = (wx - ox) * inv_res, fr = (wy - oy) * inv_res;
    if (!(fc >= 0.0 && fr >= 0.0 && fc < w && fr < h)) {
      ++st.points_cropped;
      continue;
    }
    const size_t idx = size_t(int(fr)) * size_t(w) + size_t(int(fc));
    const float z = float(wz);
    // NaN compares false: the first return in a cell takes both slots
    if (!(zmax[idx] >= z)) zmax[idx] = z;
    if (!(zmin[idx] <= z)) zmin[idx] = z;
    ++st.points_binned;
  }
  st.slices_pose_held = sweep.slices_pose_held();
  st.cells_filled = fill_holes(out, p_.hole_fill_min_neighbors, p_.step_max_m);
  compute_obstacle_layer(p_, out, nullptr, &*pose0);
  if (stats) *stats = st;
  return true;
}

int64_t fill_holes(ElevationLayers* L, int min_neighbors, double max_spread_m) {
  const int w = L->width, h = L->height;
  std::vector<std::pair<size_t, float>> fills;
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      if (L->known(r, c)) continue;
      int n = 0;
      double sum = 0.0, lo = 1e300, hi = -1e300;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          if ((dr || dc) && L->known(r + dr, c + dc)) {
            const double z = L->z_max[L->index(r + dr, c + dc)];
            ++n;
            sum += z;
            lo = std::min(lo, z);
            hi = std::max(hi, z);
          }
        }
      // a hole on an edge (neighbours differ by more than a step) stays
      // unknown: a mean there would invent an intermediate, wider obstacle
      if (n >= min_neighbors && hi - lo <= max_spread_m) fills.emplace_back(L->index(r, c), float(sum / n));
    }
  }
  // written after the scan, so a fill never feeds another fill
  for (const auto& [idx, z] : fills) {
    L->z_max[idx] = z;
    L->z_min[idx] = z;
    L->filled[idx] = 1;
  }
  return int64_t(fills.size());
}

void compute_obstacle_layer(const ElevationMapParams& p, ElevationLayers* L, ObstacleTerms* terms, const Pose2* robot) {
  const int w = L->width, h = L->height;
  const size_t n = size_t(w) * size_t(h);
  if (terms) {
    terms->sobel.assign(n, 0.0f);
    terms->laplace.assign(n, 0.0f);
    terms->step.assign(n, 0.0f);
  }
  L->obstacle.assign(n, 0);
  const float* z = L->z_max.data();
  // Sobel kernels sum 8 * (one-cell difference) over a plane: dividing by
  // 8 * resolution gives the slope in m/m, independent of the cell size.
  const double sobel_scale = 1.0 / (8.0 * L->resolution);
  const double laplace_scale = 1.0 / (L->resolution * L->resolution);
  const double blind2 = robot ? p.blind_ground_radius_m * p.blind_ground_radius_m : -1.0;
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const size_t i = L->index(r, c);
      const float zc = z[i];
      if (std::isnan(zc)) continue;
      // 3x3 window M; an empty or off-grid neighbour takes the centre value.
      // Beside the robot, where no beam reaches the ground, it is the ground
      // plane the robot stands on for a step term of its own only: a slope
      // of a few per cent at the blind zone's edge would pass the Laplacian
      // limit against it (0.04 m over a cell is 16 /m), and a steep ramp
      // starting in the blind zone rises above step_max_m where the lowest
      // ring first meets it (25 %: 0.11 m), hence blind_ground_step_max_m.
      bool near = false;
      if (blind2 > 0.0) {
        const double dx = L->origin_x + (c + 0.5) * L->resolution - robot->x;
        const double dy = L->origin_y + (r + 0.5) * L->resolution - robot->y;
        near = dx * dx + dy * dy <= blind2;
      }
      double m[3][3];
      double step = 0.0, step_blind = 0.0;  // against measured neighbours; against the assumed ground plane
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          double v = zc;
          bool empty = true;
          if (rr >= 0 && cc >= 0 && rr < h && cc < w) {
            const float zn = z[L->index(rr, cc)];
            if (!std::isnan(zn)) v = zn, empty = false;
          }
          m[dr + 1][dc + 1] = v;
          if (!empty)
            step = std::max(step, std::abs(v - zc));
          else if (near)
            step_blind = std::max(step_blind, std::abs(double(zc)));
        }
      }
      if (p.step_includes_cell_extent) step = std::max(step, double(zc - L->z_min[i]));
      // rows are y, columns are x
      const double gx = (m[0][2] + 2.0 * m[1][2] + m[2][2]) - (m[0][0] + 2.0 * m[1][0] + m[2][0]);
      const double gy = (m[2][0] + 2.0 * m[2][1] + m[2][2]) - (m[0][0] + 2.0 * m[0][1] + m[0][2]);
      const double g_s = std::sqrt(gx * gx + gy * gy) * sobel_scale;
      const double g_l = std::abs(m[0][1] + m[2][1] + m[1][0] + m[1][2] - 4.0 * m[1][1]) * laplace_scale;
      if (terms) {
        terms->sobel[i] = float(g_s);
        terms->laplace[i] = float(g_l);
        terms->step[i] = float(std::max(step, step_blind));
      }
      L->obstacle[i] = (g_s > p.sobel_max || g_l > p.laplace_max_per_m || step > p.step_max_m ||
                        step_blind > p.blind_ground_step_max_m)
                           ? 1
                           : 0;
    }
  }
}

}  // namespace evade::mapping
