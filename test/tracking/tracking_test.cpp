// Known-answer tests of obstacle parameterization and tracking: minimum
// bounding ellipses against analytic cases and a brute-force search, grid
// DBSCAN against the textbook O(n^2) DBSCAN, Kuhn-Munkres against all
// permutations, and tracks through crossings, dropouts and long clutter runs.
#include <gtest/gtest.h>
#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <type_traits>

#include "bus/memory_bus.h"
#include "tracking/tracker.h"
#include "tracking/tracker_core.h"

namespace evade::tracking {
namespace {

// ------------------------------------------------------------------ MBE
std::vector<Vec2> cell_corners(const std::vector<std::pair<int, int>>& cells, double res) {
  std::vector<Vec2> pts;
  for (auto [r, c] : cells)
    for (int dr = 0; dr <= 1; ++dr)
      for (int dc = 0; dc <= 1; ++dc) pts.push_back({(c + dc) * res, (r + dr) * res});
  return pts;
}

double max_level(const Ellipse& e, const std::vector<Vec2>& pts) {
  double m = 0.0;
  for (const auto& p : pts) m = std::max(m, ellipse_level(e, p));
  return m;
}

TEST(Mbe, RectangleCornersGiveTheAnalyticEllipse) {
  // the minimum ellipse through a w x h rectangle's corners has semi-axes w/sqrt2, h/sqrt2
  for (double yaw : {0.0, 0.4, -1.2}) {
    const double w = 1.2, h = 0.4, c = std::cos(yaw), s = std::sin(yaw);
    std::vector<Vec2> pts;
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0})
        pts.push_back({2.0 + c * sx * w / 2 - s * sy * h / 2, -1.0 + s * sx * w / 2 + c * sy * h / 2});
    const Ellipse e = min_bounding_ellipse(pts, MbeOptions{});
    EXPECT_NEAR(e.cx, 2.0, 1e-6);
    EXPECT_NEAR(e.cy, -1.0, 1e-6);
    EXPECT_NEAR(e.a, w / std::sqrt(2.0), 1e-4);
    EXPECT_NEAR(e.b, h / std::sqrt(2.0), 1e-4);
    EXPECT_NEAR(wrap_half_pi(e.theta - yaw), 0.0, 1e-4);
    EXPECT_LE(max_level(e, pts), 1.0 + 1e-9);
  }
}

TEST(Mbe, OneCellIsItsCircumcircleALineOfCellsIsThin) {
  const Ellipse one = min_bounding_ellipse(cell_corners({{3, 4}}, 0.1), MbeOptions{});
  EXPECT_NEAR(one.a, 0.1 / std::sqrt(2.0), 1e-5);
  EXPECT_NEAR(one.b, 0.1 / std::sqrt(2.0), 1e-5);
  EXPECT_NEAR(one.cx, 0.45, 1e-6);
  EXPECT_NEAR(one.cy, 0.35, 1e-6);
  std::vector<std::pair<int, int>> line;
  for (int r = 0; r < 6; ++r) line.push_back({r, 2});  // a column of 6 cells: 0.1 x 0.6 m
  const Ellipse e = min_bounding_ellipse(cell_corners(line, 0.1), MbeOptions{});
  EXPECT_NEAR(e.a, 0.6 / std::sqrt(2.0), 1e-4);
  EXPECT_NEAR(e.b, 0.1 / std::sqrt(2.0), 1e-4);
  EXPECT_NEAR(std::abs(e.theta), M_PI / 2, 1e-4);
}

TEST(Mbe, CollinearAndSinglePointsGetAThinEllipse) {
  MbeOptions opt;
  opt.min_semi_axis = 0.05;
  const Ellipse e = min_bounding_ellipse({{0, 0}, {1, 1}, {2, 2}, {0.5, 0.5}}, opt);
  EXPECT_NEAR(e.cx, 1.0, 1e-12);
  EXPECT_NEAR(e.cy, 1.0, 1e-12);
  EXPECT_NEAR(e.a, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(e.b, 0.05, 1e-12);
  EXPECT_NEAR(e.theta, M_PI / 4, 1e-12);
  const Ellipse p = min_bounding_ellipse({{3, 4}}, opt);
  EXPECT_NEAR(p.cx, 3.0, 1e-12);
  EXPECT_NEAR(p.a, 0.05, 1e-12);
}

// Brute force: for a centre, an axis angle and an axis ratio k = b/a, the
// smallest enclosing a follows directly; search those four parameters with
// a coarse grid and then shrinking coordinate steps from the best starts.
double brute_force_min_area(const std::vector<Vec2>& pts) {
  double mx = 0, my = 0;
  for (const auto& p : pts) mx += p.x, my += p.y;
  mx /= pts.size(), my /= pts.size();
  auto area = [&](const double q[4]) {
    const double c = std::cos(q[2]), s = std::sin(q[2]), k = q[3];
    if (k <= 0.01 || k > 1.0) return 1e300;
    double a2 = 0.0;
    for (const auto& p : pts) {
      const double dx = p.x - q[0], dy = p.y - q[1];
      const double u = c * dx + s * dy, v = (-s * dx + c * dy) / k;
      a2 = std::max(a2, u * u + v * v);
    }
    return M_PI * a2 * k;
  };
  std::vector<std::pair<double, std::array<double, 4>>> starts;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int t = 0; t < 12; ++t)
        for (double k : {0.2, 0.4, 0.6, 0.8, 1.0}) {
          std::array<double, 4> q = {mx + 0.03 * i, my + 0.03 * j, M_PI * t / 12, k};
          starts.push_back({area(q.data()), q});
        }
  std::sort(starts.begin(), starts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  double best = 1e300;
  for (size_t sidx = 0; sidx < 8; ++sidx) {
    auto q = starts[sidx].second;
    double f = starts[sidx].first;
    double step[4] = {0.02, 0.02, 0.1, 0.05};
    for (int round = 0; round < 60; ++round) {
      bool improved = true;
      while (improved) {
        improved = false;
        for (int d = 0; d < 4; ++d)
          for (double sgn : {-1.0, 1.0}) {
            auto t = q;
            t[d] += sgn * step[d];
            const double ft = area(t.data());
            if (ft < f) f = ft, q = t, improved = true;
          }
      }
      for (double& s : step) s *= 0.7;
    }
    best = std::min(best, f);
  }
  return best;
}

TEST(Mbe, RandomSmallClustersMatchBruteForceWithinOnePercent) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 25; ++trial) {
    // a random 4-connected cluster of 2..7 cells
    std::set<std::pair<int, int>> cells = {{0, 0}};
    const int n = 2 + int(rng() % 6);
    while (int(cells.size()) < n) {
      auto it = cells.begin();
      std::advance(it, rng() % cells.size());
      const int dir = int(rng() % 4);
      cells.insert({it->first + (dir == 0) - (dir == 1), it->second + (dir == 2) - (dir == 3)});
    }
    const auto pts = cell_corners({cells.begin(), cells.end()}, 0.1);
    const Ellipse e = min_bounding_ellipse(pts, MbeOptions{});
    const double ours = ellipse_area(e);
    const double brute = brute_force_min_area(pts);
    EXPECT_LE(max_level(e, pts), 1.0 + 1e-9) << trial;  // encloses every corner
    EXPECT_LE(ours, brute * 1.01) << trial;             // no more than 1% above the search's minimum
    EXPECT_LE(brute, ours * 1.02) << trial;             // and the search is itself close (sanity)
  }
}

TEST(Mbe, LargeClusterEnclosesEveryCorner) {
  std::mt19937 rng(3);
  std::vector<std::pair<int, int>> cells;
  for (int i = 0; i < 400; ++i) cells.push_back({int(rng() % 30), int(rng() % 17)});
  const auto pts = cell_corners(cells, 0.1);
  int iters = 0;
  const Ellipse e = min_bounding_ellipse(pts, MbeOptions{}, &iters);
  EXPECT_LE(max_level(e, pts), 1.0 + 1e-9);
  EXPECT_LT(iters, MbeOptions{}.max_iterations);  // converged to the tolerance
}

// --------------------------------------------------------------- DBSCAN
// Textbook DBSCAN over cell centres, O(n^2); points i and j are neighbours
// within the smaller of their radii eps_of(i), eps_of(j).
std::vector<int> reference_dbscan(const std::vector<std::pair<int, int>>& pts,
                                  const std::function<double(size_t)>& eps_of, int min_pts, std::vector<char>* core) {
  const size_t n = pts.size();
  auto nb = [&](size_t i) {
    std::vector<size_t> out;
    for (size_t j = 0; j < n; ++j) {
      const double dr = pts[i].first - pts[j].first, dc = pts[i].second - pts[j].second;
      const double eps = std::min(eps_of(i), eps_of(j));
      if (dr * dr + dc * dc <= eps * eps + 1e-9) out.push_back(j);
    }
    return out;
  };
  core->assign(n, 0);
  for (size_t i = 0; i < n; ++i) (*core)[i] = int(nb(i).size()) >= min_pts;
  std::vector<int> label(n, -1);
  int next = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(*core)[i] || label[i] >= 0) continue;
    std::vector<size_t> q = {i};
    label[i] = next;
    for (size_t k = 0; k < q.size(); ++k) {
      if (!(*core)[q[k]]) continue;
      for (size_t j : nb(q[k]))
        if (label[j] < 0) label[j] = next, q.push_back(j);
    }
    ++next;
  }
  return label;
}

// The grid's obstacle cells as (row, col), and each one's cluster in
// `clusters` (-1: none), in row-major order.
struct Labelled {
  std::vector<std::pair<int, int>> pts;
  std::vector<int> label;
};
Labelled labelled(const std::vector<int8_t>& grid, int w, const std::vector<std::vector<int32_t>>& clusters) {
  Labelled out;
  std::map<int, size_t> index_of;
  for (int i = 0; i < int(grid.size()); ++i)
    if (grid[size_t(i)]) index_of[i] = out.pts.size(), out.pts.push_back({i / w, i % w});
  out.label.assign(out.pts.size(), -1);
  for (size_t k = 0; k < clusters.size(); ++k)
    for (int32_t cell : clusters[k]) out.label[index_of[cell]] = int(k);
  return out;
}

// A w x h grid with `cells` obstacle cells drawn at random (repeats fall together).
std::vector<int8_t> random_grid(std::mt19937& rng, int w, int h, int cells) {
  std::vector<int8_t> grid(size_t(w) * size_t(h), 0);
  for (int k = 0; k < cells; ++k) grid[rng() % grid.size()] = 1;
  return grid;
}

TEST(Dbscan, MatchesTheTextbookAlgorithmOnRandomGrids) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    const int w = 40, h = 30;
    std::vector<int8_t> grid = random_grid(rng, w, h, 150);
    for (int b = 0; b < 4; ++b) {  // plus a few blobs
      const int r0 = int(rng() % (h - 5)), c0 = int(rng() % (w - 5));
      for (int r = r0; r < r0 + 4; ++r)
        for (int c = c0; c < c0 + 4; ++c) grid[r * w + c] = 1;
    }
    const double eps = 1.0 + (trial % 3) * 0.8;  // 1, 1.8, 2.6 cells
    const int min_pts = 2 + trial % 4;
    GridDbscan db(eps, min_pts);
    const auto [pts, got] = labelled(grid, w, db.run(grid.data(), w, h));
    std::vector<char> core;
    const auto ref = reference_dbscan(
        pts, [eps](size_t) { return eps; }, min_pts, &core);
    // the same clusters, same order (both start from row-major first core cells)
    int noise = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
      EXPECT_EQ(got[i], ref[i]) << "trial " << trial << " cell " << pts[i].first << "," << pts[i].second;
      noise += ref[i] < 0;
    }
    EXPECT_EQ(db.noise_cells(), noise);
  }
}

TEST(Dbscan, WithARadiusByRangeMatchesTheTextbookRule) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 30; ++trial) {
    const int w = 40, h = 30;
    const std::vector<int8_t> grid = random_grid(rng, w, h, 250);
    const EpsByRange eps{1.0 + (trial % 2) * 0.5, 0.02 + 0.01 * (trial % 3), 2.6};
    const double sc = double(rng() % w), sr = double(rng() % h);
    const int min_pts = 2 + trial % 3;
    GridDbscan db(eps, min_pts);
    const auto [pts, got] = labelled(grid, w, db.run(grid.data(), w, h, sc, sr));
    auto eps_of = [&](size_t i) {
      const double range = std::hypot(pts[i].second + 0.5 - sc, pts[i].first + 0.5 - sr);
      return std::min(eps.max_cells, eps.cells + eps.growth * range);
    };
    std::vector<char> core;
    const auto ref = reference_dbscan(pts, eps_of, min_pts, &core);
    for (size_t i = 0; i < pts.size(); ++i)
      EXPECT_EQ(got[i], ref[i]) << "trial " << trial << " cell " << pts[i].first << "," << pts[i].second;
  }
}

// Two 3-cell arcs with one empty cell between them in a row (0.2 m apart
// at 0.1 m cells): one object seen far away, where returns thin out, and
// two near the sensor. The radius 0.15 m + 0.02 m per m reaches 0.2 m at
// 2.5 m from the sensor (the nearer cell's range decides).
TEST(Dbscan, ARadiusByRangeBridgesAOneCellGapOnlyFarFromTheSensor) {
  const int w = 120, h = 10;
  auto clusters_at = [&](int c0, double sensor_col) {
    std::vector<int8_t> g(w * h, 0);
    for (int c : {c0, c0 + 1, c0 + 2, c0 + 4, c0 + 5, c0 + 6}) g[5 * w + c] = 1;
    GridDbscan db(EpsByRange{1.5, 0.02, 2.5}, 2);
    return db.run(g.data(), w, h, sensor_col, 5.5).size();
  };
  EXPECT_EQ(clusters_at(10, 5.0), 2u);            // the gap's near side 0.75 m away
  EXPECT_EQ(clusters_at(26, 5.0), 2u);            // 2.35 m
  EXPECT_EQ(clusters_at(28, 5.0), 1u);            // 2.55 m
  EXPECT_EQ(clusters_at(100, 5.0), 1u);           // 9.75 m (radius capped at 0.25 m)
  EXPECT_EQ(clusters_at(100, std::nan("")), 2u);  // sensor unknown: the radius at the sensor
}

TEST(Dbscan, TwoBlobsAndANoiseCell) {
  const int w = 20, h = 10;
  std::vector<int8_t> g(w * h, 0);
  for (int r = 2; r < 5; ++r)
    for (int c = 2; c < 5; ++c) g[r * w + c] = 1;
  for (int r = 5; r < 8; ++r)
    for (int c = 12; c < 15; ++c) g[r * w + c] = 1;
  g[9 * w + 19] = 1;
  GridDbscan db(2.5, 4);
  const auto cl = db.run(g.data(), w, h);
  ASSERT_EQ(cl.size(), 2u);
  EXPECT_EQ(cl[0].size(), 9u);
  EXPECT_EQ(cl[1].size(), 9u);
  EXPECT_EQ(db.noise_cells(), 1);
}

// ---------------------------------------------------------- Kuhn-Munkres
TEST(KuhnMunkres, OptimalAgainstAllPermutations) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.0, 10.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int rows = 1 + int(rng() % 6), cols = 1 + int(rng() % 6);
    std::vector<double> cost(rows * cols);
    for (auto& c : cost) c = U(rng);
    const auto asg = kuhn_munkres(cost, rows, cols);
    double got = 0.0;
    std::set<int> used;
    int assigned = 0;
    for (int r = 0; r < rows; ++r)
      if (asg[r] >= 0) {
        got += cost[r * cols + asg[r]];
        EXPECT_TRUE(used.insert(asg[r]).second);
        ++assigned;
      }
    EXPECT_EQ(assigned, std::min(rows, cols));
    // brute force over injective maps of the smaller side
    double best = 1e300;
    const int n = std::max(rows, cols);
    std::vector<int> perm(n);
    std::iota(perm.begin(), perm.end(), 0);
    do {
      double s = 0.0;
      for (int r = 0; r < rows; ++r)
        if (perm[r] < cols) s += cost[r * cols + perm[r]];
      best = std::min(best, s);
    } while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_NEAR(got, best, 1e-9) << rows << "x" << cols;
  }
}

// ---------------------------------------------------------------- tracker
TrackerParams params() {
  TrackerParams p;  // the values of config/robot.yaml (checked below)
  return p;
}

TEST(Config, RobotYamlTrackerSectionLoads) {
  const auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  const auto p = TrackerParams::from_config(root.section("tracker"));
  const auto d = params();
  EXPECT_DOUBLE_EQ(p.dbscan_eps_m, d.dbscan_eps_m);
  EXPECT_DOUBLE_EQ(p.dbscan_eps_growth_m_per_m, d.dbscan_eps_growth_m_per_m);
  EXPECT_DOUBLE_EQ(p.dbscan_eps_growth_max_m, d.dbscan_eps_growth_max_m);
  EXPECT_EQ(p.dbscan_min_points, d.dbscan_min_points);
  EXPECT_DOUBLE_EQ(p.gate_m, d.gate_m);
  EXPECT_EQ(p.max_missed_frames, d.max_missed_frames);
  EXPECT_EQ(p.shape_history_frames, d.shape_history_frames);
  EXPECT_EQ(p.large_cluster, d.large_cluster);
}

// The core's factory takes the whole configuration and returns the core's
// own class, as every core's does (CONTRIBUTING.md, "Add a process").
TEST(Config, TheFactoryBuildsTheCoreFromTheWholeConfig) {
  const auto root = config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  static_assert(std::is_same_v<decltype(TrackerCore::from_config(root)), std::unique_ptr<TrackerCore>>);
  const std::unique_ptr<TrackerCore> core = TrackerCore::from_config(root);
  ASSERT_NE(core, nullptr);
  EXPECT_EQ(core->name(), "tracker");
}

// A 10 x 10 m grid at 0.1 m with discs painted in (their full footprint).
struct Scene {
  double origin_x = -5, origin_y = -5, res = 0.1;
  int w = 100, h = 100;
  std::vector<int8_t> cells = std::vector<int8_t>(100 * 100, 0);
  void disc(double x, double y, double r) {
    for (int row = 0; row < h; ++row)
      for (int c = 0; c < w; ++c) {
        const double cx = origin_x + (c + 0.5) * res, cy = origin_y + (row + 0.5) * res;
        if (std::hypot(cx - x, cy - y) <= r) cells[row * w + c] = 1;
      }
  }
  void rect(double x0, double y0, double x1, double y1) {
    for (int row = 0; row < h; ++row)
      for (int c = 0; c < w; ++c) {
        const double cx = origin_x + (c + 0.5) * res, cy = origin_y + (row + 0.5) * res;
        if (cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1) cells[row * w + c] = 1;
      }
  }
  GridView view(int64_t utime) const {
    GridView g;
    g.utime = utime;
    g.origin_x = origin_x;
    g.origin_y = origin_y;
    g.resolution = res;
    g.width = w;
    g.height = h;
    g.obstacle = cells.data();
    return g;
  }
};

const TrackedObstacle* nearest(const std::vector<TrackedObstacle>& obs, double x, double y) {
  const TrackedObstacle* best = nullptr;
  double d = 1e300;
  for (const auto& o : obs) {
    const double dd = std::hypot(o.ellipse.cx - x, o.ellipse.cy - y);
    if (dd < d) d = dd, best = &o;
  }
  return best;
}

TEST(Tracker, CylinderFootprintGivesACentredEllipseWithAStableId) {
  Tracker t(params());
  int64_t id = -1;
  for (int f = 0; f < 20; ++f) {
    Scene s;
    s.disc(1.5, -2.0, 0.3);
    const auto& obs = t.update(s.view(1'000'000 + f * 100'000));
    ASSERT_EQ(obs.size(), 1u);
    EXPECT_NEAR(obs[0].ellipse.cx, 1.5, 0.05);
    EXPECT_NEAR(obs[0].ellipse.cy, -2.0, 0.05);
    EXPECT_GE(obs[0].ellipse.b, 0.3);  // encloses the disc's cells
    EXPECT_LE(obs[0].ellipse.a, 0.3 + 0.1);
    if (f == 0) id = obs[0].id;
    EXPECT_EQ(obs[0].id, id);
    EXPECT_EQ(obs[0].age, f);
    EXPECT_NEAR(obs[0].shape_variation, 0.0, 1e-12);  // the same cells every frame
  }
}

int run_crossing(double sep_y, bool expect_merge_free, const TrackerParams& p = params()) {
  // A moves +x at 1.8 m/s along y = +sep/2, B moves -x along y = -sep/2
  Tracker t(p);
  int64_t ida = -1, idb = -1;
  int frames_with_both = 0;
  for (int f = 0; f <= 30; ++f) {
    const double time = f * 0.1;
    const double xa = -2.7 + 1.8 * time, xb = 2.7 - 1.8 * time;
    Scene s;
    s.disc(xa, sep_y / 2, 0.3);
    s.disc(xb, -sep_y / 2, 0.3);
    const auto& obs = t.update(s.view(5'000'000 + f * 100'000));
    if (obs.size() != 2) {
      EXPECT_FALSE(expect_merge_free) << "frame " << f;
      continue;
    }
    ++frames_with_both;
    const auto* a = nearest(obs, xa, sep_y / 2);
    const auto* b = nearest(obs, xb, -sep_y / 2);
    EXPECT_NE(a, b);
    if (ida < 0) ida = a->id, idb = b->id;
    EXPECT_EQ(a->id, ida) << "frame " << f;
    EXPECT_EQ(b->id, idb) << "frame " << f;
  }
  EXPECT_GT(frames_with_both, 20);
  EXPECT_EQ(t.next_id(), 3);  // no other id was ever handed out
  return 31 - frames_with_both;
}

TEST(Tracker, CrossingObstaclesKeepTheirIds) { EXPECT_EQ(run_crossing(1.0, true), 0); }

TEST(Tracker, CrossingObstaclesThatMergeForAFewFramesKeepTheirIds) {
  // passing 0.5 m apart, centre to centre: the discs touch and DBSCAN sees
  // one cluster for a few frames; without the cut, one track coasts through
  auto p = params();
  p.merge.split = false;
  EXPECT_GE(run_crossing(0.5, false, p), 2);
}

TEST(Tracker, AMergedClusterIsCutIntoOneDetectionPerTrack) {
  // the same pass with the cut: two obstacles in every frame, each its own id
  EXPECT_EQ(run_crossing(0.5, true), 0);
}

TEST(Tracker, WalkersPassingThroughEachOtherKeepBothIdentities) {
  // Two walkers (0.25 m radius) head-on at 1.2 m/s, 0.1 m apart across:
  // for about 0.6 s DBSCAN sees one cluster that no cut can share out.
  // Each track moves on as predicted through it, both are published in
  // every frame (together covering the cluster), and each leaves with its
  // own walker.
  auto p = params();
  p.merge.hold_owners = true;
  Tracker t(p);
  int64_t ida = -1, idb = -1;
  for (int f = 0; f <= 50; ++f) {
    const double time = f * 0.1, xa = -3.0 + 1.2 * time, xb = 3.0 - 1.2 * time;
    Scene s;
    s.disc(xa, 0.05, 0.25);
    s.disc(xb, -0.05, 0.25);
    const auto& obs = t.update(s.view(2'000'000 + f * 100'000));
    ASSERT_EQ(obs.size(), 2u) << "frame " << f;
    for (int i = 0; i < s.w * s.h; ++i) {  // the published ellipses still cover every cell's centre
      if (!s.cells[size_t(i)]) continue;
      const Vec2 c{s.origin_x + (i % s.w + 0.5) * s.res, s.origin_y + (i / s.w + 0.5) * s.res};
      EXPECT_TRUE(ellipse_level(obs[0].ellipse, c) <= 1.0 || ellipse_level(obs[1].ellipse, c) <= 1.0)
          << "frame " << f << " cell " << i;
    }
    if (std::fabs(xa - xb) < 1.0) continue;  // overlapping: which is nearer is moot
    const auto* a = nearest(obs, xa, 0.05);
    const auto* b = nearest(obs, xb, -0.05);
    EXPECT_NEAR(a->ellipse.cx, xa, 0.1) << "frame " << f;
    if (ida < 0) ida = a->id, idb = b->id;
    EXPECT_EQ(a->id, ida) << "frame " << f;
    EXPECT_EQ(b->id, idb) << "frame " << f;
  }
  EXPECT_EQ(t.next_id(), 3);  // no other id was ever handed out
  EXPECT_GT(t.stats().merges_held, 0);
}

// Walkers as discs of 0.25 m radius, each a function of time (s) -> centre;
// 10 Hz frames from t = 0 to t_end. Returns, per walker, the ids published
// nearest to it (within 0.2 m) in frames where the walkers are at least
// 1 m apart (so which is which is not moot), in frame order.
using Path = std::function<Vec2(double)>;
std::vector<std::vector<int64_t>> walk(Tracker& t, const std::vector<Path>& walkers, double t_end,
                                       const std::function<bool(double)>& hidden = {}) {
  std::vector<std::vector<int64_t>> ids(walkers.size());
  for (int f = 0; f * 0.1 <= t_end + 1e-9; ++f) {
    const double time = f * 0.1;
    Scene s;
    std::vector<Vec2> at;
    for (const Path& w : walkers) at.push_back(w(time));
    for (size_t k = 0; k < at.size(); ++k)
      if (!(hidden && k == 0 && hidden(time))) s.disc(at[k].x, at[k].y, 0.25);
    const auto& obs = t.update(s.view(3'000'000 + f * 100'000));
    bool apart = true;
    for (size_t i = 0; i < at.size(); ++i)
      for (size_t j = i + 1; j < at.size(); ++j)
        apart = apart && std::hypot(at[i].x - at[j].x, at[i].y - at[j].y) >= 1.0;
    if (!apart) continue;
    for (size_t k = 0; k < at.size(); ++k) {
      const auto* o = nearest(obs, at[k].x, at[k].y);
      if (o && std::hypot(o->ellipse.cx - at[k].x, o->ellipse.cy - at[k].y) <= 0.2) ids[k].push_back(o->id);
    }
  }
  return ids;
}

// Walker A walks down (-y) at 1.2 m/s; walker B, 0.15 m beside its line,
// walks down too and turns round 0.3 s before they meet, so its velocity
// estimate still points down when the two are one cluster. They part with
// the ids exchanged; with `reid` the motions after the parting give them back.
std::vector<std::vector<int64_t>> turn_and_cross(const TrackerParams& p, TrackerStats* stats) {
  Tracker t(p);
  const Path a = [](double s) { return Vec2{0.05, 2.0 - 1.2 * s}; };
  const Path b = [](double s) { return Vec2{-0.1, s < 1.0 ? 0.6 - 1.2 * s : -0.6 + 1.2 * (s - 1.0)}; };
  auto ids = walk(t, {a, b}, 3.5);
  *stats = t.stats();
  return ids;
}

TEST(Tracker, WalkersCrossingAfterATurnComeOutWithSwappedIdsWithoutReid) {
  TrackerStats stats;
  const auto ids = turn_and_cross(params(), &stats);
  ASSERT_GE(ids[0].size(), 10u);
  ASSERT_GE(ids[1].size(), 10u);
  EXPECT_NE(ids[0].front(), ids[0].back());  // the scene does exchange them
  EXPECT_EQ(stats.ids_exchanged, 0);
}

TEST(Tracker, ReidGivesWalkersCrossingAfterATurnTheirOwnIdsBack) {
  auto p = params();
  p.reid.enabled = true;
  TrackerStats stats;
  const auto ids = turn_and_cross(p, &stats);
  ASSERT_GE(ids[0].size(), 10u);
  ASSERT_GE(ids[1].size(), 10u);
  for (size_t k = 0; k < 2; ++k) {
    // each walker ends with the id it started with; at most the frames
    // before the judgement (reid.frames after the parting) show the other one
    EXPECT_EQ(ids[k].front(), ids[k].back()) << "walker " << k;
    EXPECT_LE(std::count(ids[k].begin(), ids[k].end(), ids[1 - k].front()), p.reid.frames) << "walker " << k;
  }
  EXPECT_EQ(stats.ids_exchanged, 1);
}

TEST(Tracker, ReidKeepsTheIdsOfWalkersCrossingHeadOn) {
  // head-on through each other without a turn: the tracks part right, reid keeps them
  auto p = params();
  p.reid.enabled = true;
  Tracker t(p);
  const Path a = [](double s) { return Vec2{-3.0 + 1.2 * s, 0.05}; };
  const Path b = [](double s) { return Vec2{3.0 - 1.2 * s, -0.05}; };
  const auto ids = walk(t, {a, b}, 5.0);
  for (size_t k = 0; k < 2; ++k) {
    ASSERT_GE(ids[k].size(), 30u);
    EXPECT_EQ(std::count(ids[k].begin(), ids[k].end(), ids[k].front()), long(ids[k].size())) << "walker " << k;
  }
  EXPECT_EQ(t.stats().ids_exchanged, 0);
}

TEST(Tracker, ReidKeepsTheIdsOfWalkersPassingSideBySide) {
  // one overtakes the other 0.45 m beside it (the clusters touch): similar
  // motions before and after, nothing to exchange
  auto p = params();
  p.reid.enabled = true;
  Tracker t(p);
  const Path a = [](double s) { return Vec2{-3.0 + 1.5 * s, 0.225}; };
  const Path b = [](double s) { return Vec2{-1.5 + 0.9 * s, -0.225}; };
  const auto ids = walk(t, {a, b}, 4.5);
  for (size_t k = 0; k < 2; ++k) {
    ASSERT_GE(ids[k].size(), 12u);
    EXPECT_EQ(std::count(ids[k].begin(), ids[k].end(), ids[k].front()), long(ids[k].size())) << "walker " << k;
  }
  EXPECT_NE(ids[0].front(), ids[1].front());
  EXPECT_GT(t.stats().merges_split + t.stats().merges_held, 0);  // they did share a cluster
  EXPECT_EQ(t.stats().ids_exchanged, 0);
}

TEST(Tracker, ReidKeepsTheIdOfAWalkerBrieflyHiddenBesideAnother) {
  // A walks past a standing person 0.55 m away and is unseen for 0.3 s
  // just there: it comes back to its own id, the standing one keeps its own
  auto p = params();
  p.reid.enabled = true;
  Tracker t(p);
  const Path a = [](double s) { return Vec2{-3.0 + 1.2 * s, 0.55}; };
  const Path b = [](double) { return Vec2{0.0, 0.0}; };
  std::vector<std::vector<int64_t>> ids = walk(t, {a, b}, 5.0, [](double s) { return s > 2.3 && s < 2.65; });
  for (size_t k = 0; k < 2; ++k) {
    ASSERT_GE(ids[k].size(), 20u);
    EXPECT_EQ(std::count(ids[k].begin(), ids[k].end(), ids[k].front()), long(ids[k].size())) << "walker " << k;
  }
  EXPECT_EQ(t.stats().ids_exchanged, 0);
}

TEST(Tracker, OneObjectSeenInTwoPiecesIsNotCutWhenWholeAgain) {
  // a disc seen as two halves (a column of cells missing) long enough for
  // both halves to be confirmed tracks, then whole: one detection, the
  // older track's id
  Tracker t(params());
  int64_t utime = 0;
  auto frame = [&](bool gap) {
    Scene s;
    s.disc(1.0, 1.0, 0.35);
    if (gap)
      for (int row = 0; row < s.h; ++row) s.cells[row * s.w + 60] = 0;  // x in [1.0, 1.1)
    return t.update(s.view(utime += 100'000));
  };
  for (int f = 0; f < 8; ++f) ASSERT_EQ(frame(true).size(), 2u);
  for (int f = 0; f < 5; ++f) {
    const auto& obs = frame(false);
    ASSERT_EQ(obs.size(), 1u) << "frame " << f;
    EXPECT_NEAR(obs[0].ellipse.cx, 1.0, 0.06);
  }
  EXPECT_EQ(t.stats().merges_split, 0);
}

TEST(Tracker, PaperAssociationWithoutPredictionAlsoKeepsSeparatedIds) {
  auto p = params();
  p.predict_with_velocity = false;
  Tracker t(p);
  int64_t ida = -1;
  for (int f = 0; f <= 30; ++f) {
    const double x = -2.7 + 1.8 * f * 0.1;  // 0.18 m per frame < d_max
    Scene s;
    s.disc(x, 1.0, 0.3);
    s.disc(-x, -1.0, 0.3);
    const auto& obs = t.update(s.view(f * 100'000 + 1));
    ASSERT_EQ(obs.size(), 2u);
    const auto* a = nearest(obs, x, 1.0);
    if (ida < 0) ida = a->id;
    EXPECT_EQ(a->id, ida);
  }
}

TEST(Tracker, PartialOcclusionDoesNotCarryAStaticTrackAway) {
  // A static disc whose lower part is hidden for two frames (its centre
  // seems to move up 0.1 m a frame: smoothed velocity 0.75 m/s), then wholly
  // hidden for 8 frames, then seen again where it always was: same id. The
  // velocity-predicted centre is by then 0.875 m away (beyond d_max = 0.8);
  // the last centre is 0.2 m away.
  Tracker t(params());
  auto visible_above = [](double y_min) {
    Scene s;
    s.disc(2.0, 1.5, 0.3);
    for (int row = 0; row < s.h; ++row)
      for (int c = 0; c < s.w; ++c)
        if (s.origin_y + (row + 0.5) * s.res < y_min) s.cells[row * s.w + c] = 0;
    return s;
  };
  int64_t utime = 0;
  int64_t id = -1;
  for (int f = 0; f < 5; ++f) id = t.update(visible_above(0.0).view(utime += 100'000)).at(0).id;
  EXPECT_EQ(t.update(visible_above(1.4).view(utime += 100'000)).at(0).id, id);
  EXPECT_EQ(t.update(visible_above(1.6).view(utime += 100'000)).at(0).id, id);
  for (int f = 0; f < 8; ++f) EXPECT_TRUE(t.update(Scene{}.view(utime += 100'000)).empty());
  EXPECT_EQ(t.update(visible_above(0.0).view(utime += 100'000)).at(0).id, id);
}

TEST(Tracker, NearSideCorrectionMovesTheCentreTowardsTheBodysAxis) {
  // what a LiDAR at the origin sees of a 0.3 m disc at (3, 0): the near
  // half of its rim, one cell thick
  Scene s;
  for (int row = 0; row < s.h; ++row)
    for (int c = 0; c < s.w; ++c) {
      const double x = s.origin_x + (c + 0.5) * s.res, y = s.origin_y + (row + 0.5) * s.res;
      const double r = std::hypot(x - 3.0, y);
      if (x <= 3.0 && r <= 0.3 && r > 0.18) s.cells[row * s.w + c] = 1;
    }
  auto centre_error = [&](bool robot_known, Ellipse* e) {
    Tracker t(params());
    GridView g = s.view(1'000'000);
    g.has_robot = robot_known;
    const auto& obs = t.update(g);
    EXPECT_EQ(obs.size(), 1u);
    *e = obs.at(0).ellipse;
    return std::hypot(e->cx - 3.0, e->cy);
  };
  Ellipse raw, corrected;
  const double before = centre_error(false, &raw), after = centre_error(true, &corrected);
  EXPECT_GT(before, 0.1);
  EXPECT_LT(after, before - 0.05);
  EXPECT_GT(corrected.cx, raw.cx);  // moved away from the robot
  // the near side stays inside: every obstacle cell's centre is enclosed
  for (int row = 0; row < s.h; ++row)
    for (int c = 0; c < s.w; ++c)
      if (s.cells[row * s.w + c]) {
        EXPECT_LE(ellipse_level(corrected, {s.origin_x + (c + 0.5) * s.res, s.origin_y + (row + 0.5) * s.res}), 1.0);
      }
}

// A walker 0.2 m (cell centres) from a 4.5 m wall, both far from the
// robot: the radius by range joins them into one large cluster, and the
// split parts it again at the radius at the sensor, so the walker is a
// detection of its own and not part of a wall tile.
TEST(Tracker, AFarRadiusJoinsAWalkerToAWallButTheSplitPartsThemAgain) {
  Scene s;
  s.rect(0.0, 4.0, 4.5, 4.1);  // one row of cells, centres at y 4.05
  s.disc(2.05, 3.6, 0.26);     // topmost cell centre 3.85
  TrackerStats st;
  auto run = [&](double growth, double robot_x, double robot_y) {
    auto p = params();
    p.dbscan_eps_growth_m_per_m = growth;
    p.dbscan_eps_growth_max_m = 0.1;
    Tracker t(p);
    GridView g = s.view(1'000'000);
    g.has_robot = true, g.robot_x = robot_x, g.robot_y = robot_y;
    const std::vector<TrackedObstacle> obs = t.update(g);
    st = t.stats();
    return obs;
  };
  const auto far = run(0.0135, -4.5, -4.5);  // about 10 m: radius 0.25 m
  EXPECT_EQ(st.clusters, 1);                 // one cluster, wall and walker
  EXPECT_EQ(st.large_clusters, 1);
  const TrackedObstacle* w = nearest(far, 2.05, 3.6);
  ASSERT_NE(w, nullptr);
  EXPECT_LT(std::hypot(w->ellipse.cx - 2.05, w->ellipse.cy - 3.6), 0.1);
  EXPECT_LT(w->ellipse.a, 0.4);
  const auto fixed = run(0.0, -4.5, -4.5);  // the fixed radius keeps them apart from the start
  EXPECT_EQ(st.clusters, 2);
  const TrackedObstacle* wf = nearest(fixed, 2.05, 3.6);
  ASSERT_NE(wf, nullptr);
  EXPECT_NEAR(wf->ellipse.cx, w->ellipse.cx, 1e-9);
  EXPECT_NEAR(wf->ellipse.cy, w->ellipse.cy, 1e-9);
  run(0.0135, 2.05, 2.0);  // 1.6 m away: radius 0.17 m, apart
  EXPECT_EQ(st.clusters, 2);
}

TEST(Tracker, TracksDropAfterKMissedFramesAndIdsAreNeverReused) {
  auto p = params();
  p.max_missed_frames = 5;
  Tracker t(p);
  Scene with;
  with.disc(0.0, 2.0, 0.3);
  Scene without;
  int64_t utime = 1'000'000;
  const int64_t first = t.update(with.view(utime += 100'000))[0].id;
  for (int k = 1; k <= 5; ++k) {
    EXPECT_TRUE(t.update(without.view(utime += 100'000)).empty());
    EXPECT_EQ(t.num_tracks(), 1u) << k;
  }
  // back within K frames: same id
  EXPECT_EQ(t.update(with.view(utime += 100'000))[0].id, first);
  for (int k = 1; k <= 6; ++k) t.update(without.view(utime += 100'000));
  EXPECT_EQ(t.num_tracks(), 0u);  // 6 > K missed: gone
  const int64_t again = t.update(with.view(utime += 100'000))[0].id;
  EXPECT_GT(again, first);  // same place, new obstacle, new id
}

TEST(Tracker, TimeGoingBackwardsStartsOverWithFreshIds) {
  Tracker t(params());
  Scene s;
  s.disc(1.0, 1.0, 0.3);
  const int64_t first = t.update(s.view(10'000'000)).at(0).id;
  EXPECT_EQ(t.update(s.view(10'100'000)).at(0).id, first);
  const int64_t after = t.update(s.view(5'000'000)).at(0).id;  // a log loop
  EXPECT_EQ(t.stats().time_reset, 1);
  EXPECT_GT(after, first);
  EXPECT_EQ(t.update(s.view(5'100'000)).at(0).id, after);
}

TEST(Tracker, LongClutterRunKeepsMemoryBounded) {
  auto p = params();
  p.max_tracks = 64;
  Tracker t(p);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> pos(-4.5, 4.5);
  size_t max_tracks_seen = 0, max_second_half = 0;
  size_t heap_at_2000 = 0;  // bytes the allocator has handed out (mallinfo2): memory, not just the table
  for (int f = 0; f < 10'000; ++f) {
    if (f == 2000) heap_at_2000 = mallinfo2().uordblks;
    Scene s;
    const int n = int(rng() % 12);
    for (int k = 0; k < n; ++k) s.disc(pos(rng), pos(rng), 0.15 + 0.2 * (rng() % 3));
    for (int k = 0; k < 30; ++k) s.cells[rng() % s.cells.size()] = 1;  // speckle
    // a 4 m wall every 500 frames: the large-cluster path (tiles, and with a
    // radius by range its second DBSCAN, whose buffers are the grid's size)
    // has run before the heap is first read
    if (f % 500 == 0) s.rect(-2.0, 4.6, 2.0, 4.8);
    t.update(s.view(1 + int64_t(f) * 100'000));
    max_tracks_seen = std::max(max_tracks_seen, t.num_tracks());
    if (f >= 5000) max_second_half = std::max(max_second_half, t.num_tracks());
  }
  // at most 12 detections a frame, each track lives at most K + 1 frames unseen
  EXPECT_LE(max_tracks_seen, size_t(12 * (p.max_missed_frames + 1)));
  EXPECT_LE(max_tracks_seen, size_t(p.max_tracks));
  EXPECT_LE(max_second_half, max_tracks_seen);
  EXPECT_GT(t.next_id(), 10'000);           // ids kept growing, none reused, no overflow at 100 labels
  EXPECT_GE(t.stats().large_clusters, 20);  // every wall frame
  const long long growth = static_cast<long long>(mallinfo2().uordblks) - static_cast<long long>(heap_at_2000);
  std::printf("[figures] tracker heap, frame 2000 -> 10000: %zu -> %zu bytes (%+lld)\n", heap_at_2000,
              mallinfo2().uordblks, growth);
  EXPECT_LT(growth, 64 * 1024);  // flat: 8000 more frames add no more than scratch-buffer slack
}

TEST(Tracker, TrackTableNeverExceedsItsLimit) {
  auto p = params();
  p.max_tracks = 5;
  Tracker t(p);
  Scene s;
  for (int k = 0; k < 9; ++k) s.disc(-4 + k, 0, 0.2);
  const auto& obs = t.update(s.view(100));
  EXPECT_EQ(obs.size(), 5u);
  EXPECT_EQ(t.num_tracks(), 5u);
  EXPECT_EQ(t.stats().over_track_limit, 4);
}

TEST(ShapeVariation, KnownAnswers) {
  std::deque<Ellipse> h;
  for (int i = 0; i < 4; ++i) h.push_back(Ellipse{0, 0, i % 2 ? 1.2 : 1.0, 0.5, 0.3});
  // a alternates 1.0, 1.2: mean 1.1, four deviations of 0.1 -> 0.04 / (4 - 1)
  EXPECT_NEAR(shape_variation(h, ThetaVariation::kRaw), 0.04 / 3, 1e-12);
  EXPECT_NEAR(shape_variation(h, ThetaVariation::kBoundary), 0.04 / 3, 1e-12);
  // theta is an axis: -pi/2 + 0.05 and pi/2 - 0.05 are 0.1 rad apart, not 3.04
  std::deque<Ellipse> t = {Ellipse{0, 0, 1.0, 0.5, -M_PI / 2 + 0.05}, Ellipse{0, 0, 1.0, 0.5, M_PI / 2 - 0.05}};
  EXPECT_NEAR(shape_variation(t, ThetaVariation::kRaw), 2 * 0.05 * 0.05, 1e-12);
  EXPECT_NEAR(shape_variation(t, ThetaVariation::kBoundary), 2 * 0.025 * 0.025, 1e-12);
  // a circle's axis is meaningless: with kBoundary its jitter costs nothing
  std::deque<Ellipse> c = {Ellipse{0, 0, 0.3, 0.3, 0.0}, Ellipse{0, 0, 0.3, 0.3, 1.0}};
  EXPECT_NEAR(shape_variation(c, ThetaVariation::kBoundary), 0.0, 1e-12);
  EXPECT_GT(shape_variation(c, ThetaVariation::kRaw), 0.4);
  EXPECT_EQ(shape_variation(std::deque<Ellipse>(1), ThetaVariation::kRaw), 0.0);
}

TEST(ShapeVariation, UsesOnlyTheLastMFrames) {
  auto p = params();
  p.shape_history_frames = 4;
  Tracker t(p);
  for (int f = 0; f < 12; ++f) {
    Scene s;
    s.disc(0.0, 0.0, f < 6 ? 0.5 : 0.3);  // a changes at frame 6, then stays
    const auto& obs = t.update(s.view(1 + f * 100'000));
    ASSERT_EQ(obs.size(), 1u);
    if (f == 6) {
      EXPECT_GT(obs[0].shape_variation, 0.001);
    }
    if (f >= 9) {
      EXPECT_NEAR(obs[0].shape_variation, 0.0, 1e-12) << f;
    }
  }
}

TEST(Tracker, LargeClustersFollowThePolicy) {
  Scene wall;
  wall.rect(-3.0, 1.0, 2.0, 1.2);  // a 5 m wall
  auto p = params();
  p.large_cluster = LargeClusterPolicy::kKeep;
  {
    Tracker t(p);
    const auto& o = t.update(wall.view(1));
    ASSERT_EQ(o.size(), 1u);
    EXPECT_GT(o[0].ellipse.a, 2.5);
  }
  p.large_cluster = LargeClusterPolicy::kDrop;
  {
    Tracker t(p);
    EXPECT_TRUE(t.update(wall.view(1)).empty());
    EXPECT_EQ(t.stats().large_dropped, 1);
  }
  p.large_cluster = LargeClusterPolicy::kSplit;
  p.split_tile_m = 1.5;
  {
    Tracker t(p);
    const auto& o = t.update(wall.view(1));
    EXPECT_EQ(o.size(), 4u);  // x tiles [-4.5,-3), [-3,-1.5), [-1.5,0), [0,1.5), [1.5,3) minus the empty first
    for (const auto& e : o) EXPECT_LT(e.ellipse.a, 1.5);
  }
}

// ---------------------------------------------------------------- core
TEST(Core, PublishesObstaclesStampedWithTheMapTime) {
  bus::MemoryBus bus;
  auto p = params();
  p.near_side_shift_b = 0.0;  // a painted full disc, not a LiDAR's near side
  TrackerCore core(p);
  bus.add(core);
  Scene s;
  s.disc(1.0, 1.0, 0.3);
  evade::grid_map_t m;
  m.utime = 4242;
  m.origin[0] = s.origin_x;
  m.origin[1] = s.origin_y;
  m.resolution = s.res;
  m.width = s.w;
  m.height = s.h;
  m.robot_x = m.robot_y = m.robot_yaw = 0;
  m.elevation.assign(s.h, std::vector<float>(s.w, 0.0f));
  m.obstacle.resize(s.h);
  for (int r = 0; r < s.h; ++r) m.obstacle[r].assign(s.cells.begin() + r * s.w, s.cells.begin() + (r + 1) * s.w);
  bus.inject("ELEVATION_MAP", m, 10'000);
  auto out = bus.decoded<evade::obstacle_list_t>("OBSTACLES");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].utime, 4242);
  ASSERT_EQ(out[0].num_obstacles, 1);
  EXPECT_EQ(out[0].obstacles[0].id, 1);
  EXPECT_NEAR(out[0].obstacles[0].x, 1.0, 0.05);
  EXPECT_GE(out[0].obstacles[0].a, out[0].obstacles[0].b);
  m.resolution = -1;  // malformed: counted, skipped
  bus.inject("ELEVATION_MAP", m, 20'000);
  EXPECT_EQ(core.counter("map_invalid"), 1);
  m.resolution = 1e-6;  // eps would span 150,000 cells
  bus.inject("ELEVATION_MAP", m, 30'000);
  EXPECT_EQ(core.counter("map_resolution_unsupported"), 1);
  const uint8_t junk[5] = {9, 9, 9, 9, 9};  // not a grid_map_t at all
  bus.inject("ELEVATION_MAP", junk, sizeof junk, 40'000);
  EXPECT_EQ(bus.decoded<evade::obstacle_list_t>("OBSTACLES").size(), 1u);
}

}  // namespace
}  // namespace evade::tracking
