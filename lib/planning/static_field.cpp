#include "planning/static_field.h"

#include <ceres/cubic_interpolation.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>

namespace evade::planning {
namespace {

constexpr double kFar = 1e12;  // squared cells: "no site"

bool well_formed(const evade::grid_map_t& m) {
  const size_t cells = static_cast<size_t>(std::max(0, m.width)) * static_cast<size_t>(std::max(0, m.height));
  return m.width > 0 && m.height > 0 && m.resolution > 0 && std::isfinite(m.resolution) && std::isfinite(m.origin[0]) &&
         std::isfinite(m.origin[1]) && m.obstacle.size() == static_cast<size_t>(m.height) && cells <= 4'000'000 &&
         std::all_of(m.obstacle.begin(), m.obstacle.end(),
                     [&](const std::vector<int8_t>& row) { return row.size() == static_cast<size_t>(m.width); });
}

// The static cells of the map: obstacle cells not inside a grown mover,
// unless inside a kept ellipse.
std::vector<char> static_sites(const evade::grid_map_t& m, const std::vector<Ellipse>& movers,
                               const std::vector<Ellipse>& keep, double margin) {
  std::vector<char> site(static_cast<size_t>(m.width) * m.height, 0);
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) {
      if (m.obstacle[r][c] == 0) continue;
      const double x = m.origin[0] + (c + 0.5) * m.resolution, y = m.origin[1] + (r + 0.5) * m.resolution;
      const auto in = [&](const Ellipse& e) { return e.contains(x, y, margin); };
      const auto in_kept = [&](const Ellipse& e) { return e.contains(x, y, 0.0); };
      if (std::any_of(movers.begin(), movers.end(), in) && !std::any_of(keep.begin(), keep.end(), in_kept)) continue;
      site[static_cast<size_t>(r) * m.width + c] = 1;
    }
  return site;
}

}  // namespace

void squared_distance_1d(const std::vector<double>& f, std::vector<double>* out) {
  const int n = static_cast<int>(f.size());
  out->assign(f.size(), kFar);
  std::vector<int> v(f.size());
  std::vector<double> z(f.size() + 1);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] >= kFar) continue;  // not a site: no parabola
    double s = 0;
    while (k >= 0) {
      s = ((f[q] + double(q) * q) - (f[v[k]] + double(v[k]) * v[k])) / (2.0 * q - 2.0 * v[k]);
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -std::numeric_limits<double>::infinity() : s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0) return;
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    (*out)[q] = double(q - v[j]) * (q - v[j]) + f[v[j]];
  }
}

std::vector<double> squared_distance_2d(const std::vector<char>& site, int width, int height) {
  std::vector<double> d(site.size(), kFar), f, g;
  // columns, then rows over the column results
  for (int c = 0; c < width; ++c) {
    f.assign(height, kFar);
    for (int r = 0; r < height; ++r)
      if (site[static_cast<size_t>(r) * width + c]) f[r] = 0;
    squared_distance_1d(f, &g);
    for (int r = 0; r < height; ++r) d[static_cast<size_t>(r) * width + c] = g[r];
  }
  for (int r = 0; r < height; ++r) {
    f.assign(d.begin() + static_cast<ptrdiff_t>(r) * width, d.begin() + static_cast<ptrdiff_t>(r + 1) * width);
    squared_distance_1d(f, &g);
    std::copy(g.begin(), g.end(), d.begin() + static_cast<ptrdiff_t>(r) * width);
  }
  return d;
}

namespace {

// Cells [r0, r1) x [c0, c1) of the map.
struct CellBox {
  int r0 = 0, r1 = 0, c0 = 0, c1 = 0;
  int rows() const { return r1 - r0; }
  int cols() const { return c1 - c0; }
};

// The signed distance (m, cut at +-cap) of the cells of `box` to the
// boundary of `site`'s cells in `box`, interpolated bicubically. Indexed by
// the map's own rows and columns: the interpolation of a point whose 4 x 4
// cells lie in the box reads what the same grid over the whole map reads.
struct SignedGrid {
  CellBox box;
  std::vector<double> values;  // row-major over box
  ceres::Grid2D<double, 1> grid;
  ceres::BiCubicInterpolator<ceres::Grid2D<double, 1>> interp;
  SignedGrid(const CellBox& b, std::vector<double> v)
      : box(b), values(std::move(v)), grid(values.data(), b.r0, b.r1, b.c0, b.c1), interp(grid) {}
};

std::unique_ptr<SignedGrid> signed_grid(const std::vector<char>& site, int W, const CellBox& box, double res,
                                        double cap) {
  const int rows = box.rows(), cols = box.cols();
  std::vector<char> in(static_cast<size_t>(rows) * cols), free_in(in.size());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const size_t i = static_cast<size_t>(r) * cols + c;
      in[i] = site[static_cast<size_t>(box.r0 + r) * W + box.c0 + c];
      free_in[i] = !in[i];
    }
  const std::vector<double> to_obstacle = squared_distance_2d(in, cols, rows);
  const std::vector<double> to_free = squared_distance_2d(free_in, cols, rows);
  std::vector<double> signed_d(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const double d = in[i] ? -(std::sqrt(to_free[i]) - 0.5) * res : (std::sqrt(to_obstacle[i]) - 0.5) * res;
    signed_d[i] = std::clamp(d, -cap, cap);
  }
  return std::make_unique<SignedGrid>(box, std::move(signed_d));
}

}  // namespace

struct StaticField::Impl {
  double ox = 0, oy = 0, res = 0, cap = 0;
  int width = 0, height = 0;
  std::vector<float> extent;    // per static cell: its patch's longest bounding-box side (m); 0 elsewhere
  std::vector<char> obstacle;   // the map's obstacle cells, row-major
  std::vector<char> structure;  // the static (structure) cells, row-major
  // The field over the window's cells, and the points (fractional cell
  // coordinates, cell centres at integers) where it is read: r in [r_lo,
  // r_hi], c in [c_lo, c_hi] (infinite: the whole map).
  std::unique_ptr<SignedGrid> near;
  double r_lo = -std::numeric_limits<double>::infinity(), r_hi = std::numeric_limits<double>::infinity();
  double c_lo = -std::numeric_limits<double>::infinity(), c_hi = std::numeric_limits<double>::infinity();
  // The whole map's field, built when first read beyond the window.
  mutable std::once_flag whole_once;
  mutable std::unique_ptr<SignedGrid> whole;

  // The fractional cell coordinates of a point: cell (r, c) has its centre
  // at origin + (c + 0.5, r + 0.5) res.
  double col(double x) const { return (x - ox) / res - 0.5; }
  double row(double y) const { return (y - oy) / res - 0.5; }
  bool in_window(double r, double c) const { return r >= r_lo && r <= r_hi && c >= c_lo && c <= c_hi; }
  const SignedGrid& whole_grid() const {
    if (std::isinf(r_hi)) return *near;
    std::call_once(whole_once, [&] { whole = signed_grid(structure, width, {0, height, 0, width}, res, cap); });
    return *whole;
  }
  double evaluate(const SignedGrid& g, double r, double c, double* gx, double* gy) const {
    double f = 0, dfdr = 0, dfdc = 0;
    g.interp.Evaluate(r, c, &f, &dfdr, &dfdc);
    *gx = dfdc / res;
    *gy = dfdr / res;
    return f;
  }
};

namespace {

// Per site: the longest bounding-box side (in cells) of its 8-connected patch.
std::vector<float> patch_extents(const std::vector<char>& site, int W, int H) {
  std::vector<float> out(site.size(), 0.0f);
  std::vector<char> seen(site.size(), 0);
  std::vector<int> stack, members;
  for (int start = 0; start < W * H; ++start) {
    if (!site[start] || seen[start]) continue;
    int r0 = H, r1 = -1, c0 = W, c1 = -1;
    stack.assign(1, start);
    members.clear();
    seen[start] = 1;
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      members.push_back(i);
      const int r = i / W, c = i % W;
      r0 = std::min(r0, r), r1 = std::max(r1, r), c0 = std::min(c0, c), c1 = std::max(c1, c);
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || rr >= H || cc < 0 || cc >= W) continue;
          const int j = rr * W + cc;
          if (site[j] && !seen[j]) seen[j] = 1, stack.push_back(j);
        }
    }
    const float e = static_cast<float>(std::max(r1 - r0 + 1, c1 - c0 + 1));
    for (int i : members) out[i] = e;
  }
  return out;
}

// Calls visit(i) for each cell i (row-major W x H, origin ox, oy, cell
// res) whose centre is inside e.
template <class Visit>
void cells_in(int W, int H, double ox, double oy, double res, const Ellipse& e, Visit visit) {
  const double reach = std::max(e.a, e.b);
  const int c0 = std::max(0, static_cast<int>(std::floor((e.x - reach - ox) / res)));
  const int c1 = std::min(W - 1, static_cast<int>(std::floor((e.x + reach - ox) / res)));
  const int r0 = std::max(0, static_cast<int>(std::floor((e.y - reach - oy) / res)));
  const int r1 = std::min(H - 1, static_cast<int>(std::floor((e.y + reach - oy) / res)));
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      if (e.contains(ox + (c + 0.5) * res, oy + (r + 0.5) * res, 0.0)) visit(static_cast<size_t>(r) * W + c);
}

// The largest patch extent (m) of `extent` (per cell) at a cell inside e.
double largest_in(const std::vector<float>& extent, int W, int H, double ox, double oy, double res, const Ellipse& e) {
  double best = 0;
  cells_in(W, H, ox, oy, res, e, [&](size_t i) { best = std::max(best, static_cast<double>(extent[i])); });
  return best;
}

// The static cells that are structure (in a patch at least
// min_structure_m long) and, in *extent, each one's patch extent (m).
std::vector<char> structure_sites(const evade::grid_map_t& m, const std::vector<Ellipse>& movers,
                                  const std::vector<Ellipse>& keep, const StaticFieldParams& p,
                                  std::vector<float>* extent) {
  std::vector<char> site = static_sites(m, movers, keep, p.mover_margin_m);
  *extent = patch_extents(site, m.width, m.height);
  for (size_t i = 0; i < site.size(); ++i) {
    (*extent)[i] *= static_cast<float>(m.resolution);
    if (site[i] && (*extent)[i] < p.min_structure_m - 1e-6) site[i] = 0, (*extent)[i] = 0.0f;
  }
  return site;
}

}  // namespace

namespace {

// The window's cells: every cell of the 4 x 4 that interpolates a point
// of the window (rows r_lo..r_hi, columns c_lo..c_hi in fractional cell
// coordinates; beyond the map, its border cells, as ceres::Grid2D reads
// them), and round each such cell every cell nearer than the cut (cap /
// res + 0.5 cells) and one more, within the map. A cell's nearest site
// (obstacle or free) within the cut is then in the window, and one beyond
// it gives the cut either way: the window's value of each such cell is the
// whole map's, bit for bit.
CellBox window_cells(double r_lo, double r_hi, double c_lo, double c_hi, double res, double cap, int W, int H) {
  const int margin = static_cast<int>(std::ceil(cap / res + 0.5)) + 1;
  const auto lo = [&](double v, int n) { return static_cast<int>(std::clamp(std::floor(v) - 1.0, 0.0, n - 1.0)); };
  const auto hi = [&](double v, int n) { return static_cast<int>(std::clamp(std::floor(v) + 2.0, 0.0, n - 1.0)); };
  CellBox b;
  b.r0 = std::max(0, lo(r_lo, H) - margin);
  b.r1 = std::min(H, hi(r_hi, H) + margin + 1);
  b.c0 = std::max(0, lo(c_lo, W) - margin);
  b.c1 = std::min(W, hi(c_hi, W) + margin + 1);
  return b;
}

}  // namespace

std::shared_ptr<const StaticField> StaticField::build(const evade::grid_map_t& map, const std::vector<Ellipse>& movers,
                                                      const std::vector<Ellipse>& keep, const StaticFieldParams& p,
                                                      const FieldWindow& window) {
  if (!well_formed(map) || !(window.x0 <= window.x1) || !(window.y0 <= window.y1)) return nullptr;
  const int W = map.width, H = map.height;
  // Structure without the movers' cells first; then the movers' cells
  // inside a kept ellipse that holds structure on its own stay static too
  // (a wall a walker passes keeps its cells), not those of a kept ellipse
  // without any (two walkers side by side, one standing, are no wall).
  // Over the whole map: a patch's length is its whole length.
  std::vector<float> extent;
  std::vector<char> site = structure_sites(map, movers, {}, p, &extent);
  std::vector<Ellipse> anchored;
  for (const Ellipse& e : keep)
    if (largest_in(extent, W, H, map.origin[0], map.origin[1], map.resolution, e) > 0.0) anchored.push_back(e);
  if (!anchored.empty() && !movers.empty()) site = structure_sites(map, movers, anchored, p, &extent);
  auto impl = std::make_shared<Impl>();
  impl->ox = map.origin[0], impl->oy = map.origin[1], impl->res = map.resolution, impl->cap = p.max_distance_m;
  impl->width = W, impl->height = H;
  CellBox box{0, H, 0, W};
  if (!window.whole()) {
    impl->c_lo = impl->col(window.x0), impl->c_hi = impl->col(window.x1);
    impl->r_lo = impl->row(window.y0), impl->r_hi = impl->row(window.y1);
    box = window_cells(impl->r_lo, impl->r_hi, impl->c_lo, impl->c_hi, impl->res, impl->cap, W, H);
  }
  impl->near = signed_grid(site, W, box, impl->res, impl->cap);
  impl->extent = std::move(extent);
  impl->obstacle.resize(site.size());
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) impl->obstacle[static_cast<size_t>(r) * W + c] = map.obstacle[r][c] != 0;
  auto out = std::make_shared<StaticField>();
  out->static_cells_ = static_cast<int>(std::count(site.begin(), site.end(), 1));
  impl->structure = std::move(site);
  out->impl_ = std::move(impl);
  out->d_safe_ = p.d_safe_m;
  return out;
}

StaticField::LatticeCell StaticField::lattice_origin(double origin_x, double origin_y, double resolution) {
  return {std::llround(origin_x / resolution), std::llround(origin_y / resolution)};
}

std::vector<StaticField::LatticeCell> StaticField::structure_cells() const {
  const Impl& m = *impl_;
  const LatticeCell o = lattice_origin(m.ox, m.oy, m.res);
  std::vector<LatticeCell> out;
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c)
      if (m.structure[static_cast<size_t>(r) * m.width + c]) out.push_back({c + o.ix, r + o.iy});
  return out;
}

double StaticField::resolution() const { return impl_->res; }

double StaticField::distance(double x, double y, double* gx, double* gy) const {
  const Impl& m = *impl_;
  const double c = m.col(x), r = m.row(y);
  if (!m.in_window(r, c)) {
    *gx = *gy = 0.0;
    return m.cap;  // beyond the window: far
  }
  return m.evaluate(*m.near, r, c, gx, gy);
}

double StaticField::map_distance(double x, double y, double* gx, double* gy) const {
  const Impl& m = *impl_;
  const double c = m.col(x), r = m.row(y);
  return m.evaluate(m.in_window(r, c) ? *m.near : m.whole_grid(), r, c, gx, gy);
}

double StaticField::structure_extent(const Ellipse& e) const {
  const Impl& m = *impl_;
  return largest_in(m.extent, m.width, m.height, m.ox, m.oy, m.res, e);
}

StaticField::Own StaticField::own_cells(const Ellipse& e) const {
  const Impl& m = *impl_;
  int cells = 0, structure = 0, r0 = m.height, r1 = -1, c0 = m.width, c1 = -1;
  cells_in(m.width, m.height, m.ox, m.oy, m.res, e, [&](size_t i) {
    cells += m.obstacle[i];
    if (!m.structure[i]) return;
    ++structure;
    const int r = static_cast<int>(i) / m.width, c = static_cast<int>(i) % m.width;
    r0 = std::min(r0, r), r1 = std::max(r1, r), c0 = std::min(c0, c), c1 = std::max(c1, c);
  });
  Own out;
  if (cells > 0) out.structure_share = static_cast<double>(structure) / cells;
  if (structure > 0) out.structure_extent_m = std::max(r1 - r0 + 1, c1 - c0 + 1) * m.res;
  return out;
}

BarrierValue StaticField::footprint_barrier(double px, double py, double yaw, const Footprint& fp) const {
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  BarrierValue best;
  double best_off = 0;
  bool first = true;
  for (double off : fp.offsets) {
    BarrierValue v;
    v.h = distance(px + off * cy, py + off * sy, &v.gx, &v.gy) - fp.radius - d_safe_;
    if (first || v.h < best.h) best = v, best_off = off, first = false;
  }
  // the disc's centre moves with yaw by off (-sin, cos)
  best.gth = best.gx * (-best_off * sy) + best.gy * (best_off * cy);
  return best;
}

BarrierValue static_field_barrier(const StaticField& f, double px, double py, double yaw, const Footprint& fp) {
  return f.footprint_barrier(px, py, yaw, fp);
}

bool is_slow_track(const evade::track_prediction_t& t, const StaticFieldParams& p) {
  return std::hypot(t.vx, t.vy) <= p.max_speed_mps;
}

ObstacleTrack field_track(std::shared_ptr<const StaticField> field, double x0, double y0, int N, double decay) {
  ObstacleTrack o;
  o.id = kStaticFieldId;
  o.x.assign(N + 1, x0);
  o.y.assign(N + 1, y0);
  o.a.assign(N + 1, 0.0);
  o.b.assign(N + 1, 0.0);
  o.theta.assign(N + 1, 0.0);
  o.decay = decay;
  o.field = std::move(field);
  return o;
}

}  // namespace evade::planning
