// DBSCAN (Ester et al. 1996) on the obstacle cells of a grid. The grid is
// the spatial index: the eps-neighbourhood of a cell is a fixed list of cell
// offsets, so clustering n obstacle cells costs O(n * offsets), linear in n.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace evade::tracking {

class GridDbscan {
 public:
  // eps in cells (a cell is a neighbour when the distance between cell
  // centres is <= eps_cells); min_points counts the cell itself, as in DBSCAN.
  GridDbscan(double eps_cells, int min_points);

  // occupied: width * height, row-major, nonzero = obstacle cell.
  // Returns clusters as lists of cell indices (row * width + col); noise
  // cells belong to none. Cluster order follows the first core cell in
  // row-major order, so the result is deterministic.
  const std::vector<std::vector<int32_t>>& run(const int8_t* occupied, int width, int height);

  int64_t noise_cells() const { return noise_; }
  size_t neighbourhood_size() const { return offsets_.size(); }

 private:
  struct Offset {
    int dr, dc;
  };
  std::vector<Offset> offsets_;
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
