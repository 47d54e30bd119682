// DBSCAN (Ester et al. 1996) on the obstacle cells of a grid. The grid is
// the spatial index: the eps-neighbourhood of a cell is a fixed list of cell
// offsets, so clustering n obstacle cells costs O(n * offsets), linear in n.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace evade::tracking {

// A radius that grows with the distance from the sensor, all in cells:
// eps(r) = min(max_cells, cells + growth * r). A LiDAR's returns on one
// surface lie r * (azimuth step) / sin(grazing angle) apart, so a far
// surface seen at a slant leaves gaps between its cells that a near one
// does not. growth 0 is the fixed radius of DBSCAN.
struct EpsByRange {
  double cells = 1.5;      // at the sensor
  double growth = 0.0;     // cells added per cell of range (m per m)
  double max_cells = 1.5;  // never more (>= cells)

  // Whether the radius grows at all (else it is the fixed `cells`).
  bool by_range() const { return growth > 0.0 && max_cells > cells; }
};

class GridDbscan {
 public:
  // eps in cells (a cell is a neighbour when the distance between cell
  // centres is <= eps_cells); min_points counts the cell itself, as in DBSCAN.
  GridDbscan(double eps_cells, int min_points) : GridDbscan(EpsByRange{eps_cells, 0.0, eps_cells}, min_points) {}
  // With a radius by range two cells are neighbours when their distance is
  // within the radius at the one nearer the sensor (symmetric, and a cell
  // near the robot never reaches farther than the radius there).
  GridDbscan(const EpsByRange& eps, int min_points);

  // occupied: width * height, row-major, nonzero = obstacle cell.
  // (sensor_col, sensor_row): the sensor in cell units (cell (c, r)'s centre
  // is at (c + 0.5, r + 0.5)); NaN when unknown, which takes every cell's
  // radius at the sensor (the smallest). Returns clusters as lists of cell
  // indices (row * width + col); noise cells belong to none. Cluster order
  // follows the first core cell in row-major order, so the result is
  // deterministic.
  const std::vector<std::vector<int32_t>>& run(const int8_t* occupied, int width, int height,
                                               double sensor_col = std::nan(""), double sensor_row = std::nan(""));

  int64_t noise_cells() const { return noise_; }
  // Per grid cell of the last run: its cluster's index in run()'s result,
  // or negative (not an obstacle cell, or noise).
  const std::vector<int32_t>& labels() const { return label_; }
  size_t neighbourhood_size() const { return offsets_.size(); }

 private:
  struct Offset {
    int dr, dc;
    double d2;  // squared length, cells^2
  };
  // Whether cells i and j (an offset o apart) are neighbours.
  bool near(size_t i, size_t j, const Offset& o) const {
    return !by_range_ || o.d2 <= std::min(eps2_[i], eps2_[j]) + 1e-9;
  }
  void set_radii(int width, double sensor_col, double sensor_row);

  EpsByRange eps_;
  bool by_range_;
  std::vector<Offset> offsets_;
  std::vector<double> eps2_;  // per obstacle cell, with a radius by range: its eps^2 (cells^2)
  int min_points_;
  std::vector<int32_t> label_;  // per grid cell: -2 not an obstacle, -1 unlabelled, >= 0 cluster
  std::vector<uint8_t> core_;
  std::vector<int32_t> cells_;
  std::vector<int32_t> queue_;
  std::vector<std::vector<int32_t>> clusters_;
  int64_t noise_ = 0;
};

// Kuhn-Munkres (Hungarian) assignment minimising the summed cost of a
// rows x cols matrix (row-major). Returns, for each row, its column or -1
// (when rows > cols some rows stay unassigned). O(n^2 m).
std::vector<int> kuhn_munkres(const std::vector<double>& cost, int rows, int cols);

}  // namespace evade::tracking
