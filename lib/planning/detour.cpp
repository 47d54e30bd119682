#include "planning/detour.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>

#include "planning/problem.h"

namespace evade::planning {
namespace {

constexpr double kFar = 1e6;  // clearance with no obstacle near

// The grid: cell (i, j) has its centre at (x0 + i cell, y0 + j cell).
struct Grid {
  double x0 = 0, y0 = 0, cell = 0;
  int nx = 0, ny = 0;
  int index(int i, int j) const { return j * nx + i; }
  bool contains(int i, int j) const { return i >= 0 && i < nx && j >= 0 && j < ny; }
  // The cell whose centre is nearest to (x, y), possibly outside the grid.
  void nearest(double x, double y, int* i, int* j) const {
    *i = static_cast<int>(std::lround((x - x0) / cell));
    *j = static_cast<int>(std::lround((y - y0) / cell));
  }
  // The same, clamped into the grid, as an index.
  int cell_of(double x, double y) const {
    int i, j;
    nearest(x, y, &i, &j);
    return index(std::clamp(i, 0, nx - 1), std::clamp(j, 0, ny - 1));
  }
  double cx(int idx) const { return x0 + (idx % nx) * cell; }
  double cy(int idx) const { return y0 + (idx / nx) * cell; }
};

}  // namespace

void SettledMemory::update(int64_t utime, const std::vector<std::pair<int64_t, Ellipse>>& settled,
                           const std::vector<int64_t>& moving) {
  for (const auto& [id, e] : settled) entries_[id] = {e, utime};
  for (int64_t id : moving) entries_.erase(id);
  for (auto it = entries_.begin(); it != entries_.end();) {
    // expired, or from a later time (the log or the clock jumped back)
    const int64_t age = utime - it->second.last_seen_us;
    if (age > memory_us_ || age < 0)
      it = entries_.erase(it);
    else
      ++it;
  }
}

std::vector<Ellipse> SettledMemory::obstacles() const {
  std::vector<Ellipse> out;
  out.reserve(entries_.size());
  for (const auto& [id, e] : entries_) out.push_back(e.ellipse);
  return out;
}

double DetourPlanner::clearance(const std::vector<Ellipse>& obstacles, double px, double py) const {
  double h = kFar;
  for (const Ellipse& o : obstacles) {
    // Beyond the major axis plus d_safe and comfort, h cannot be the smallest
    // one that matters: skip the line-ellipse distance.
    if (std::hypot(px - o.x, py - o.y) > o.a + d_safe_ + p_.comfort_m + p_.cell_m) continue;
    h = std::min(h, barrier(px, py, o.x, o.y, o.a, o.b, o.theta, d_safe_).h);
  }
  if (field_) {
    double gx, gy;
    h = std::min(h, field_->map_distance(px, py, &gx, &gy) - field_radius_ - field_->d_safe() + p_.margin_m);
  }
  return h;
}

namespace {

// The blocked stretch of the route ahead: from the first blocked route
// point within the lookahead to the last one of the run that follows it;
// *rejoin is the first point rejoin_m past it that is free (-1: none
// before s_end). False when nothing within the lookahead is blocked.
bool blocked_stretch(const DetourPlanner& planner, const DetourParams& p, const RouteFollower& route,
                     const std::vector<Ellipse>& obstacles, double s_start, double s_end, double* rejoin) {
  const double step = p.cell_m;
  double first_blocked = -1, free_run = 0;
  *rejoin = -1;
  // counted steps: at arc lengths of 1e17 m, s += step would not move s
  const int samples = static_cast<int>(std::floor((s_end - s_start) / step + 1e-9)) + 1;
  for (int i = 0; i < samples; ++i) {
    const double s = s_start + i * step;
    double rx, ry;
    route.position_at(s, &rx, &ry);
    const bool blocked = planner.clearance(obstacles, rx, ry) < p.margin_m;
    if (first_blocked < 0) {
      if (!blocked && s > s_start + p.lookahead_m) break;
      if (blocked) first_blocked = s;
      continue;
    }
    free_run = blocked ? 0.0 : free_run + step;
    if (free_run >= p.rejoin_m) {
      *rejoin = s;
      break;
    }
  }
  return first_blocked >= 0;
}

// Distance of each cell from the route between s_start and mark_end: a
// two-pass chamfer transform from the route's cells.
std::vector<double> route_distance(const Grid& g, const RouteFollower& route, double s_start, double mark_end) {
  const int n = g.nx * g.ny;
  const double step = g.cell;
  std::vector<double> off_route(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  const int marks = static_cast<int>(std::floor((mark_end - s_start) / (0.5 * step) + 1e-9)) + 1;
  for (int q = 0; q < marks; ++q) {
    const double s = s_start + q * 0.5 * step;
    double rx, ry;
    route.position_at(s, &rx, &ry);
    int i, j;
    g.nearest(rx, ry, &i, &j);
    if (g.contains(i, j)) off_route[static_cast<size_t>(g.index(i, j))] = 0.0;
  }
  const double diag = std::sqrt(2.0) * g.cell;
  auto relax = [&](int i, int j, int ni, int nj, double w) {
    if (!g.contains(ni, nj)) return;
    double& d = off_route[static_cast<size_t>(g.index(i, j))];
    d = std::min(d, off_route[static_cast<size_t>(g.index(ni, nj))] + w);
  };
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      relax(i, j, i - 1, j, g.cell);
      relax(i, j, i, j - 1, g.cell);
      relax(i, j, i - 1, j - 1, diag);
      relax(i, j, i + 1, j - 1, diag);
    }
  for (int j = g.ny - 1; j >= 0; --j)
    for (int i = g.nx - 1; i >= 0; --i) {
      relax(i, j, i + 1, j, g.cell);
      relax(i, j, i, j + 1, g.cell);
      relax(i, j, i + 1, j + 1, diag);
      relax(i, j, i - 1, j + 1, diag);
    }
  return off_route;
}

// The cost factor per metre of each cell, and which cells are blocked
// (h < margin_m) and inside d_safe (h < 0: where the constraints do not
// let the robot be).
struct CellCosts {
  std::vector<double> factor;
  std::vector<char> blocked, inside;
};

CellCosts cell_costs(const DetourPlanner& planner, const DetourParams& p, const Grid& g,
                     const std::vector<Ellipse>& obstacles, const std::vector<double>& off_route) {
  const int n = g.nx * g.ny;
  CellCosts c{std::vector<double>(static_cast<size_t>(n)), std::vector<char>(static_cast<size_t>(n), 0),
              std::vector<char>(static_cast<size_t>(n), 0)};
  for (int idx = 0; idx < n; ++idx) {
    const double h = planner.clearance(obstacles, g.cx(idx), g.cy(idx));
    const double dev = off_route[static_cast<size_t>(idx)];
    double f = 1.0 + p.deviation_cost * (std::isfinite(dev) ? dev : 0.0);
    c.inside[static_cast<size_t>(idx)] = h < 0.0;
    if (h < p.margin_m) {
      c.blocked[static_cast<size_t>(idx)] = 1;
      f = p.blocked_cost;
    } else if (h < p.comfort_m) {
      f += p.proximity_cost * (p.comfort_m - h) / (p.comfort_m - p.margin_m);
    }
    c.factor[static_cast<size_t>(idx)] = f;
  }
  return c;
}

// Hysteresis: the free cells along the previous way round (prev_x,
// prev_y) and next to it cost `discount` times as much, so that two ways
// of about the same length do not take turns.
void discount_previous_way(const Grid& g, const std::vector<double>& prev_x, const std::vector<double>& prev_y,
                           double discount, CellCosts* c) {
  const int n = g.nx * g.ny;
  std::vector<char> mark(static_cast<size_t>(n), 0);
  for (size_t k = 0; k + 1 < prev_x.size(); ++k) {
    const double len = std::hypot(prev_x[k + 1] - prev_x[k], prev_y[k + 1] - prev_y[k]);
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / (0.5 * g.cell))));
    for (int q = 0; q <= pieces; ++q) {
      const double t = static_cast<double>(q) / pieces;
      const double qx = prev_x[k] + t * (prev_x[k + 1] - prev_x[k]);
      const double qy = prev_y[k] + t * (prev_y[k + 1] - prev_y[k]);
      int i, j;
      g.nearest(qx, qy, &i, &j);
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          if (g.contains(i + di, j + dj)) mark[static_cast<size_t>(g.index(i + di, j + dj))] = 1;
    }
  }
  for (int idx = 0; idx < n; ++idx)
    if (mark[static_cast<size_t>(idx)] && !c->blocked[static_cast<size_t>(idx)])
      c->factor[static_cast<size_t>(idx)] *= discount;
}

// A*, 8-connected, from cell `start` to cell `goal` (centre (tx, ty)); a
// move costs its length times the mean factor of its two cells. The
// heuristic (straight-line distance times the smallest factor) is
// admissible, so the way found is the cheapest on the grid. The cell path,
// start first (empty when the goal was not reached); *expanded counts the
// cells expanded.
std::vector<int> cheapest_path(const Grid& g, const std::vector<double>& factor, double min_factor, int start, int goal,
                               double tx, double ty, int* expanded) {
  const int n = g.nx * g.ny;
  std::vector<double> cost(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  std::vector<int> parent(static_cast<size_t>(n), -1);
  std::vector<char> closed(static_cast<size_t>(n), 0);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  auto heuristic = [&](int idx) { return min_factor * std::hypot(g.cx(idx) - tx, g.cy(idx) - ty); };
  cost[static_cast<size_t>(start)] = 0;
  open.push({heuristic(start), start});
  static constexpr int kDi[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDj[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const int cur = open.top().second;
    open.pop();
    if (closed[static_cast<size_t>(cur)]) continue;
    closed[static_cast<size_t>(cur)] = 1;
    ++*expanded;
    if (cur == goal) break;
    const int ci = cur % g.nx, cj = cur / g.nx;
    for (int d = 0; d < 8; ++d) {
      const int ni = ci + kDi[d], nj = cj + kDj[d];
      if (!g.contains(ni, nj)) continue;
      const int nb = g.index(ni, nj);
      if (closed[static_cast<size_t>(nb)]) continue;
      const double len = (d < 4 ? 1.0 : std::sqrt(2.0)) * g.cell;
      const double c = cost[static_cast<size_t>(cur)] +
                       len * 0.5 * (factor[static_cast<size_t>(cur)] + factor[static_cast<size_t>(nb)]);
      if (c < cost[static_cast<size_t>(nb)]) {
        cost[static_cast<size_t>(nb)] = c;
        parent[static_cast<size_t>(nb)] = cur;
        open.push({c + heuristic(nb), nb});
      }
    }
  }
  std::vector<int> cells;
  if (!closed[static_cast<size_t>(goal)]) return cells;  // cannot happen on a connected grid
  for (int c = goal; c != -1; c = parent[static_cast<size_t>(c)]) cells.push_back(c);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

// The way may cross cells inside d_safe (h < 0) only to leave the zone
// the robot is in (blocked_cost makes that the shortest way out); one
// that enters such a zone later found no gap. (A squeeze with
// 0 <= h < margin_m is a way, if a costly one.)
bool enters_d_safe_later(const std::vector<int>& cells, const std::vector<char>& inside) {
  bool left_start_zone = false;
  for (int c : cells) {
    if (!inside[static_cast<size_t>(c)])
      left_start_zone = true;
    else if (left_start_zone)
      return true;
  }
  return false;
}

// The cell path between its ends smoothed by a moving average of half
// width `half` cells, appended to (x, y).
void append_smoothed(const Grid& g, const std::vector<int>& cells, int half, std::vector<double>* x,
                     std::vector<double>* y) {
  const int m = static_cast<int>(cells.size());
  for (int k = 1; k + 1 < m; ++k) {
    const int w = std::min({half, k, m - 1 - k});
    double sx = 0, sy = 0;
    for (int q = k - w; q <= k + w; ++q) {
      sx += g.cx(cells[static_cast<size_t>(q)]);
      sy += g.cy(cells[static_cast<size_t>(q)]);
    }
    x->push_back(sx / (2 * w + 1));
    y->push_back(sy / (2 * w + 1));
  }
}

}  // namespace

DetourPlanner::Result DetourPlanner::plan(const RouteFollower& route, double px, double py,
                                          const std::vector<Ellipse>& obstacles, std::vector<double>* x,
                                          std::vector<double>* y) {
  x->clear();
  y->clear();
  last_expanded_ = 0;
  auto forget = [&](Result r) {
    prev_x_.clear();
    prev_y_.clear();
    return r;
  };
  if (!p_.enabled || obstacles.empty() || !route.has_route()) return forget(Result::kClear);
  const double s_start = route.progress();
  // No farther than a grid of max_cells could reach (a long route blocked to
  // its end must not cost a scan of all of it every cycle).
  const double s_end = std::min(route.length(), s_start + p_.lookahead_m + std::sqrt(p_.max_cells) * p_.cell_m);
  double rejoin;
  if (!blocked_stretch(*this, p_, route, obstacles, s_start, s_end, &rejoin)) return forget(Result::kClear);
  if (rejoin < 0) return forget(Result::kNoWay);  // blocked to the route's end or beyond any grid's reach
  double tx, ty;
  route.position_at(rejoin, &tx, &ty);

  // The grid: the box of robot and rejoin point, padded.
  Grid g;
  g.cell = p_.cell_m;
  g.x0 = std::min(px, tx) - p_.pad_m;
  g.y0 = std::min(py, ty) - p_.pad_m;
  const double wx = std::fabs(px - tx) + 2 * p_.pad_m, wy = std::fabs(py - ty) + 2 * p_.pad_m;
  // sized in double first: a robot reported kilometres off its route must
  // not overflow the cell counts
  const double cells_x = std::ceil(wx / g.cell) + 1, cells_y = std::ceil(wy / g.cell) + 1;
  if (!(cells_x * cells_y <= p_.max_cells)) return forget(Result::kNoWay);
  g.nx = static_cast<int>(cells_x);
  g.ny = static_cast<int>(cells_y);

  const std::vector<double> off_route = route_distance(g, route, s_start, std::min(s_end, rejoin + p_.pad_m));
  CellCosts c = cell_costs(*this, p_, g, obstacles, off_route);
  double min_factor = 1.0;
  if (!prev_x_.empty() && p_.keep_side_discount < 1.0) {
    discount_previous_way(g, prev_x_, prev_y_, p_.keep_side_discount, &c);
    min_factor = p_.keep_side_discount;
  }
  const std::vector<int> cells =
      cheapest_path(g, c.factor, min_factor, g.cell_of(px, py), g.cell_of(tx, ty), tx, ty, &last_expanded_);
  if (cells.empty() || enters_d_safe_later(cells, c.inside)) return forget(Result::kNoWay);
  // A way that keeps within min_offset_m of the route is the MPC's own
  // swerve: the route stays the reference (a box beside the route whose
  // ellipse comes a little too close, or a bin, is passed as before).
  double widest = 0.0;
  for (int cell : cells) widest = std::max(widest, off_route[static_cast<size_t>(cell)]);
  if (widest < p_.min_offset_m) return forget(Result::kClear);
  // The way: the robot, the cell path between its ends smoothed, then the
  // rejoin point and the rest of the route.
  x->push_back(px);
  y->push_back(py);
  append_smoothed(g, cells, static_cast<int>(std::lround(p_.smoothing_m / g.cell)), x, y);
  x->push_back(tx);
  y->push_back(ty);
  route.vertices_after(rejoin, x, y);
  prev_x_ = *x;
  prev_y_ = *y;
  return Result::kDetour;
}

}  // namespace evade::planning
