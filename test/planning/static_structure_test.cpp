// The planner's static structure state (static_structure.h): which cells
// make the field (structure patches only, movers' cells left out), which
// tracks it stands for, the map it is built from, and what it does to a
// problem's obstacles.
#include "planning/static_structure.h"

#include <gtest/gtest.h>

#include <cmath>

#include "box_map.h"

namespace evade::planning {
namespace {

using testing::Box;

constexpr int64_t kT0 = 10'000'000;

// The map as the elevation map marks it: every cell a box overlaps.
evade::grid_map_t map_of(const std::vector<Box>& boxes, int64_t utime) { return testing::box_map(boxes, utime, 0.0f); }

evade::track_prediction_t track(int64_t id, const Ellipse& e, double vx) {
  evade::track_prediction_t t;
  t.id = id;
  t.vx = vx;
  t.vy = t.ax = t.ay = 0;
  t.horizon = 3;
  for (int k = 0; k < t.horizon; ++k) {
    t.x.push_back(e.x + vx * 0.1 * k);
    t.y.push_back(e.y);
    t.a.push_back(e.a);
    t.b.push_back(e.b);
    t.theta.push_back(e.theta);
    t.sigma.push_back(0.0);
  }
  return t;
}

// A scene of tracks, all listed for 5 s, `seen` of them in OBSTACLES.
struct Scene {
  evade::prediction_list_t predictions;
  evade::obstacle_list_t observed;
  void add(int64_t id, const Ellipse& e, double vx, bool seen = true) {
    predictions.tracks.push_back(track(id, e, vx));
    predictions.num_tracks = static_cast<int32_t>(predictions.tracks.size());
    if (!seen) return;
    evade::obstacle_t o{};
    o.id = id;
    o.x = e.x;
    o.y = e.y;
    o.a = e.a;
    o.b = e.b;
    o.theta = e.theta;
    observed.obstacles.push_back(o);
    observed.num_obstacles = static_cast<int32_t>(observed.obstacles.size());
  }
  StaticStructure::Inputs inputs(int64_t odometry_utime) const {
    StaticStructure::Inputs in;
    in.odometry_utime = odometry_utime;
    in.predictions = &predictions;
    in.observed = &observed;
    in.track_age_s = [](int64_t) { return 5.0; };
    return in;
  }
};

// A wall along x = 3.0..3.2 from y = -6 to 6, its tile (id 1) static.
const Box kWall{3.0, 3.2, -6.0, 6.0};
const Ellipse kWallTile{3.1, 0.0, 6.0, 0.2, M_PI / 2};

ObstacleTrack problem_obstacle(int64_t id) {
  ObstacleTrack o;
  o.id = id;
  o.x = o.y = o.a = o.b = o.theta = std::vector<double>(4, 0.0);
  return o;
}

double distance_at(const StaticStructure& s, double x, double y) {
  double gx, gy;
  return s.field()->distance(x, y, &gx, &gy);
}

TEST(StaticStructure, AStaticWallTileIsItsCellsAndLeavesTheEllipseConstraints) {
  StaticStructure s{StaticFieldParams{}};
  s.keep_map(map_of({kWall}, kT0));
  Scene sc;
  sc.predictions.utime = kT0;
  sc.add(1, kWallTile, 0.0);
  sc.add(2, {1.0, 2.0, 0.25, 0.25, 0.0}, 1.0);  // a walker, moving
  ASSERT_EQ(s.update(sc.inputs(kT0 + 20'000)), StaticStructure::Update::kBuilt);
  EXPECT_TRUE(s.stands_for(1));
  EXPECT_FALSE(s.stands_for(2));
  EXPECT_NEAR(distance_at(s, 2.5, 0.05), 0.5, 0.02);
  Problem pb;
  pb.N = 3;
  pb.obstacles = {problem_obstacle(1), problem_obstacle(2)};
  s.apply(1.0, 0.0, 0.9, &pb);
  ASSERT_EQ(pb.obstacles.size(), 2u);
  EXPECT_EQ(pb.obstacles[0].id, kStaticFieldId);
  EXPECT_TRUE(pb.obstacles[0].field);
  EXPECT_DOUBLE_EQ(pb.obstacles[0].decay, 0.9);
  EXPECT_EQ(pb.obstacles[1].id, 2);
  // max_distance_m (3 m) or more from every static cell the field is flat
  // where the robot can reach: it stays out of the problem
  pb.obstacles = {problem_obstacle(1), problem_obstacle(2)};
  s.apply(-0.1, 0.0, 0.9, &pb);
  ASSERT_EQ(pb.obstacles.size(), 1u);
  EXPECT_EQ(pb.obstacles[0].id, 2);
}

TEST(StaticStructure, AMoversStrayCellsAndABinStandingAloneAreNoStructure) {
  StaticStructure s{StaticFieldParams{}};
  // a walker's cells 0.5 m behind its ellipse (the scan before its track
  // caught up), and a 0.4 m bin standing still
  const Box stray{0.9, 1.2, 1.9, 2.1}, bin{0.8, 1.2, -2.2, -1.8};
  s.keep_map(map_of({kWall, stray, bin}, kT0));
  Scene sc;
  sc.predictions.utime = kT0;
  sc.add(1, kWallTile, 0.0);
  sc.add(2, {1.6, 2.0, 0.25, 0.25, 0.0}, 1.0);
  sc.add(3, {1.0, -2.0, 0.3, 0.3, 0.0}, 0.0);
  ASSERT_EQ(s.update(sc.inputs(kT0)), StaticStructure::Update::kBuilt);
  EXPECT_GT(distance_at(s, 1.05, 2.0), 1.5);    // the stray cells are not in the field
  EXPECT_GT(distance_at(s, 1.0, -2.0), 1.5);    // nor the bin's
  EXPECT_LT(distance_at(s, 3.1, -2.0), -0.04);  // the wall is
  EXPECT_TRUE(s.stands_for(1));
  EXPECT_FALSE(s.stands_for(3));  // the bin keeps its ellipse
  EXPECT_EQ(s.field()->static_cells(), 2 * 120);
}

TEST(StaticStructure, AWalkerStandingBesideAnotherIsNoStructureButAWallAWalkerPassesIs) {
  StaticStructure s{StaticFieldParams{}};
  // two walkers side by side, 1.1 m of cells together: one standing (a
  // wide ellipse, as a new track's, over most of the other), one walking
  // off; and a third walking along the wall, touching it
  const Box standing{-0.2, 0.3, 2.8, 3.2}, walking{0.3, 0.9, 2.8, 3.2}, by_wall{2.6, 3.0, -3.2, -2.8};
  s.keep_map(map_of({kWall, standing, walking, by_wall}, kT0));
  Scene sc;
  sc.predictions.utime = kT0;
  sc.add(1, kWallTile, 0.0);
  sc.add(2, {0.05, 3.0, 0.8, 0.8, 0.0}, 0.0);
  sc.add(3, {0.6, 3.0, 0.3, 0.3, 0.0}, 0.3);
  sc.add(4, {2.8, -3.0, 0.25, 0.25, 0.0}, 0.5);
  ASSERT_EQ(s.update(sc.inputs(kT0)), StaticStructure::Update::kBuilt);
  EXPECT_FALSE(s.stands_for(2));  // the standing walker keeps its ellipse
  EXPECT_GT(distance_at(s, 0.05, 3.0), 1.5);
  EXPECT_TRUE(s.stands_for(1));
  EXPECT_LT(distance_at(s, 3.05, -3.0), 0.0);  // the wall beside the walker is still wall
}

TEST(StaticStructure, AWallsCellsStayStructureWhateverTrackClaimsThem) {
  StaticStructure s{StaticFieldParams{}};
  s.keep_map(map_of({kWall}, kT0));
  Scene sc;
  sc.predictions.utime = kT0;
  sc.add(1, kWallTile, 0.0, /*seen=*/false);  // coasting: its cells may be hidden
  ASSERT_EQ(s.update(sc.inputs(kT0)), StaticStructure::Update::kBuilt);
  EXPECT_FALSE(s.stands_for(1));               // its ellipse stays
  EXPECT_LT(distance_at(s, 3.1, 0.0), -0.04);  // but the wall's cells are in the field
  // the wall cut into tiles, each under a new id (listed 0.5 s) that reads
  // slow: the wall's cells stay, and a tile whose own cells are structure
  // by themselves (1.5 m of wall) is its cells at once; the short piece at
  // the wall's end (0.3 m), as a walker come up against the wall would
  // be, keeps its ellipse until its speed is known
  Scene tiles;
  tiles.predictions.utime = kT0;
  tiles.add(7, {3.1, -0.75, 0.75, 0.15, M_PI / 2}, 0.0);
  tiles.add(8, {3.1, 0.75, 0.75, 0.15, M_PI / 2}, 0.0);
  tiles.add(9, {3.1, 5.85, 0.2, 0.15, M_PI / 2}, 0.0);
  StaticStructure::Inputs young = tiles.inputs(kT0);
  young.track_age_s = [](int64_t) { return 0.5; };
  ASSERT_EQ(s.update(young), StaticStructure::Update::kBuilt);
  EXPECT_TRUE(s.stands_for(7));
  EXPECT_TRUE(s.stands_for(8));
  EXPECT_FALSE(s.stands_for(9));
  EXPECT_LT(distance_at(s, 3.1, 0.0), -0.04);
  EXPECT_LT(distance_at(s, 3.1, 5.85), -0.04);
  ASSERT_EQ(s.update(tiles.inputs(kT0)), StaticStructure::Update::kBuilt);  // listed 5 s
  EXPECT_TRUE(s.stands_for(9));
  // a tile that reads fast for a moment is a mover: its ellipse, not its
  // cells (the rest of the wall stays)
  tiles.predictions.tracks[1] = track(8, {3.1, 0.75, 0.75, 0.15, M_PI / 2}, 0.5);
  ASSERT_EQ(s.update(tiles.inputs(kT0)), StaticStructure::Update::kBuilt);
  EXPECT_FALSE(s.stands_for(8));
  EXPECT_GT(distance_at(s, 3.1, 0.75), 0.0);
  EXPECT_LT(distance_at(s, 3.1, -2.0), -0.04);
}

TEST(StaticStructure, APersonStandingBesideAWallKeepsItsEllipse) {
  StaticStructure s{StaticFieldParams{}};
  // a person 0.2 m from the wall, standing, tracked: its ellipse (grown
  // towards the robot as the tracker's near-side shift does) takes in
  // some of the wall's cells, but most of its cells are its own
  const Box person{2.4, 2.8, -0.2, 0.2};
  s.keep_map(map_of({kWall, person}, kT0));
  Scene sc;
  sc.predictions.utime = kT0;
  sc.add(1, kWallTile, 0.0);
  sc.add(2, {2.75, 0.0, 0.45, 0.3, 0.0}, 0.0);
  ASSERT_EQ(s.update(sc.inputs(kT0)), StaticStructure::Update::kBuilt);
  EXPECT_TRUE(s.stands_for(1));
  EXPECT_FALSE(s.stands_for(2));
  EXPECT_GT(distance_at(s, 2.6, 0.0), 0.1);  // its cells are no structure either
  EXPECT_LT(distance_at(s, 3.1, 0.0), -0.04);
}

TEST(StaticStructure, AStaleMapGivesNoFieldAndLeavesTheProblemAlone) {
  const StaticFieldParams p;
  StaticStructure s{p};
  Scene sc;
  sc.predictions.utime = kT0;
  sc.add(1, kWallTile, 0.0);
  EXPECT_EQ(s.update(sc.inputs(kT0)), StaticStructure::Update::kStale);  // no map yet
  s.keep_map(map_of({kWall}, kT0));
  const int64_t late = kT0 + std::llround(p.map_max_age_s * 1e6) + 1;
  EXPECT_EQ(s.update(sc.inputs(late)), StaticStructure::Update::kStale);
  EXPECT_FALSE(s.field());
  EXPECT_FALSE(s.stands_for(1));
  Problem pb;
  pb.N = 3;
  pb.obstacles = {problem_obstacle(1)};
  s.apply(0.0, 0.0, 0.9, &pb);
  ASSERT_EQ(pb.obstacles.size(), 1u);
  EXPECT_EQ(pb.obstacles[0].id, 1);
  // a malformed map: no field
  evade::grid_map_t bad = map_of({kWall}, kT0);
  bad.obstacle.pop_back();
  s.clear();
  s.keep_map(bad);
  EXPECT_EQ(s.update(sc.inputs(kT0)), StaticStructure::Update::kInvalid);
  EXPECT_FALSE(s.field());
}

TEST(StaticStructure, TheFieldIsFromTheKeptMapNearestThePredictions) {
  StaticStructure s{StaticFieldParams{}};
  // four maps 0.1 s apart, the wall 1 m further each time; the first is
  // dropped (three kept)
  for (int i = 0; i < 4; ++i) s.keep_map(map_of({{3.0 + i, 3.2 + i, -6.0, 6.0}}, kT0 + i * 100'000));
  Scene sc;
  sc.predictions.utime = kT0 + 100'000 + 2'000;  // made from the second map's scan
  ASSERT_EQ(s.update(sc.inputs(kT0 + 300'000)), StaticStructure::Update::kBuilt);
  EXPECT_NEAR(distance_at(s, 3.5, 0.05), 0.5, 0.02);
  sc.predictions.utime = kT0;  // the first map is gone: the nearest kept is the second
  ASSERT_EQ(s.update(sc.inputs(kT0 + 300'000)), StaticStructure::Update::kBuilt);
  EXPECT_NEAR(distance_at(s, 3.5, 0.05), 0.5, 0.02);
  sc.predictions.utime = kT0 + 300'000;
  ASSERT_EQ(s.update(sc.inputs(kT0 + 300'000)), StaticStructure::Update::kBuilt);
  EXPECT_NEAR(distance_at(s, 5.5, 0.05), 0.5, 0.02);
}

// kWall's field in a problem of 3 steps for one disc of radius 0.2 m,
// the robot at (2.5, 0).
Problem wall_problem(StaticStructure* s) {
  s->keep_map(map_of({kWall}, kT0));
  Scene sc;
  sc.predictions.utime = kT0;
  EXPECT_EQ(s->update(sc.inputs(kT0)), StaticStructure::Update::kBuilt);
  Problem pb;
  pb.N = 3;
  pb.footprint.radius = 0.2;
  s->apply(2.5, 0.0, 0.9, &pb);
  return pb;
}

TEST(StaticStructure, APlanIntoTheWallsMarginIntrudesOneAlongItDoesNot) {
  StaticStructure s{StaticFieldParams{}};
  Problem pb = wall_problem(&s);
  ASSERT_EQ(pb.obstacles.size(), 1u);
  // the wall's face at x 3.0: h = 3.0 - x - 0.2 - d_safe (0.03)
  const std::vector<double> into{2.5, 0.0, 0.0, 2.7, 0.0, 0.0, 2.9, 0.0, 0.0, 3.0, 0.0, 0.0};
  EXPECT_NEAR(structure_intrusion(pb, into), 0.2 + 0.03, 0.02);
  const std::vector<double> along{2.5, 0.0, 0.0, 2.5, 0.3, 0.0, 2.5, 0.6, 0.0, 2.5, 0.9, 0.0};
  EXPECT_EQ(structure_intrusion(pb, along), 0.0);
  // from inside the margin (h_0 < 0), only going further in counts
  const std::vector<double> stay{2.8, 0.0, 0.0, 2.8, 0.2, 0.0, 2.8, 0.4, 0.0, 2.85, 0.4, 0.0};
  EXPECT_NEAR(structure_intrusion(pb, stay), 0.05, 0.02);
  // no field in the problem: nothing to intrude into
  pb.obstacles.clear();
  EXPECT_EQ(structure_intrusion(pb, into), 0.0);
}

TEST(StaticStructure, APlanIntoTheWallItselfGoesAsDeepAsItsBodyDoes) {
  StaticStructure s{StaticFieldParams{}};
  Problem pb = wall_problem(&s);
  ASSERT_EQ(pb.obstacles.size(), 1u);
  // the disc's edge ends on the wall's face (x 2.8 + 0.2): into the margin
  // by d_safe (0.03), not into the wall
  const std::vector<double> to_face{2.5, 0.0, 0.0, 2.6, 0.0, 0.0, 2.7, 0.0, 0.0, 2.8, 0.0, 0.0};
  EXPECT_NEAR(structure_intrusion(pb, to_face), 0.03, 0.01);
  EXPECT_LT(structure_depth(pb, to_face).body, 0.005);
  // its centre on the face: the body 0.2 m into the wall
  const std::vector<double> into{2.5, 0.0, 0.0, 2.7, 0.0, 0.0, 2.9, 0.0, 0.0, 3.0, 0.0, 0.0};
  EXPECT_NEAR(structure_depth(pb, into).body, 0.2, 0.02);
  EXPECT_GT(structure_intrusion(pb, into), structure_depth(pb, into).body);
  // from a start already touching (0.05 m in), only going further in counts
  const std::vector<double> touching{2.85, 0.0, 0.0, 2.85, 0.2, 0.0, 2.9, 0.4, 0.0, 2.95, 0.4, 0.0};
  EXPECT_NEAR(structure_depth(pb, touching).body, 0.1, 0.02);
  const std::vector<double> backing{2.85, 0.0, 0.0, 2.8, 0.0, 0.0, 2.7, 0.0, 0.0, 2.6, 0.0, 0.0};
  EXPECT_EQ(structure_depth(pb, backing).body, 0.0);
  pb.obstacles.clear();
  EXPECT_EQ(structure_depth(pb, into).body, 0.0);
}

// The map as it comes from a scan with the robot at (x, y): every cell
// whose centre is within 0.45 m of it empty (the LiDAR drops returns
// nearer than its min_range_m). With `shift_x_m`, the map (its origin and
// every cell) is moved along x off the odometry frame's lattice.
evade::grid_map_t scan_map(const std::vector<Box>& boxes, int64_t utime, double x, double y, double shift_x_m = 0.0) {
  evade::grid_map_t m = map_of(boxes, utime);
  m.origin[0] += shift_x_m;
  m.robot_x = x;
  m.robot_y = y;
  for (int r = 0; r < m.height; ++r)
    for (int c = 0; c < m.width; ++c)
      if (std::hypot(m.origin[0] + (c + 0.5) * m.resolution - x, m.origin[1] + (r + 0.5) * m.resolution - y) < 0.45)
        m.obstacle[r][c] = 0;
  return m;
}

// s given the map m and predictions (none) stamped with its utime.
StaticStructure::Update fed(StaticStructure* s, const evade::grid_map_t& m) {
  Scene sc;
  sc.predictions.utime = m.utime;
  s->keep_map(m);
  return s->update(sc.inputs(m.utime));
}

TEST(StaticStructure, AWallTheRobotComesWithinTheLidarsMinRangeOfStaysInTheField) {
  StaticStructure s{StaticFieldParams{}};
  // seen from 2 m (in blind_memory_frames scans, 2), then from 0.3 m off
  // its face (x 3.0), where the scan has none of its cells within 0.45 m
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0 - 100'000, 1.0, 0.0)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0, 1.0, 0.0)), StaticStructure::Update::kBuilt);
  EXPECT_NEAR(distance_at(s, 2.7, 0.0), 0.3, 0.02);
  const evade::grid_map_t near = scan_map({kWall}, kT0 + 100'000, 2.7, 0.0);
  ASSERT_EQ(fed(&s, near), StaticStructure::Update::kBuilt);
  EXPECT_NEAR(distance_at(s, 2.7, 0.0), 0.3, 0.02);
  // and again while the robot stays there
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0 + 200'000, 2.7, 0.0)), StaticStructure::Update::kBuilt);
  EXPECT_NEAR(distance_at(s, 2.7, 0.0), 0.3, 0.02);
  // off, or forgotten (a new odometry epoch): the wall starts 0.45 m off
  // the robot in the scan, and the field says so
  StaticFieldParams off;
  off.blind_radius_m = 0.0;
  StaticStructure s_off{off};
  ASSERT_EQ(fed(&s_off, scan_map({kWall}, kT0 - 100'000, 1.0, 0.0)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s_off, scan_map({kWall}, kT0, 1.0, 0.0)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s_off, near), StaticStructure::Update::kBuilt);
  EXPECT_GT(distance_at(s_off, 2.7, 0.0), 0.4);
  s.clear();
  ASSERT_EQ(fed(&s, near), StaticStructure::Update::kBuilt);
  EXPECT_GT(distance_at(s, 2.7, 0.0), 0.4);
}

TEST(StaticStructure, ACellThatFlickersOnInOneScanAsTheRobotComesUpIsNotRemembered) {
  // A wall x 3.0..3.2, y 0..6, its end at y 0, seen from (1, -0.5) in
  // every scan; in the last scan before the robot stands at (2.7, 0),
  // one cell beyond its end (y -0.1..0) is marked too, as a range error at
  // the edge marks it. Standing there, the cell lies within the blind disc:
  // the wall's own cells there are remembered, the one-scan cell is not.
  const Box wall{3.0, 3.2, 0.0, 6.0}, flicker{3.0, 3.1, -0.1, 0.0};
  StaticStructure s{StaticFieldParams{}};
  ASSERT_EQ(fed(&s, scan_map({wall}, kT0 - 200'000, 1.0, -0.5)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s, scan_map({wall}, kT0 - 100'000, 1.0, -0.5)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s, scan_map({wall, flicker}, kT0, 1.0, -0.5)), StaticStructure::Update::kBuilt);
  EXPECT_LT(distance_at(s, 3.05, -0.05), 0.0) << "the flicker is structure in its own scan";
  ASSERT_EQ(fed(&s, scan_map({wall}, kT0 + 100'000, 2.7, 0.0)), StaticStructure::Update::kBuilt);
  // the wall's end cell and the flicker's both lie 0.35 m from the robot
  // (cell centres), where the scan has none
  EXPECT_NEAR(distance_at(s, 3.05, -0.3), 0.3, 0.03) << "to the wall's end, not the flicker";
  EXPECT_NEAR(distance_at(s, 2.75, 0.05), 0.25, 0.03) << "the wall's face is remembered";
  // with every scan's structure remembered (1), the flicker stays there
  StaticFieldParams once;
  once.blind_memory_frames = 1;
  StaticStructure s1{once};
  ASSERT_EQ(fed(&s1, scan_map({wall, flicker}, kT0, 1.0, -0.5)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s1, scan_map({wall}, kT0 + 100'000, 2.7, 0.0)), StaticStructure::Update::kBuilt);
  EXPECT_LT(distance_at(s1, 3.05, -0.3), 0.25);
}

// A map whose origin lies 0.04 m off the lattice (a map snapped
// otherwise than the elevation map snaps it): the memory gives back
// exactly the wall's cells the scan drops within the blind disc, measured
// from their centres in this map. Taken from the lattice index alone, the
// disc lies 0.04 m off and the cells of the wall's second column near
// its edge are neither in the scan nor given back.
TEST(StaticStructure, TheBlindDiscIsMeasuredFromTheMapsOwnOrigin) {
  constexpr double kShift = -0.04;
  StaticStructure s{StaticFieldParams{}};
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0 - 100'000, 1.0, 0.0, kShift)), StaticStructure::Update::kBuilt);
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0, 1.0, 0.0, kShift)), StaticStructure::Update::kBuilt);
  const int whole = s.field()->static_cells();
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0 + 100'000, 2.7, 0.0, kShift)), StaticStructure::Update::kBuilt);
  EXPECT_EQ(s.field()->static_cells(), whole);
  StaticFieldParams off;
  off.blind_radius_m = 0.0;
  StaticStructure s_off{off};
  ASSERT_EQ(fed(&s_off, scan_map({kWall}, kT0 + 100'000, 2.7, 0.0, kShift)), StaticStructure::Update::kBuilt);
  EXPECT_LT(s_off.field()->static_cells(), whole - 8);  // the scan alone drops that many
}

TEST(StaticStructure, StructureThatIsGoneWhereTheLidarSeesIsNotRemembered) {
  StaticStructure s{StaticFieldParams{}};
  ASSERT_EQ(fed(&s, scan_map({kWall}, kT0, 1.0, 0.0)), StaticStructure::Update::kBuilt);
  // the wall's cells are gone from a scan that sees where they were
  ASSERT_EQ(fed(&s, scan_map({}, kT0 + 100'000, 1.0, 0.0)), StaticStructure::Update::kBuilt);
  EXPECT_EQ(s.field()->static_cells(), 0);
  // so the robot coming up to where the wall stood finds nothing there
  ASSERT_EQ(fed(&s, scan_map({}, kT0 + 200'000, 2.7, 0.0)), StaticStructure::Update::kBuilt);
  EXPECT_EQ(s.field()->static_cells(), 0);
}

}  // namespace
}  // namespace evade::planning
