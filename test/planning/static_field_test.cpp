// Static structure by its true shape (static_field.h): the distance
// transform, a jackal-sized robot through a doorway of its width + 0.3 m
// whose edges' ellipses close the gap, every footprint disc kept d_safe
// clear of the static cells, moving tracks' cells left out, and the
// planner without a map (or with a stale one) back on the ellipses.
#include "planning/static_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "box_map.h"
#include "bus/log.h"
#include "bus/memory_bus.h"
#include "config/config.h"
#include "drive_harness.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/params.h"
#include "planning/planner_core.h"

namespace evade::planning {
namespace {

using testing::Box;

PlannerParams jackal_params() {
  PlannerParams p = PlannerParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
  p.footprint = Footprint::covering(0.46, 0.42, p.footprint_discs);  // config/robots/jackal.yaml
  p.static_field.enabled = true;                                     // off by default (robot.yaml)
  return p;
}

// A wall across the route at x in [3.0, 3.2] with a gap of `gap` m centred
// on y = 0, from y = -6 to 6.
std::vector<Box> doorway(double gap) { return {{3.0, 3.2, -6.0, -0.5 * gap}, {3.0, 3.2, 0.5 * gap, 6.0}}; }

// The map as the elevation map marks it: every cell a box overlaps.
evade::grid_map_t map_of(const std::vector<Box>& boxes, int64_t utime) { return testing::box_map(boxes, utime, 1.5f); }

// The tracker's view of the boxes: 1.5 m tiles, each in the minimum
// bounding ellipse of its rectangle (semi-axes sqrt(2) x half-sides).
std::vector<Ellipse> tiles(const std::vector<Box>& boxes) {
  std::vector<Ellipse> out;
  for (const Box& b : boxes)
    for (double y = b.y0; y < b.y1 - 1e-9; y += 1.5) {
      const double y1 = std::min(b.y1, y + 1.5);
      out.push_back({0.5 * (b.x0 + b.x1), 0.5 * (y + y1), std::sqrt(2.0) * 0.5 * (y1 - y),
                     std::sqrt(2.0) * 0.5 * (b.x1 - b.x0), M_PI / 2});
    }
  return out;
}

evade::prediction_list_t predictions_of(const std::vector<Ellipse>& es, int64_t utime) {
  evade::prediction_list_t m;
  m.utime = utime;
  m.dt = 0.1;
  m.horizon = 26;
  for (size_t i = 0; i < es.size(); ++i) {
    evade::track_prediction_t t;
    t.id = static_cast<int64_t>(i) + 1;
    t.vx = t.vy = t.ax = t.ay = 0;
    t.horizon = m.horizon;
    t.x.assign(m.horizon, es[i].x);
    t.y.assign(m.horizon, es[i].y);
    t.a.assign(m.horizon, es[i].a);
    t.b.assign(m.horizon, es[i].b);
    t.theta.assign(m.horizon, es[i].theta);
    t.sigma.assign(m.horizon, 0.0);
    m.tracks.push_back(t);
  }
  m.num_tracks = static_cast<int32_t>(m.tracks.size());
  return m;
}

evade::obstacle_list_t observed_of(const std::vector<Ellipse>& es, int64_t utime) {
  evade::obstacle_list_t m;
  m.utime = utime;
  for (size_t i = 0; i < es.size(); ++i) {
    evade::obstacle_t o{};
    o.id = static_cast<int64_t>(i) + 1;
    o.x = es[i].x;
    o.y = es[i].y;
    o.a = es[i].a;
    o.b = es[i].b;
    o.theta = es[i].theta;
    m.obstacles.push_back(o);
  }
  m.num_obstacles = static_cast<int32_t>(m.obstacles.size());
  return m;
}

// Distance from (x, y) to the nearest obstacle cell's square of map m.
double distance_to_cells(const evade::grid_map_t& m, double x, double y) {
  double best = 1e9;
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c) {
      if (!m.obstacle[r][c]) continue;
      const double x0 = m.origin[0] + c * m.resolution, y0 = m.origin[1] + r * m.resolution;
      const double dx = std::max({x0 - x, 0.0, x - (x0 + m.resolution)});
      const double dy = std::max({y0 - y, 0.0, y - (y0 + m.resolution)});
      best = std::min(best, std::hypot(dx, dy));
    }
  return best;
}

// The smallest over the footprint's discs of the distance to the cells
// less the disc's radius.
double disc_clearance(const evade::grid_map_t& m, const Footprint& fp, double x, double y, double yaw) {
  double best = 1e9;
  for (double off : fp.offsets)
    best = std::min(best, distance_to_cells(m, x + off * std::cos(yaw), y + off * std::sin(yaw)) - fp.radius);
  return best;
}

struct DoorRun {
  double final_x = 0;
  double min_body_clearance = 1e9;  // executed poses, every 0.02 s
  double min_plan_clearance = 1e9;  // the states of every OK plan, at its steps
  std::vector<evade::plan_t> plans;
  int64_t stale = 0, fields = 0;
};

// Closed loop (DriveHarness): odometry at 50 Hz, the map, OBSTACLES
// and predictions at 10 Hz (maps only before `maps_until_s`), the robot
// follows CMD_VEL exactly.
// `cart`: a 1.2 x 0.4 m box at (1.5, 2.0) that rolls at 0.5 m/s along x
// until cart_stops_s, then stands (its track id: the last).
DoorRun run_door(const PlannerParams& p, double gap, double duration_s, double maps_until_s = 1e9,
                 double cart_stops_s = -1.0) {
  std::vector<Box> boxes = doorway(gap);
  std::vector<Ellipse> es = tiles(boxes);
  const size_t walls = boxes.size(), tiles_n = es.size();
  testing::DriveHarness loop(p);
  const testing::RobotState& robot = loop.robot();
  DoorRun out;
  const int64_t t0 = testing::DriveHarness::kStartUs;
  evade::path_t route;
  route.n = 2;
  route.x = {0.0, 7.0};
  route.y = {0.0, 0.0};
  loop.bus().inject("ROUTE", route, t0);
  const evade::grid_map_t truth = map_of(boxes, t0);
  loop.run(
      duration_s,
      [&](const testing::DriveHarness::Step& s) {
        if (s.i % 5 != 0) return;
        boxes.resize(walls);
        es.resize(tiles_n);
        double cart_v = 0.0;
        if (cart_stops_s >= 0) {
          cart_v = s.t < cart_stops_s ? 0.5 : 0.0;
          const double cx = 1.5 + 0.5 * std::min(s.t, cart_stops_s);
          boxes.push_back({cx - 0.6, cx + 0.6, 1.8, 2.2});
          es.push_back({cx, 2.0, 0.85, 0.28, 0.0});
        }
        if (s.t < maps_until_s) loop.bus().inject("ELEVATION_MAP", map_of(boxes, s.now), s.now);
        loop.bus().inject("OBSTACLES", observed_of(es, s.now), s.now);
        evade::prediction_list_t pred = predictions_of(es, s.now);
        if (cart_stops_s >= 0) pred.tracks.back().vx = cart_v;
        loop.bus().inject("OBSTACLE_PREDICTIONS", pred, s.now);
      },
      [&](const evade::plan_t& pl, const testing::DriveHarness::Step&) { out.plans.push_back(pl); },
      [&](const testing::DriveHarness::Step&) {
        if (std::fabs(robot.x - 3.1) < 1.0)
          out.min_body_clearance =
              std::min(out.min_body_clearance, disc_clearance(truth, p.footprint, robot.x, robot.y, robot.yaw));
      });
  for (const auto& pl : out.plans) {
    if (pl.status != evade::plan_t::STATUS_OK) continue;
    for (size_t k = 1; k < pl.x.size(); ++k)
      if (std::fabs(pl.x[k] - 3.1) < 0.8)
        out.min_plan_clearance =
            std::min(out.min_plan_clearance, disc_clearance(truth, p.footprint, pl.x[k], pl.y[k], pl.yaw[k]));
  }
  out.final_x = robot.x;
  out.stale = loop.core().counter("static_map_stale");
  out.fields = loop.core().counter("static_field");
  return out;
}

bool has_id(const evade::plan_t& pl, int64_t id) {
  return std::find(pl.obstacle_id.begin(), pl.obstacle_id.end(), id) != pl.obstacle_id.end();
}

TEST(StaticField, DistanceTransformIsExact) {
  std::mt19937 rng(7);
  const int W = 23, H = 17;
  std::vector<char> site(W * H, 0);
  for (auto& s : site) s = (rng() % 13) == 0;
  const std::vector<double> d = squared_distance_2d(site, W, H);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      double best = 1e12;
      for (int rr = 0; rr < H; ++rr)
        for (int cc = 0; cc < W; ++cc)
          if (site[rr * W + cc]) best = std::min(best, double((r - rr) * (r - rr) + (c - cc) * (c - cc)));
      EXPECT_DOUBLE_EQ(d[r * W + c], best) << r << "," << c;
    }
}

// A 24 x 24 m map at 0.1 m (origin (-12, -12)) with the robot at (0, 0):
// walls crossing the window's edges, a wall of which less than
// min_structure_m lies inside the window's cells, a wall a mover stands
// against (its cells inside a kept ellipse), a mover's cells, a bin and
// scattered short patches; every cell an obstacle cell of a box.
evade::grid_map_t window_test_map() {
  evade::grid_map_t m{};
  m.resolution = 0.1;
  m.width = m.height = 240;
  m.origin[0] = m.origin[1] = -12.0;
  m.elevation.assign(240, std::vector<float>(240, 0.0f));
  m.obstacle.assign(240, std::vector<int8_t>(240, 0));
  const auto box = [&](double x0, double x1, double y0, double y1) {
    for (int r = 0; r < 240; ++r)
      for (int c = 0; c < 240; ++c) {
        const double x = -12.0 + (c + 0.5) * 0.1, y = -12.0 + (r + 0.5) * 0.1;
        if (x > x0 && x < x1 && y > y0 && y < y1) m.obstacle[r][c] = 1;
      }
  };
  box(-11.0, 11.0, 2.0, 2.2);    // a wall across the window, through both edges
  box(5.6, 11.5, -0.6, -0.4);    // a wall whose first 0.5 m only lie inside the window's cells
  box(5.8, 5.9, -3.0, -1.0);     // a wall 30 cells beyond the last cell a read at the robot's reach touches
  box(-1.8, -1.6, -11.0, -0.4);  // a wall from below, ending 0.4 m under the robot
  box(1.0, 1.3, -1.0, -0.7);     // a bin (no structure)
  box(-3.1, -2.8, 1.7, 2.0);     // a walker against the wall (a mover; the wall's cells kept)
  box(2.0, 2.3, -2.3, -2.0);     // a walker in the open (a mover)
  std::mt19937 rng(11);
  for (int i = 0; i < 60; ++i) {  // scattered short patches and some longer pieces, away from (0, 0)
    const double x = -11.5 + 23.0 * (rng() % 1000) / 1000.0, y = -11.5 + 23.0 * (rng() % 1000) / 1000.0;
    const double len = 0.2 + 1.6 * (rng() % 100) / 100.0;
    if (std::fabs(x) < 7.0 && std::fabs(y) < 7.0) continue;
    if (rng() % 2)
      box(x, x + len, y, y + 0.15);
    else
      box(x, x + 0.15, y, y + len);
  }
  return m;
}

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(StaticField, WindowReadsWhatTheWholeMapReads) {
  const PlannerParams pp = jackal_params();
  const double reach = static_field_reach_m(pp);
  EXPECT_NEAR(reach, 25 * 0.1 * 1.0 + (0.46 / 2 - 0.46 / 6) + 0.05, 1e-9);
  const evade::grid_map_t m = window_test_map();
  const std::vector<Ellipse> movers{{-2.95, 1.85, 0.25, 0.25, 0.0}, {2.15, -2.15, 0.25, 0.25, 0.0}};
  const std::vector<Ellipse> keep{{-3.0, 2.1, 1.5, 0.3, 0.0}, {1.15, -0.85, 0.3, 0.3, 0.0}, {8.0, -0.5, 2.0, 0.3, 0.0}};
  const StaticFieldParams& sp = pp.static_field;
  const auto whole = StaticField::build(m, movers, keep, sp);
  ASSERT_TRUE(whole);
  // the wall that barely enters the window is structure, the bin is not
  double gx, gy;
  EXPECT_LT(whole->distance(8.0, -0.5, &gx, &gy), 0.0);
  EXPECT_GT(whole->distance(1.15, -0.85, &gx, &gy), 0.5);
  // robots at the map's centre, near its edge and corner, and off it
  for (const auto& [x0, y0] :
       std::vector<std::pair<double, double>>{{0.0, 0.0}, {0.37, -0.21}, {-10.6, 3.3}, {11.2, 11.7}, {13.0, 0.0}}) {
    // the robot's reach, and with the route 5 m ahead of it (the detour's)
    FieldWindow ahead = FieldWindow::around(x0, y0, reach);
    ahead.include(x0 + 5.0, y0 - 1.0);
    const auto with_route = StaticField::build(m, movers, keep, sp, ahead);
    const auto win = StaticField::build(m, movers, keep, sp, FieldWindow::around(x0, y0, reach));
    ASSERT_TRUE(win && with_route);
    EXPECT_EQ(win->static_cells(), whole->static_cells());
    int compared = 0;
    for (double y = ahead.y0; y <= ahead.y1; y += 0.0123)
      for (double x = ahead.x0; x <= ahead.x1; x += 0.0123) {
        double wgx, wgy, hgx, hgy;
        const double h = whole->distance(x, y, &hgx, &hgy);
        double w = with_route->distance(x, y, &wgx, &wgy);
        ASSERT_TRUE(same(w, h) && same(wgx, hgx) && same(wgy, hgy)) << x << ", " << y << ": " << w << " " << h;
        if (std::fabs(x - x0) > reach || std::fabs(y - y0) > reach) continue;
        w = win->distance(x, y, &wgx, &wgy);
        ASSERT_TRUE(same(w, h) && same(wgx, hgx) && same(wgy, hgy)) << x << ", " << y << ": " << w << " " << h;
        ++compared;
      }
    EXPECT_GT(compared, 180000);
    // every pose whose discs lie within the reach
    std::mt19937 rng(3);
    for (int i = 0; i < 2000; ++i) {
      const double r = (reach - 0.2) * (rng() % 1000) / 1000.0, a = 2 * M_PI * (rng() % 1000) / 1000.0;
      const double yaw = 2 * M_PI * (rng() % 1000) / 1000.0;
      const BarrierValue bw = win->footprint_barrier(x0 + r * std::cos(a), y0 + r * std::sin(a), yaw, pp.footprint);
      const BarrierValue bh = whole->footprint_barrier(x0 + r * std::cos(a), y0 + r * std::sin(a), yaw, pp.footprint);
      ASSERT_TRUE(same(bw.h, bh.h) && same(bw.gx, bh.gx) && same(bw.gy, bh.gy) && same(bw.gth, bh.gth));
    }
    // beyond the reach: far, no gradient; the detour's reads: the whole map's
    for (double x = -13.0; x <= 13.0; x += 0.173) {
      const double y = y0 + reach + 0.01 + 0.3 * std::fabs(x);
      double hgx, hgy;
      EXPECT_EQ(win->distance(x, y, &gx, &gy), sp.max_distance_m);
      EXPECT_EQ(gx, 0.0);
      EXPECT_EQ(gy, 0.0);
      const double w = win->map_distance(x, y, &gx, &gy), h = whole->distance(x, y, &hgx, &hgy);
      ASSERT_TRUE(same(w, h) && same(gx, hgx) && same(gy, hgy)) << x << ", " << y;
    }
    // which tracks the field stands for does not depend on the window
    for (const Ellipse& e : keep) {
      EXPECT_EQ(win->structure_extent(e), whole->structure_extent(e));
      EXPECT_EQ(win->own_cells(e).structure_share, whole->own_cells(e).structure_share);
      EXPECT_EQ(win->own_cells(e).structure_extent_m, whole->own_cells(e).structure_extent_m);
    }
  }
  EXPECT_FALSE(StaticField::build(m, movers, keep, sp, {1.0, 0.0, 0.0, 1.0}));
  EXPECT_FALSE(StaticField::build(m, movers, keep, sp, {NAN, 1.0, 0.0, 1.0}));
}

TEST(StaticField, SignedDistanceIsZeroOnTheCellsEdgeAndAMoversCellsAreLeftOut) {
  StaticFieldParams sp;
  const evade::grid_map_t m = map_of({{3.0, 3.2, -6.0, 6.0}, {1.0, 1.2, -0.1, 0.1}}, 0);
  // the small box is a mover's: left out; the wall stays
  const Ellipse mover{1.1, 0.0, 0.15, 0.15, 0.0};
  const auto f = StaticField::build(m, {mover}, {}, sp);
  ASSERT_TRUE(f);
  double gx, gy;
  EXPECT_NEAR(f->distance(2.5, 0.05, &gx, &gy), 0.5, 0.02);  // in front of the wall's face at x = 3.0
  EXPECT_LT(gx, -0.9);                                       // pointing away from it
  EXPECT_NEAR(f->distance(3.0, 0.05, &gx, &gy), 0.0, 0.02);
  EXPECT_LT(f->distance(3.1, 0.05, &gx, &gy), -0.04);  // inside: negative
  EXPECT_GT(f->distance(1.1, 0.05, &gx, &gy), 1.5);    // the mover's cells are not static
  // a mover at the wall: the wall's cells inside a static track's ellipse
  // that holds structure stay static
  const Ellipse at_wall{3.1, 0.0, 0.15, 0.15, 0.0}, wall{3.1, 0.0, 6.0, 0.2, M_PI / 2};
  EXPECT_GT(StaticField::build(m, {at_wall}, {}, sp)->distance(3.1, 0.05, &gx, &gy), 0.0);
  EXPECT_LT(StaticField::build(m, {at_wall}, {wall}, sp)->distance(3.1, 0.05, &gx, &gy), 0.0);
}

TEST(StaticField, AJackalGoesThroughAGapOfItsWidthPlus30cmWhoseEdgesEllipsesCloseIt) {
  const PlannerParams p = jackal_params();
  const double gap = 0.42 + 0.3;
  const DoorRun r = run_door(p, gap, 20.0);
  EXPECT_GT(r.final_x, 5.0) << "stopped at the door";
  EXPECT_GT(r.min_body_clearance, 0.0);
  EXPECT_GT(r.fields, 100);
  // the same door by the tracks' ellipses alone: the robot does not get through
  PlannerParams ellipses = p;
  ellipses.static_field.enabled = false;
  EXPECT_LT(run_door(ellipses, gap, 20.0).final_x, 3.0);
}

TEST(StaticField, EveryDiscOfEveryPlanKeepsDSafeFromTheStaticCells) {
  const PlannerParams p = jackal_params();
  const DoorRun r = run_door(p, 0.42 + 0.3, 20.0);
  ASSERT_GT(r.final_x, 5.0);
  EXPECT_GE(r.min_plan_clearance, p.static_field.d_safe_m - 2e-3);
  EXPECT_LT(r.min_plan_clearance, p.static_field.d_safe_m + 0.05);  // the door made the constraint active
}

TEST(StaticField, APersonOrABinStandingAloneIsNotStructure) {
  const evade::grid_map_t m = map_of({{3.0, 3.2, -6.0, 6.0}, {1.0, 1.4, -0.2, 0.2}}, 0);
  const auto f = StaticField::build(m, {}, {}, StaticFieldParams{});
  EXPECT_EQ(f->structure_extent({1.2, 0.0, 0.3, 0.3, 0.0}), 0.0);  // its ellipse stays
  double gx, gy;
  EXPECT_GT(f->distance(1.2, 0.0, &gx, &gy), 1.5);  // and its cells are not in the field
  EXPECT_NEAR(f->structure_extent({3.1, 1.0, 1.06, 0.14, M_PI / 2}), 12.0, 1e-6);
  EXPECT_EQ(f->structure_extent({0.0, 0.0, 0.3, 0.3, 0.0}), 0.0);
}

TEST(StaticField, ACartIsItsEllipseWhileItRollsAndItsCellsOnceItStands) {
  const PlannerParams p = jackal_params();
  // the cart rolls for 1 s, then stands: a patch of 1.2 m, slow and
  // tracked long, so its cells stand for it (a wall's tile whose centre
  // jumped for a moment is structure again as soon as it reads slow)
  const DoorRun r = run_door(p, 0.42 + 0.3, 4.0, 1e9, 1.0);
  const int64_t cart = static_cast<int64_t>(tiles(doorway(0.72)).size()) + 1;
  int rolling = 0, standing = 0;
  for (const auto& pl : r.plans) {
    if (pl.obstacle_id.empty()) continue;
    const double t = (pl.utime - 1'000'000) * 1e-6;
    if (t < 0.9) {
      EXPECT_TRUE(has_id(pl, cart)) << t;
      ++rolling;
    } else if (t > 1.5) {
      EXPECT_FALSE(has_id(pl, cart)) << t;
      EXPECT_TRUE(has_id(pl, kStaticFieldId)) << t;
      ++standing;
    }
  }
  EXPECT_GT(rolling, 3);
  EXPECT_GT(standing, 5);
}

TEST(StaticField, WithoutAMapOrWithAStaleOneTheStaticTracksAreEllipsesAgain) {
  const PlannerParams p = jackal_params();
  // maps for the first 2 s only: then the field goes stale, the tracks' ellipses come back
  const DoorRun r = run_door(p, 0.42 + 0.3, 4.0, 2.0);
  ASSERT_GT(r.plans.size(), 30u);
  bool field_seen = false;
  for (const auto& pl : r.plans) {
    const double t = (pl.utime - 1'000'000) * 1e-6;
    if (pl.obstacle_id.empty()) continue;  // a plan made without solving
    if (t > 1.5 && t < 2.0) {
      EXPECT_TRUE(has_id(pl, kStaticFieldId)) << t;
      EXPECT_FALSE(has_id(pl, 4) || has_id(pl, 5)) << t;  // the static tiles beside the gap: by their cells
      field_seen = true;
    }
    if (t > 2.0 + p.static_field.map_max_age_s + 0.05) {
      EXPECT_FALSE(has_id(pl, kStaticFieldId)) << t;
      EXPECT_TRUE(has_id(pl, 4) && has_id(pl, 5)) << t;  // the tiles beside the gap by their ellipses
    }
  }
  EXPECT_TRUE(field_seen);
  EXPECT_GT(r.stale, 5);
  // never a map: always the ellipses
  const DoorRun none = run_door(p, 0.42 + 0.3, 2.0, -1.0);
  for (const auto& pl : none.plans) EXPECT_FALSE(has_id(pl, kStaticFieldId));
  EXPECT_GT(none.stale, 5);
}

}  // namespace
}  // namespace evade::planning
