// The counterfactual reaction time (metrics_rules()) on logs whose planner
// inputs are made here, and on the golden paper_sim case in logs/.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "bus/core.h"
#include "bus/log.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "evade/sim_truth_t.hpp"
#include "metrics/plan_replay.h"
#include "metrics/run_metrics.h"
#include "metrics/track_association.h"
#include "planning/params.h"

namespace evade::metrics {
namespace {

config::Node repo_config() { return config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"); }

constexpr int64_t kT0 = 1'000'000'000;  // us
constexpr double kRobotSpeed = 0.8;     // m/s along y = 0 from x = 0

// A cylinder (r 0.25) moving at constant velocity, its perception track id.
struct Mover {
  int id;
  int64_t track;
  double x0, y0, vx, vy;
  double x(double t) const { return x0 + vx * t; }
  double y(double t) const { return y0 + vy * t; }
};

evade::prediction_list_t predictions(const std::vector<Mover>& movers, double t, int64_t utime) {
  evade::prediction_list_t pl{};
  pl.utime = utime;
  pl.dt = 0.1;
  pl.horizon = 26;
  for (const auto& m : movers) {
    evade::track_prediction_t tp{};
    tp.id = m.track;
    tp.vx = m.vx;
    tp.vy = m.vy;
    tp.horizon = pl.horizon;
    for (int k = 0; k < pl.horizon; ++k) {
      tp.x.push_back(m.x(t + 0.1 * k));
      tp.y.push_back(m.y(t + 0.1 * k));
      tp.a.push_back(0.3);
      tp.b.push_back(0.3);
      tp.theta.push_back(0.0);
      tp.sigma.push_back(0.05);
    }
    pl.tracks.push_back(tp);
  }
  pl.num_tracks = static_cast<int32_t>(pl.tracks.size());
  return pl;
}

evade::obstacle_list_t obstacles(const std::vector<Mover>& movers, double t, int64_t utime) {
  evade::obstacle_list_t ol{};
  ol.utime = utime;
  for (const auto& m : movers) {
    evade::obstacle_t o{};
    o.id = m.track;
    o.x = m.x(t);
    o.y = m.y(t);
    o.a = o.b = 0.25;
    o.num_cells = 10;
    o.age = static_cast<int32_t>(t * 10);
    ol.obstacles.push_back(o);
  }
  ol.num_obstacles = static_cast<int32_t>(ol.obstacles.size());
  return ol;
}

evade::sim_truth_t truth(const std::vector<Mover>& movers, double t, int64_t utime) {
  evade::sim_truth_t s{};
  s.utime = utime;
  s.x = kRobotSpeed * t;
  s.v = kRobotSpeed;
  s.footprint_length = 0.42;
  s.footprint_width = 0.31;
  s.obstacles_moving = true;
  s.scenario = "synthetic";
  s.goal_x = 30.0;
  s.goal_tolerance = 0.3;
  s.duration_s = 20.0;
  for (const auto& m : movers) {
    evade::sim_obstacle_t o{};
    o.id = m.id;
    o.shape = "cylinder";
    o.x = m.x(t);
    o.y = m.y(t);
    o.radius = 0.25;
    o.height = 0.5;
    o.vx = m.vx;
    o.vy = m.vy;
    s.obstacles.push_back(o);
  }
  s.num_obstacles = static_cast<int32_t>(s.obstacles.size());
  s.lidar_returns.assign(s.obstacles.size(), 40);
  return s;
}

// The robot drives its route (0,0) -> (30,0) at 0.8 m/s regardless of the
// plans (the odometry is given); perception sees the movers exactly.
// ODOMETRY and SIM_TRUTH at 50 Hz, OBSTACLES and OBSTACLE_PREDICTIONS at
// 10 Hz, ROUTE at 1 Hz.
std::vector<bus::LogEvent> planner_inputs(const std::vector<Mover>& movers, double duration_s) {
  std::vector<bus::LogEvent> ev;
  for (int k = 0; k * 0.02 <= duration_s; ++k) {
    const double t = k * 0.02;
    const int64_t u = kT0 + k * 20'000;
    if (k % 50 == 0) {
      evade::path_t r{};
      r.utime = u;
      r.n = 2;
      r.x = {0.0, 30.0};
      r.y = {0.0, 0.0};
      ev.push_back({u, "ROUTE", bus::encode(r)});
    }
    if (k % 5 == 0) {
      ev.push_back({u, "OBSTACLES", bus::encode(obstacles(movers, t, u))});
      ev.push_back({u, "OBSTACLE_PREDICTIONS", bus::encode(predictions(movers, t, u))});
    }
    evade::odometry_t o{};
    o.utime = u;
    o.x = kRobotSpeed * t;
    o.v = kRobotSpeed;
    ev.push_back({u, "ODOMETRY", bus::encode(o)});
    ev.push_back({u, "SIM_TRUTH", bus::encode(truth(movers, t, u))});
  }
  return ev;
}

// The inputs plus the PLANs a planner made from them: a recorded run.
std::vector<bus::LogEvent> recorded_run(const std::vector<Mover>& movers, double duration_s,
                                        const planning::PlannerParams& planner) {
  auto ev = planner_inputs(movers, duration_s);
  PlanReplay replay(planner, ev);
  std::vector<bus::LogEvent> out = ev;
  for (const auto& p : replay.plans()) out.push_back({p.utime, "PLAN", bus::encode(p)});
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
  return out;
}

// Head-on: from (12, 0) towards the robot at 1 m/s; the robot's 10 m
// window (|dx| <= 5) takes it in when 12 - 1.8 t <= 5, t = 3.89 s.
const Mover kHeadOn{0, 11, 12.0, 0.0, -1.0, 0.0};
// Alongside: 4.6 m to the left, keeping pace: inside the window from the
// start, never within the planner's 4 m consider radius, never ahead-and-
// oncoming or a slow leader.
const Mover kAlongside{1, 22, 1.0, 4.6, kRobotSpeed, 0.0};

std::vector<evade::sim_truth_t> truth_of(const std::vector<bus::LogEvent>& ev) {
  std::vector<evade::sim_truth_t> truth;
  for (const auto& e : ev) {
    evade::sim_truth_t s;
    if (e.channel == "SIM_TRUTH" && bus::decode(e.data.data(), e.data.size(), &s)) truth.push_back(s);
  }
  return truth;
}

TEST(TrackAssociation, EachTrackIsTheObstacleNearestIt) {
  auto ev = planner_inputs({kHeadOn, kAlongside}, 2.0);
  const auto owners = associate_tracks(ev, truth_of(ev), 1.0, 0.5);
  EXPECT_EQ(owners.timelines.size(), 2u);
  EXPECT_EQ(owners.owner(11, kT0 + 1'000'000), 0);
  EXPECT_EQ(owners.owner(22, kT0 + 1'000'000), 1);
  EXPECT_EQ(owners.owner(33, kT0 + 1'000'000), TrackOwners::kNone);  // never seen
  EXPECT_EQ(owners.owner(11, kT0 - 1), TrackOwners::kNone);          // before it was seen
  EXPECT_EQ(owners.tracks_of(0), std::set<int64_t>{11});
  EXPECT_EQ(owners.tracks_of(1), std::set<int64_t>{22});
  // a track 1.5 m off every obstacle's surface is none of them
  Mover ghost = kAlongside;
  ghost.y0 += 1.75;
  auto ev2 = planner_inputs({ghost}, 1.0);
  const auto none = associate_tracks(ev2, truth_of(ev), 1.0, 0.5);
  EXPECT_EQ(none.owner(22, kT0 + 500'000), TrackOwners::kNone);
  EXPECT_TRUE(none.tracks_of(1).empty());
}

TEST(TrackAssociation, ATrackHandedOverToAnotherObstacleChangesOwnerFromItsFirstVote) {
  // Track 11 follows the head-on mover until t = 3 s, then stays on a
  // static bin at (8, 6); a blip of 0.2 s on the bin at t = 1 s changes
  // nothing (shorter than switch_s).
  auto ev = planner_inputs({kHeadOn, Mover{1, 99, 8.0, 6.0, 0.0, 0.0}}, 6.0);
  for (auto& e : ev) {
    const double t = (e.timestamp - kT0) * 1e-6;
    const bool on_bin = t >= 3.0 || (t >= 1.0 && t < 1.2);
    if (e.channel == "OBSTACLES") {
      evade::obstacle_list_t ol;
      ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &ol));
      ol.obstacles.resize(1);  // the bin itself is not reported under its own track
      ol.num_obstacles = 1;
      if (on_bin) ol.obstacles[0].x = 8.0, ol.obstacles[0].y = 6.0;
      e.data = bus::encode(ol);
    } else if (e.channel == "OBSTACLE_PREDICTIONS") {
      evade::prediction_list_t pl;
      ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &pl));
      pl.tracks.resize(1);
      pl.num_tracks = 1;
      if (on_bin) pl.tracks[0].x.assign(pl.horizon, 8.0), pl.tracks[0].y.assign(pl.horizon, 6.0);
      e.data = bus::encode(pl);
    }
  }
  const auto owners = associate_tracks(ev, truth_of(ev), 1.0, 0.5);
  EXPECT_EQ(owners.owner(11, kT0 + 1'100'000), 0);  // the blip
  EXPECT_EQ(owners.owner(11, kT0 + 2'900'000), 0);
  EXPECT_EQ(owners.owner(11, kT0 + 3'000'000), 1);  // from the first vote for the bin
  EXPECT_EQ(owners.owner(11, kT0 + 5'000'000), 1);
  EXPECT_EQ(owners.tracks_of(0), std::set<int64_t>{11});
  EXPECT_EQ(owners.tracks_of(1), std::set<int64_t>{11});
  ASSERT_EQ(owners.timelines.at(11).size(), 2u);
}

TEST(PlanReplay, StripTracksLeavesOutTheIdsOfBothListTypesAndNothingElse) {
  auto pl = bus::encode(predictions({kHeadOn, kAlongside}, 0.0, kT0));
  auto ol = bus::encode(obstacles({kHeadOn, kAlongside}, 0.0, kT0));
  evade::odometry_t o{};
  o.x = 1.0;
  auto od = bus::encode(o);
  const auto od_before = od;
  EXPECT_TRUE(strip_tracks(&pl, {11}));
  EXPECT_TRUE(strip_tracks(&ol, {11}));
  EXPECT_FALSE(strip_tracks(&od, {11}));
  EXPECT_EQ(od, od_before);
  evade::prediction_list_t p2;
  evade::obstacle_list_t o2;
  ASSERT_TRUE(bus::decode(pl.data(), pl.size(), &p2));
  ASSERT_TRUE(bus::decode(ol.data(), ol.size(), &o2));
  ASSERT_EQ(p2.num_tracks, 1);
  EXPECT_EQ(p2.tracks[0].id, 22);
  ASSERT_EQ(o2.num_obstacles, 1);
  EXPECT_EQ(o2.obstacles[0].id, 22);
}

// A plan along y = 0 at 1 m/s from x0, made at utime, 26 states 0.1 s apart.
evade::plan_t straight_plan(int64_t utime, double x0, double y = 0.0) {
  evade::plan_t p{};
  p.utime = utime;
  p.horizon = 25;
  p.num_states = 26;
  for (int k = 0; k < p.num_states; ++k) {
    p.x.push_back(x0 + 0.1 * k);
    p.y.push_back(y);
    p.yaw.push_back(0.0);
  }
  p.v.assign(25, 1.0);
  p.omega.assign(25, 0.0);
  return p;
}

TEST(PlanReplay, PlanDistanceComparesPositionsAtTheSameTimes) {
  const auto a = straight_plan(kT0, 0.0);
  EXPECT_EQ(plan_distance_m(a, a, 0.1), 0.0);
  EXPECT_NEAR(plan_distance_m(a, straight_plan(kT0, 0.0, 0.2), 0.1), 0.2, 1e-12);
  // the same motion planned 50 ms later (half a step): the same positions
  // at the same times
  const auto later = straight_plan(kT0 + 50'000, 0.05);
  EXPECT_NEAR(plan_distance_m(later, a, 0.1), 0.0, 1e-12);
  EXPECT_NEAR(plan_distance_m(a, later, 0.1), 0.0, 1e-12);
  // ... or standing still at 0.05 from then on: 0.1 k behind a at its step
  // k, up to k = 24 (its step 25 is beyond a's horizon)
  auto stopped = later;
  stopped.x.assign(26, 0.05);
  EXPECT_NEAR(plan_distance_m(stopped, a, 0.1), 2.4, 1e-9);
  // no time in common
  EXPECT_TRUE(std::isinf(plan_distance_m(straight_plan(kT0 + 3'000'000, 3.0), a, 0.1)));
}

TEST(PlanReplay, APlanningCycleKeepsThePlannerBusyForTheLogsComputeTime) {
  const auto planner = planning::PlannerParams::from_config(repo_config());
  const auto inputs = planner_inputs({kAlongside}, 3.0);
  const PlanReplay instant(planner, inputs);  // no PLAN in the log: no compute time
  EXPECT_EQ(instant.compute_model().base_us, 0.0);
  const auto fast = instant.plans();
  EXPECT_GE(fast.size(), 30u);  // 10 Hz for 3 s
  // recorded PLANs saying 10 iterations took 250 ms and 20 took 350 ms:
  // 150 ms + 10 ms per iteration, longer than the 100 ms period
  auto slow_log = inputs;
  for (int it : {10, 20}) {
    evade::plan_t p{};
    p.utime = kT0;
    p.iterations = it;
    p.solve_time_us = 150'000 + 10'000 * it;
    slow_log.push_back({kT0, "PLAN", bus::encode(p)});
  }
  const PlanReplay slow(planner, slow_log);
  EXPECT_NEAR(slow.compute_model().base_us, 150'000, 1e-6);
  EXPECT_NEAR(slow.compute_model().per_iteration_us, 10'000, 1e-9);
  const auto plans = slow.plans();
  EXPECT_LT(plans.size(), fast.size() * 3 / 4);  // a cycle every 160-180 ms instead of 100
  for (size_t i = 0; i + 1 < plans.size(); ++i) {
    if (plans[i].status != evade::plan_t::STATUS_OK) continue;
    EXPECT_EQ(plans[i].solve_time_us, 150'000 + 10'000 * plans[i].iterations);
    // the next plan starts from the newest odometry that came while it was
    // busy (ODOMETRY every 20 ms)
    EXPECT_GE(plans[i + 1].utime - plans[i].utime, plans[i].solve_time_us - 20'000) << i;
  }
}

TEST(Reaction, AHeadOnMoverIsReactedToAndOneAlongsideIsNot) {
  const auto planner = planning::PlannerParams::from_config(repo_config());
  const auto ev = recorded_run({kHeadOn, kAlongside}, 6.0, planner);
  MetricsParams params;
  const auto m = compute_metrics(ev, params, &planner);
  // the replay with nothing removed reproduces the recorded plans exactly
  ASSERT_TRUE(m.replay_check);
  EXPECT_GT(m.replay_check->compared, 50);
  EXPECT_EQ(m.replay_check->compared, m.plans);
  EXPECT_EQ(m.replay_check->differing, 0);
  EXPECT_EQ(m.replay_check->max_distance_m, 0.0);

  const ObstacleTrack& head_on = m.obstacles.at(0);
  const ObstacleTrack& alongside = m.obstacles.at(1);
  ASSERT_TRUE(head_on.t_enter_s);
  EXPECT_NEAR(*head_on.t_enter_s, 7.0 / 1.8, 0.021);
  EXPECT_EQ(head_on.tracks, std::vector<int64_t>{11});
  ASSERT_TRUE(head_on.t_react_s);
  // Seen from the start (12 m away), it shapes the plan before it enters
  // the paper's 10 m window: the first cycle in the window reacts.
  ASSERT_TRUE(head_on.t_change_s);
  EXPECT_LE(*head_on.t_change_s, *head_on.t_react_s);
  EXPECT_GE(*head_on.t_react_s, *head_on.t_enter_s);
  EXPECT_LE(*head_on.t_react_s - *head_on.t_enter_s, 0.5);

  EXPECT_EQ(alongside.tracks, std::vector<int64_t>{22});
  EXPECT_FALSE(alongside.t_change_s);
  EXPECT_FALSE(alongside.t_react_s);
  EXPECT_EQ(m.reaction_missed, 1);
  ASSERT_TRUE(m.reaction_time_s);
  EXPECT_NEAR(*m.reaction_time_s, *head_on.t_react_s - *head_on.t_enter_s, 1e-9);
}

TEST(Reaction, AMoverFirstSeenInsideTheWindowIsReactedToAfterItIsSeen) {
  // The same head-on mover, but perception only reports it from t = 5 s
  // (1 m inside the window, 3 m from the robot): the reaction comes after.
  const auto planner = planning::PlannerParams::from_config(repo_config());
  auto ev = recorded_run({kHeadOn}, 6.0, planner);
  std::vector<bus::LogEvent> late;
  for (auto& e : ev) {
    if ((e.channel == "OBSTACLES" || e.channel == "OBSTACLE_PREDICTIONS") && e.timestamp < kT0 + 5'000'000)
      strip_tracks(&e.data, {kHeadOn.track});
    if (e.channel != "PLAN") late.push_back(e);
  }
  PlanReplay replay(planner, late);
  for (const auto& p : replay.plans()) late.push_back({p.utime, "PLAN", bus::encode(p)});
  std::stable_sort(late.begin(), late.end(), [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
  const auto m = compute_metrics(late, MetricsParams{}, &planner);
  const ObstacleTrack& head_on = m.obstacles.at(0);
  ASSERT_TRUE(head_on.t_react_s);
  ASSERT_TRUE(head_on.t_change_s);
  EXPECT_EQ(*head_on.t_change_s, *head_on.t_react_s);
  // A plan is stamped with the odometry it starts from, which the list
  // that made it may follow by up to one odometry period (20 ms here).
  EXPECT_GE(*head_on.t_react_s, 5.0 - 0.02 - 1e-9);
  EXPECT_LE(*head_on.t_react_s, 5.3);  // within three cycles of its first sighting
}

TEST(Reaction, AnUnknownPlanModeIsAClearError) {
  const auto planner = planning::PlannerParams::from_config(repo_config());
  auto ev = recorded_run({kHeadOn}, 1.0, planner);
  for (auto& e : ev) {
    if (e.channel != "PLAN") continue;
    evade::plan_t p;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &p));
    p.mode = "no_such_mode";
    e.data = bus::encode(p);
  }
  try {
    compute_metrics(ev, MetricsParams{}, &planner);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_mode"), std::string::npos) << e.what();
  }
}

// The golden paper_sim case (logs/README.md: t = 10-13 s of a live run,
// the robot meeting the movers near x = -5). Obstacle 6 comes head-on
// along y = -0.8 at 0.7 m/s and enters the 10 m window 1.1 s into the
// window; the replay starts cold there, so it is compared with itself.
TEST(Reaction, GoldenPaperSimHeadOnMover) {
  const auto log = bus::read_log(std::string(EVADE_SOURCE_DIR) + "/logs/paper_sim_crossing/input.lcmlog");
  const auto planner = planning::PlannerParams::from_config(repo_config());
  const auto m = compute_metrics(log, MetricsParams{}, &planner);
  const ObstacleTrack* head_on = nullptr;
  for (const auto& o : m.obstacles) {
    if (o.id == 6) head_on = &o;
    if (!o.dynamic) {
      EXPECT_FALSE(o.t_react_s) << "static obstacle " << o.id;
    }
  }
  ASSERT_NE(head_on, nullptr);
  ASSERT_TRUE(head_on->t_enter_s);
  ASSERT_FALSE(head_on->tracks.empty());
  ASSERT_TRUE(head_on->t_react_s);
  const double reaction = *head_on->t_react_s - *head_on->t_enter_s;
  EXPECT_GE(reaction, 0.0);
  EXPECT_LE(reaction, 1.0);
  // the replay is deterministic
  PlanReplay replay(planner, log);
  const auto a = replay.plans(), b = replay.plans();
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 20u);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(plan_distance_m(a[i], b[i], planner.dt_s), 0.0) << i;
}

}  // namespace
}  // namespace evade::metrics
