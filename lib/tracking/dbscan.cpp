#include "tracking/dbscan.h"

#include <cmath>
#include <limits>

namespace evade::tracking {

GridDbscan::GridDbscan(const EpsByRange& eps, int min_points)
    : eps_(eps), by_range_(eps.by_range()), min_points_(min_points) {
  const double reach = by_range_ ? eps.max_cells : eps.cells;
  const int r = int(std::floor(reach + 1e-9));
  for (int dr = -r; dr <= r; ++dr)
    for (int dc = -r; dc <= r; ++dc) {
      const double d2 = double(dr * dr + dc * dc);
      if (d2 <= reach * reach + 1e-9) offsets_.push_back({dr, dc, d2});
    }
}

void GridDbscan::set_radii(int w, double sensor_col, double sensor_row) {
  const bool known = std::isfinite(sensor_col) && std::isfinite(sensor_row);
  for (int32_t i : cells_) {
    const double range = known ? std::hypot(i % w + 0.5 - sensor_col, i / w + 0.5 - sensor_row) : 0.0;
    const double e = std::min(eps_.max_cells, eps_.cells + eps_.growth * range);
    eps2_[size_t(i)] = e * e;
  }
}

const std::vector<std::vector<int32_t>>& GridDbscan::run(const int8_t* occ, int w, int h, double sensor_col,
                                                         double sensor_row) {
  const size_t n = size_t(w) * size_t(h);
  label_.assign(n, -2);
  core_.assign(n, 0);
  cells_.clear();
  clusters_.clear();
  noise_ = 0;
  for (size_t i = 0; i < n; ++i)
    if (occ[i]) {
      label_[i] = -1;
      cells_.push_back(int32_t(i));
    }
  if (by_range_) {
    eps2_.resize(n);
    set_radii(w, sensor_col, sensor_row);
  }
  // core cells: at least min_points obstacle cells within eps (itself included)
  for (int32_t i : cells_) {
    const int r = i / w, c = i % w;
    int count = 0;
    for (const auto& o : offsets_) {
      const int rr = r + o.dr, cc = c + o.dc;
      if (rr < 0 || cc < 0 || rr >= h || cc >= w) continue;
      const size_t j = size_t(rr) * w + cc;
      if (label_[j] != -2 && near(size_t(i), j, o)) ++count;
    }
    core_[i] = count >= min_points_;
  }
  // grow clusters from core cells; border cells join the first cluster that reaches them
  for (int32_t seed : cells_) {
    if (!core_[seed] || label_[seed] >= 0) continue;
    const int32_t id = int32_t(clusters_.size());
    clusters_.emplace_back();
    auto& members = clusters_.back();
    queue_.clear();
    queue_.push_back(seed);
    label_[seed] = id;
    for (size_t q = 0; q < queue_.size(); ++q) {
      const int32_t i = queue_[q];
      members.push_back(i);
      if (!core_[i]) continue;  // border cells do not expand
      const int r = i / w, c = i % w;
      for (const auto& o : offsets_) {
        const int rr = r + o.dr, cc = c + o.dc;
        if (rr < 0 || cc < 0 || rr >= h || cc >= w) continue;
        const size_t j = size_t(rr) * w + cc;
        if (label_[j] != -1 || !near(size_t(i), j, o)) continue;
        label_[j] = id;
        queue_.push_back(int32_t(j));
      }
    }
  }
  for (int32_t i : cells_)
    if (label_[i] < 0) ++noise_;
  return clusters_;
}

std::vector<int> kuhn_munkres(const std::vector<double>& cost, int rows, int cols) {
  std::vector<int> result(size_t(std::max(rows, 0)), -1);
  if (rows <= 0 || cols <= 0) return result;
  const bool transposed = rows > cols;  // the potential method needs rows <= cols
  const int n = transposed ? cols : rows, m = transposed ? rows : cols;
  auto a = [&](int i, int j) {  // 1-based
    return transposed ? cost[size_t(j - 1) * cols + (i - 1)] : cost[size_t(i - 1) * cols + (j - 1)];
  };
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0), minv(m + 1);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  std::vector<char> used(m + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), inf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a(i0, j) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  for (int j = 1; j <= m; ++j) {
    if (!p[j]) continue;
    if (transposed)
      result[size_t(j - 1)] = p[j] - 1;
    else
      result[size_t(p[j] - 1)] = j - 1;
  }
  return result;
}

}  // namespace evade::tracking
