// The recovery's passive-safety bound (planning/passive_safety.h): the
// speed from which the robot stands before a mover going at its own speed
// in any direction could reach its front; a mover predicted to walk away
// bounds it as one walking towards it, and one turning round (its estimate
// through zero) as one at the speed it walked lately; far from every
// mover, or beside only settled obstacles, nothing is bounded. braking_point keeps where braking
// from each step ends out of each mover's reach, which braking meets.
#include "planning/passive_safety.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "planning/recent_max.h"
#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::moving_obstacle;
using testing::straight_problem;

constexpr double kDecel = 1.5;  // testing::default_limits()

// The defaults with a 0.3 s reaction, twice config/robot.yaml's: the
// distances below are chosen so that the walkers bind with it.
PassiveSafetyParams slow_reaction() {
  PassiveSafetyParams p;
  p.reaction_s = 0.3;
  return p;
}

// The 0.42 x 0.31 m robot at the origin heading +x at 1 m/s, and a walker of
// radius 0.3 m at (x, y) walking at (vx, vy), tracked age_s.
Problem robot_and_walker(double x, double y, double vx, double vy, double age_s) {
  Problem pb = straight_problem(0, 0, 0, 1.0, 1.0);
  pb.footprint = Footprint::covering(0.42, 0.31, 3);
  pb.d_safe = 0.15;
  ObstacleTrack w = moving_obstacle(3, x, y, vx, vy, 0.3, 0.3, 0.0, 0.9, pb.N, pb.dt);
  w.age_s = age_s;
  pb.obstacles = {w};
  return pb;
}

// the gap from the front disc of robot_and_walker's robot to a walker at (x, y)
double front_gap(double x, double y) {
  const Footprint f = Footprint::covering(0.42, 0.31, 3);
  return std::hypot(x - f.offsets.back(), y) - f.radius - 0.3;
}

TEST(PassiveSafety, FromTheBoundTheRobotStandsBeforeTheMoverCanReachIt) {
  const double tau = 0.3;
  for (double s : {0.0, 0.5, 1.4, 5.0}) {
    for (double gap : {0.2, 0.5, 1.0, 2.0, 6.0}) {
      const double v = passive_safe_speed(gap, s, tau, kDecel);
      if (gap <= s * tau) {
        EXPECT_EQ(v, 0.0) << "s " << s << " gap " << gap;
        continue;
      }
      ASSERT_GT(v, 0.0);
      // the robot's way and the mover's until the robot stands fill the gap
      const double stop_s = tau + v / kDecel;
      EXPECT_NEAR(v * tau + v * v / (2 * kDecel) + s * stop_s, gap, 1e-9) << "s " << s << " gap " << gap;
    }
  }
  // nearer or faster: slower
  EXPECT_LT(passive_safe_speed(0.8, 1.4, tau, kDecel), passive_safe_speed(1.2, 1.4, tau, kDecel));
  EXPECT_LT(passive_safe_speed(1.2, 2.0, tau, kDecel), passive_safe_speed(1.2, 1.4, tau, kDecel));
}

TEST(PassiveSafety, AWalkerBesideBoundsTheSpeedWhereverItIsPredictedToGo) {
  PassiveSafetyParams p = slow_reaction();
  p.braking_point = false;
  // 1 m beside the robot, predicted to walk away from it at 1 m/s
  const Problem away = robot_and_walker(0.0, -1.3, 0.0, -1.0, 3.0);
  const double bound = passive_speed_bound(p, away);
  EXPECT_NEAR(bound, passive_safe_speed(front_gap(0.0, -1.3), 1.0, p.reaction_s, kDecel), 0.01);
  EXPECT_LT(bound, 0.5);
  // walking towards it at the same speed: the same bound
  EXPECT_NEAR(passive_speed_bound(p, robot_and_walker(0.0, -1.3, 0.0, 1.0, 3.0)), bound, 1e-9);
  // the bound goes into the problem's v_cap at every step
  Problem pb = away;
  ASSERT_TRUE(bound_passively(p, &pb));
  ASSERT_EQ(pb.v_cap.size(), static_cast<size_t>(pb.N));
  for (double cap : pb.v_cap) EXPECT_NEAR(cap, bound, 1e-12);
  // an existing lower cap (a hidden region's) stays
  pb = away;
  pb.v_cap.assign(pb.N, 0.1);
  ASSERT_TRUE(bound_passively(p, &pb));
  for (double cap : pb.v_cap) EXPECT_NEAR(cap, 0.1, 1e-12);
}

TEST(PassiveSafety, FarFromEveryMoverNothingIsBounded) {
  const PassiveSafetyParams p = slow_reaction();
  Problem pb = robot_and_walker(0.0, -8.0, 0.0, 1.0, 3.0);
  EXPECT_EQ(passive_speed_bound(p, pb), pb.lim.v_max);
  EXPECT_FALSE(bound_passively(p, &pb));
  EXPECT_TRUE(pb.v_cap.empty());
  // no obstacle at all
  pb.obstacles.clear();
  EXPECT_FALSE(bound_passively(p, &pb));
}

TEST(PassiveSafety, SettledObstaclesAreNotMoversYoungTracksAreFast) {
  const PassiveSafetyParams p = slow_reaction();
  // a bin 0.4 m ahead, tracked 3 s, standing: the constraints' alone
  const Problem bin = robot_and_walker(0.21 + 0.4 + 0.3, 0.0, 0.0, 0.0, 3.0);
  EXPECT_EQ(passive_speed_bound(p, bin), bin.lim.v_max);
  // the same track seen for the first time: its speed is not known yet
  const Problem young = robot_and_walker(0.21 + 0.4 + 0.3, 0.0, 0.0, 0.0, 0.1);
  const double gap = front_gap(0.21 + 0.4 + 0.3, 0.0);
  EXPECT_NEAR(passive_speed_bound(p, young), passive_safe_speed(gap, p.unknown_speed_mps, p.reaction_s, kDecel), 0.01);
  // a young track faster than that keeps its own speed
  const Problem fast = robot_and_walker(5.0, 0.0, -4.0, 0.0, 0.1);
  EXPECT_NEAR(passive_speed_bound(p, fast), passive_safe_speed(front_gap(5.0, 0.0), 4.0, p.reaction_s, kDecel), 0.01);
}

TEST(PassiveSafety, AWalkerTurningRoundBindsAtTheSpeedItWalkedLately) {
  const PassiveSafetyParams p = slow_reaction();
  // 1.2 m ahead, tracked 3 s, its estimate through zero as it turns round
  Problem turning = robot_and_walker(0.21 + 1.2 + 0.3, 0.0, 0.0, 0.0, 3.0);
  EXPECT_EQ(passive_speed_bound(p, turning), turning.lim.v_max);
  // it walked at 1.4 m/s a moment ago (what the planner remembers)
  turning.obstacles[0].recent_speed_mps = 1.4;
  const double gap = front_gap(0.21 + 1.2 + 0.3, 0.0);
  const double bound = passive_speed_bound(p, turning);
  EXPECT_NEAR(bound, passive_safe_speed(gap, 1.4, p.reaction_s, kDecel), 0.01);
  EXPECT_LT(bound, 0.9);
  // a prediction faster than what it showed lately keeps its own speed
  Problem fast = robot_and_walker(0.21 + 1.2 + 0.3, 0.0, -2.0, 0.0, 3.0);
  fast.obstacles[0].recent_speed_mps = 1.4;
  EXPECT_NEAR(passive_speed_bound(p, fast), passive_safe_speed(gap, 2.0, p.reaction_s, kDecel), 0.01);
}

TEST(PassiveSafety, AMoverMeasuredNearerThanPredictedBindsWhereItWasMeasured) {
  PassiveSafetyParams p = slow_reaction();
  p.measured_position = false;
  // predicted (step 0) 2 m ahead, walking at 1.4 m/s; the filter lags: the
  // tracker measured it 0.6 m nearer
  Problem pb = robot_and_walker(0.21 + 2.0 + 0.3, 0.0, -1.4, 0.0, 3.0);
  pb.obstacles[0].measured = ObstacleTrack::Body{0.21 + 1.4 + 0.3, 0.0, 0.3, 0.3, 0.0};
  const double predicted = passive_safe_speed(front_gap(0.21 + 2.0 + 0.3, 0.0), 1.4, p.reaction_s, kDecel);
  const double measured = passive_safe_speed(front_gap(0.21 + 1.4 + 0.3, 0.0), 1.4, p.reaction_s, kDecel);
  ASSERT_LT(measured, predicted - 0.1);
  EXPECT_NEAR(passive_speed_bound(p, pb), predicted, 0.01) << "off: the prediction alone";
  p.measured_position = true;
  EXPECT_NEAR(passive_speed_bound(p, pb), measured, 0.01);
  // the reach bound grows from the measured body too
  Problem bounded = pb;
  ASSERT_TRUE(bound_passively(p, &bounded));
  ASSERT_EQ(bounded.reach.size(), 1u);
  EXPECT_NEAR(bounded.reach[0].x, 0.21 + 1.4 + 0.3, 1e-12);
  // measured farther than predicted: the prediction stands
  pb.obstacles[0].measured = ObstacleTrack::Body{0.21 + 2.6 + 0.3, 0.0, 0.3, 0.3, 0.0};
  EXPECT_NEAR(passive_speed_bound(p, pb), predicted, 0.01);
}

TEST(RecentMax, TheLargestWithinTheWindowOfTheLastAdd) {
  RecentMax m;
  EXPECT_EQ(m.max(), 0.0);
  const int64_t s = 1000000;  // 1 s in us
  m.add(0, 1.4, 2.0);
  m.add(s / 2, 0.1, 2.0);  // turning round
  m.add(s, 0.3, 2.0);
  EXPECT_DOUBLE_EQ(m.max(), 1.4);
  m.add(2 * s, 0.2, 2.0);  // 2 s after the 1.4: still within
  EXPECT_DOUBLE_EQ(m.max(), 1.4);
  m.add(2 * s + 1, 0.2, 2.0);  // now it is older than 2 s
  EXPECT_DOUBLE_EQ(m.max(), 0.3);
  m.add(5 * s, 0.0, 2.0);  // everything before 3 s forgotten
  EXPECT_DOUBLE_EQ(m.max(), 0.0);
  m.add(5 * s, NAN, 2.0);  // not added
  EXPECT_DOUBLE_EQ(m.max(), 0.0);
  // window 0: the last value alone
  m.add(6 * s, 0.9, 0.0);
  m.add(7 * s, 0.5, 0.0);
  EXPECT_DOUBLE_EQ(m.max(), 0.5);
  // time going back (a new epoch) forgets the old series
  m.add(8 * s, 3.0, 2.0);
  m.add(s, 0.4, 2.0);
  EXPECT_DOUBLE_EQ(m.max(), 0.4);
}

TEST(PassiveSafety, AMoverBehindIsFartherFromTheFrontThanOneAhead) {
  const PassiveSafetyParams p = slow_reaction();
  const double ahead = passive_speed_bound(p, robot_and_walker(1.3, 0.0, 1.0, 0.0, 3.0));
  const double behind = passive_speed_bound(p, robot_and_walker(-1.3, 0.0, -1.0, 0.0, 3.0));
  EXPECT_LT(ahead, behind);
}

// The least slack of pb's reach-bound constraints for controls u.
double reach_slack(const Problem& pb, const std::vector<double>& u) {
  std::vector<double> states, g;
  evaluate_constraints(pb, u.data(), &states, &g);
  double least = std::numeric_limits<double>::infinity();
  for (int j = pb.num_rate_constraints() + pb.num_barrier_constraints(); j < pb.num_constraints(); ++j)
    least = std::min(least, g[static_cast<size_t>(j)]);
  return least;
}

// Controls: turn on the spot by `turn` rad (within the omega and alpha
// limits), then speed up to v; projected onto pb's limits.
std::vector<double> turn_then_drive(const Problem& pb, double turn, double v) {
  std::vector<double> u(static_cast<size_t>(pb.num_controls()), 0.0);
  double left = turn, w = pb.omega_prev;
  for (int k = 0; k < pb.N; ++k) {
    // brake the turn in time: at most the speed from which alpha stops it within what is left
    const double stop = std::sqrt(2.0 * pb.lim.alpha * std::fabs(left));
    const double want = std::clamp(std::copysign(std::min(stop, pb.lim.omega_max), left), w - pb.lim.alpha * pb.dt,
                                   w + pb.lim.alpha * pb.dt);
    w = std::fabs(left) < 0.02 ? 0.0 : want;
    u[2 * k + 1] = w;
    left -= w * pb.dt;
    u[2 * k] = std::fabs(left) < 0.05 ? v : 0.0;
  }
  project_controls(pb, &u);
  return u;
}

// Driving straight at a mover, the braking point's bound is the speed
// bound: at the bound's speed the first step's constraint is met exactly.
TEST(PassiveSafety, HeadOnTheBrakingPointIsTheSpeedBound) {
  const PassiveSafetyParams p = slow_reaction();
  for (double x : {1.2, 1.6, 2.0}) {
    Problem pb = robot_and_walker(x, 0.0, -1.0, 0.0, 3.0);
    pb.v_prev = 0.0;
    const double bound = passive_speed_bound(p, pb);
    ASSERT_GT(bound, 0.05);
    ASSERT_LT(bound, pb.lim.v_max);
    const std::vector<ReachBound> bounds = passive_reach_bounds(p, pb);
    ASSERT_EQ(bounds.size(), 1u);
    EXPECT_EQ(bounds[0].id, 3);
    EXPECT_EQ(bounds[0].allowance_m[0], 0.0);  // standing meets it
    EXPECT_NEAR(reach_value(bounds[0], 0, pb.x0, pb.y0, pb.yaw0, bound, false).g, 0.0, 1e-9) << "x " << x;
    EXPECT_LT(reach_value(bounds[0], 0, pb.x0, pb.y0, pb.yaw0, bound + 0.05, false).g, 0.0) << "x " << x;
  }
}

// A walker 1.8 m ahead of a robot at rest, walking at 1 m/s: driving at
// it is bounded, turning a quarter and driving out of its way at full
// speed is not (the speed bound forbids both).
TEST(PassiveSafety, TheBrakingPointBoundsTheApproachNotTheWayOut) {
  PassiveSafetyParams p = slow_reaction();
  Problem pb = robot_and_walker(1.8, 0.0, -1.0, 0.0, 3.0);
  pb.v_prev = 0.0;
  pb.lim.omega_max = 2.0;  // the quarter turn fits the horizon with time to drive
  const double bound = passive_speed_bound(p, pb);
  ASSERT_LT(bound, 0.8);  // the premise: the walker binds
  Problem reach = pb;
  ASSERT_TRUE(bound_passively(p, &reach));
  EXPECT_TRUE(reach.v_cap.empty());
  ASSERT_EQ(reach.reach.size(), 1u);
  EXPECT_EQ(reach.num_constraints(), pb.num_constraints() + pb.N);
  const double tol = 1e-6;
  EXPECT_LT(reach_slack(reach, turn_then_drive(pb, 0.0, 1.0)), -0.05) << "straight at it";
  EXPECT_GE(reach_slack(reach, turn_then_drive(pb, 0.5 * M_PI, 1.0)), -tol) << "out of its way";
  EXPECT_GE(reach_slack(reach, turn_then_drive(pb, -0.5 * M_PI, 1.0)), -tol) << "out of its way";
  EXPECT_GE(reach_slack(reach, std::vector<double>(static_cast<size_t>(pb.num_controls()), 0.0)), -tol) << "standing";
  // the speed bound caps the way out too
  p.braking_point = false;
  Problem capped = pb;
  ASSERT_TRUE(bound_passively(p, &capped));
  EXPECT_TRUE(capped.reach.empty());
  const std::vector<double> out = turn_then_drive(pb, 0.5 * M_PI, 1.0);
  double fastest = 0.0;
  for (int k = 0; k < pb.N; ++k) fastest = std::max(fastest, out[2 * static_cast<size_t>(k)]);
  EXPECT_GT(fastest, capped.v_cap[0] + 0.1);
}

// Whatever the bound, braking from the measured controls meets it: the
// bounds never ask more than braking gives (here a walker 0.6 m ahead of
// a robot at up to 1 m/s, coming at 1 m/s; at 1 m/s braking misses the
// bound at the first steps).
TEST(PassiveSafety, BrakingAlwaysMeetsTheReachBounds) {
  const PassiveSafetyParams p = slow_reaction();
  bool missed = false;
  for (double v0 : {0.0, 0.5, 1.0}) {
    Problem free = robot_and_walker(0.21 + 0.6 + 0.3, 0.0, -1.0, 0.0, 3.0);
    free.v_prev = v0;
    free.omega_prev = 0.4;
    Problem pb = free;
    ASSERT_TRUE(bound_passively(p, &pb));
    for (double a : pb.reach[0].allowance_m) missed |= a > 0.0;
    std::vector<double> brake(static_cast<size_t>(pb.num_controls()), 0.0);
    project_controls(pb, &brake);
    EXPECT_GE(reach_slack(pb, brake), -1e-9) << "v0 " << v0;
    // keeping the speed reaches further than that
    if (v0 > 0) {
      EXPECT_LT(reach_slack(pb, turn_then_drive(free, 0.0, v0)), -0.01) << "v0 " << v0;
    }
  }
  EXPECT_TRUE(missed) << "the premise: some step asks more than braking gives";
}

// project_onto_reach slows a plan that drives at a walker until every
// step keeps the bound, within the rate limits; braking, and a plan it
// projected already, stay as they are.
TEST(PassiveSafety, ProjectionSlowsAPlanOntoTheReachBounds) {
  const PassiveSafetyParams p = slow_reaction();
  Problem pb = robot_and_walker(1.8, 0.0, -1.0, 0.0, 3.0);
  pb.v_prev = 0.8;
  ASSERT_TRUE(bound_passively(p, &pb));
  std::vector<double> on = turn_then_drive(pb, 0.0, 1.0);
  ASSERT_LT(reach_slack(pb, on), -0.05);  // the premise
  ASSERT_TRUE(project_onto_reach(pb, &on));
  EXPECT_GE(reach_slack(pb, on), -1e-6);
  std::vector<double> states, g;
  evaluate_constraints(pb, on.data(), &states, &g);
  for (int j = 0; j < pb.num_rate_constraints(); ++j) EXPECT_GE(g[static_cast<size_t>(j)], -1e-9) << "rate " << j;
  // no slower than it must: at step 0 a little faster misses the bound
  ASSERT_LT(on[0], 0.8);
  ASSERT_GT(on[0], 0.8 - kDecel * pb.dt);
  double g_faster = std::numeric_limits<double>::infinity();
  for (const ReachBound& r : pb.reach)
    g_faster = std::min(g_faster, reach_value(r, 0, 0, 0, 0, on[0] + 0.005, false).g);
  EXPECT_LT(g_faster, 0.0);
  std::vector<double> brake(static_cast<size_t>(pb.num_controls()), 0.0);
  project_controls(pb, &brake);
  const std::vector<double> braking = brake;
  EXPECT_FALSE(project_onto_reach(pb, &brake));
  EXPECT_EQ(brake, braking);
  // projecting again changes nothing
  const std::vector<double> once = on;
  EXPECT_FALSE(project_onto_reach(pb, &on));
  EXPECT_EQ(on, once);
}

// ---- turn_bound: a turn on the spot swings the footprint's end discs ----

constexpr double kAlpha = 3.0;  // testing::default_limits()' turn-rate limit, rad/s^2

TEST(PassiveTurn, FromTheRateTheTurnSlowsBeforeTheMoverCanReachThePoint) {
  const double tau = 0.15;
  for (double r : {0.0, 0.05}) {
    for (double s : {0.0, 0.5, 1.4, 5.0}) {
      EXPECT_TRUE(std::isinf(passive_safe_turn_rate(0.2, s, 0.0, tau, kAlpha, r))) << "a point that does not swing";
      for (double q : {0.1, 0.31, 0.6}) {
        for (double gap : {0.05, 0.2, 0.5, 1.0}) {
          const double w = passive_safe_turn_rate(gap, s, q, tau, kAlpha, r), wr = r / q;
          const std::string at = "r " + std::to_string(r) + " s " + std::to_string(s) + " q " + std::to_string(q) +
                                 " gap " + std::to_string(gap);
          ASSERT_GE(w, wr) << at << ": the residual swing is never bound";
          if (w == wr) {  // any faster comes too fast before the mover could be there
            EXPECT_GE(s * tau + q * wr * tau, gap - 1e-9) << at;
            continue;
          }
          // the mover's way until the turn is down to wr and the point's swing meanwhile fill the gap
          EXPECT_NEAR(s * (tau + (w - wr) / kAlpha) + q * (w * tau + (w * w - wr * wr) / (2 * kAlpha)), gap, 1e-9)
              << at;
        }
      }
    }
  }
  EXPECT_EQ(passive_safe_turn_rate(0.1, 1.0, 0.31, tau, kAlpha, 0.0), 0.0) << "within its reach before any turn stops";
  // nearer, faster or a longer lever: slower; a residual: faster
  const auto rate = [&](double gap, double s, double q, double r) {
    return passive_safe_turn_rate(gap, s, q, tau, kAlpha, r);
  };
  EXPECT_LT(rate(0.3, 1.2, 0.31, 0.0), rate(0.5, 1.2, 0.31, 0.0));
  EXPECT_LT(rate(0.5, 1.6, 0.31, 0.0), rate(0.5, 1.2, 0.31, 0.0));
  EXPECT_LT(rate(0.5, 1.2, 0.31, 0.0), rate(0.5, 1.2, 0.1, 0.0));
  EXPECT_LT(rate(0.5, 1.2, 0.31, 0.0), rate(0.5, 1.2, 0.31, 0.05));
}

// The Scout 2.0 (0.93 x 0.70 m, three discs 0.31 m apart) at the origin
// facing +y, and a walker of radius 0.3 m at (x, y) walking at (vx, vy),
// tracked 3 s.
Problem scout_and_walker(double x, double y, double vx, double vy) {
  Problem pb = straight_problem(0, 0, M_PI / 2, 0.0, 0.5);
  pb.footprint = Footprint::covering(0.93, 0.70, 3);
  pb.d_safe = 0.15;
  ObstacleTrack w = moving_obstacle(3, x, y, vx, vy, 0.3, 0.3, 0.0, 0.9, pb.N, pb.dt);
  w.age_s = 3.0;
  pb.obstacles = {w};
  return pb;
}

TEST(PassiveTurn, AWalkerBesideTheRearBoundsTheTurnThatSwingsTheRearToIt) {
  const PassiveSafetyParams p;  // config/robot.yaml's reaction
  // on the robot's left (-x) beside its rear half, 0.17 m from its side,
  // walking away to the left at 1.2 m/s: a clockwise turn swings the rear
  // towards it
  const Problem pb = scout_and_walker(-0.82, -0.4, -1.2, 0.0);
  const TurnBounds t = passive_turn_bounds(p, pb);
  // clockwise: the rear corner, 0.465 m from the base, swings into its
  // reach; it may still come at the residual
  const double residual = p.turn_residual_mps / 0.465;
  EXPECT_NEAR(t.lo, -residual, 1e-9) << "clockwise: the rear swings into its reach";
  EXPECT_EQ(t.hi, pb.lim.omega_max) << "counter-clockwise swings the rear away";
  // the same walker on the right: the other way round
  const TurnBounds right = passive_turn_bounds(p, scout_and_walker(0.82, -0.4, 1.2, 0.0));
  EXPECT_NEAR(right.hi, residual, 1e-9);
  EXPECT_EQ(right.lo, -pb.lim.omega_max);
  // 2 m away, or standing for seconds: no bound
  const TurnBounds far = passive_turn_bounds(p, scout_and_walker(-2.5, -0.4, -1.2, 0.0));
  EXPECT_EQ(far.lo, -pb.lim.omega_max);
  EXPECT_EQ(far.hi, pb.lim.omega_max);
  const TurnBounds standing = passive_turn_bounds(p, scout_and_walker(-0.82, -0.4, 0.0, 0.0));
  EXPECT_EQ(standing.lo, -pb.lim.omega_max);
  // walking at the rear along its length (into the standing robot): the
  // turn swings the rear along its way, which gets nothing out of it, so
  // the bound stays
  const TurnBounds oncoming = passive_turn_bounds(p, scout_and_walker(-0.82, -0.4, 1.2, 0.0));
  EXPECT_NEAR(oncoming.lo, -residual, 1e-9);
  // the paper's point robot swings nothing
  Problem point = scout_and_walker(-0.82, -0.4, -1.2, 0.0);
  point.footprint = Footprint{};
  const TurnBounds none = passive_turn_bounds(p, point);
  EXPECT_EQ(none.lo, -pb.lim.omega_max);
  EXPECT_EQ(none.hi, pb.lim.omega_max);
}

// A dog running back past the middle of the robot's left side: the side's
// nearest point only slides along itself, whichever way the robot turns,
// but the dog reaches either corner before a turn at the limit stops, and
// each turn swings one corner out to the side.
TEST(PassiveTurn, ADogRunningPastTheSideBoundsTheTurnThatSwingsEitherCornerToIt) {
  const PassiveSafetyParams p;
  // the Scout faces +y: its left side is at x = -0.35, the dog's body
  // 0.25 m from it, running at 2.5 m/s towards -y
  const TurnBounds dog = passive_turn_bounds(p, scout_and_walker(-0.9, 0.0, 0.0, -2.5));
  EXPECT_GT(dog.lo, -0.3) << "clockwise swings the rear corner out";
  EXPECT_LE(dog.lo, 0.0);
  EXPECT_LT(dog.hi, 0.3) << "counter-clockwise swings the front corner out";
  EXPECT_GE(dog.hi, 0.0);
  // a walker there at 1 m/s cannot get round to a corner in time: the
  // turn is free both ways (the limit)
  const Problem walking = scout_and_walker(-0.9, 0.0, 0.0, -1.0);
  const TurnBounds walker = passive_turn_bounds(p, walking);
  EXPECT_EQ(walker.lo, -walking.lim.omega_max);
  EXPECT_EQ(walker.hi, walking.lim.omega_max);
}

// A turn on the spot moves the front edge's sides forwards: a walker ahead
// of the left side bounds the counter-clockwise turn. But where the
// walker's way along a lane passes through the robot standing (the robot
// at -0.3 rad to the lane, its rear corner sticks out into it) and the
// same turn, made at the limits, straightens the robot out of the lane
// before the walker gets there, the turn is not bound.
TEST(PassiveTurn, ATurnThatGetsTheBodyOutOfAWalkersWayInTimeIsNotBound) {
  const PassiveSafetyParams p;
  const auto scout_at = [](double vx, double vy) {
    Problem pb = scout_and_walker(0.3, 0.7, vx, vy);
    pb.yaw0 = -0.3;
    pb.obstacles[0] = moving_obstacle(3, 0.3, 0.7, vx, vy, 0.25, 0.25, 0.0, 0.9, pb.N, pb.dt);
    pb.obstacles[0].age_s = 3.0;
    return pb;
  };
  // walking up and away at 1.2 m/s: it never meets the standing robot;
  // the left side's forward swing is bound
  const TurnBounds away = passive_turn_bounds(p, scout_at(0.0, 1.2));
  EXPECT_LT(away.hi, 0.45);
  EXPECT_GT(away.hi, 0.0);
  // coming down the lane past the robot at 1.2 m/s: standing, its rear
  // corner is met; a little turned it is not, and the turn at the limits
  // gets there first
  const Problem lane_pb = scout_at(-1.2, 0.0);
  const TurnBounds lane = passive_turn_bounds(p, lane_pb);
  EXPECT_EQ(lane.hi, lane_pb.lim.omega_max);
  // at 3 m/s cutting into the lane towards the rear corner: the turn
  // cannot get the corner out of its way first, the bound stays
  const TurnBounds fast = passive_turn_bounds(p, scout_at(-3.0, -0.3));
  EXPECT_LT(fast.hi, 0.45);
  // the same mirrored (the robot at +0.3 rad, the walker on its right):
  // the clockwise turn
  const auto mirrored = [&](double vx, double vy) {
    Problem pb = scout_at(vx, -vy);
    pb.yaw0 = 0.3;
    pb.obstacles[0] = moving_obstacle(3, 0.3, -0.7, vx, -vy, 0.25, 0.25, 0.0, 0.9, pb.N, pb.dt);
    pb.obstacles[0].age_s = 3.0;
    return passive_turn_bounds(p, pb);
  };
  EXPECT_NEAR(mirrored(0.0, 1.2).lo, -away.hi, 1e-9);
  EXPECT_EQ(mirrored(-1.2, 0.0).lo, -lane_pb.lim.omega_max);
  EXPECT_NEAR(mirrored(-3.0, -0.3).lo, -fast.hi, 1e-9);
}

TEST(PassiveTurn, TheSolvedPlansFirstTurnKeepsTheBound) {
  const PassiveSafetyParams p;
  // the route runs along +x: the robot facing +y wants to turn clockwise
  Problem pb = scout_and_walker(-0.82, -0.4, -1.2, 0.0);
  const CeresMpcSolver solver{SolverOptions{}};
  const SolveResult free = solver.solve(pb, std::vector<double>(pb.num_controls(), 0.0));
  ASSERT_TRUE(free.finite);
  ASSERT_LT(free.u[1], -0.2) << "the premise: unbounded, it turns clockwise at once";
  ASSERT_TRUE(bound_turn_passively(p, &pb));
  ASSERT_EQ(pb.omega_lo.size(), static_cast<size_t>(pb.N));
  EXPECT_EQ(pb.omega_lo[1], -pb.lim.omega_max) << "later steps are the next cycles' to bound";
  const SolveResult bounded = solver.solve(pb, std::vector<double>(pb.num_controls(), 0.0));
  ASSERT_TRUE(bounded.finite);
  EXPECT_GE(bounded.u[1], pb.omega_lo[0] - 1e-9);
  EXPECT_LE(bounded.u[1], pb.omega_hi[0] + 1e-9);
  // project_controls keeps it too, from a turn already under way
  pb.omega_prev = -0.5;
  std::vector<double> u = testing::constant_controls(pb, 0.0, -0.5);
  project_controls(pb, &u);
  EXPECT_NEAR(u[1], -0.5 + pb.lim.alpha * pb.dt, 1e-12) << "slowed as fast as the limit allows";
  // no mover near: nothing bound, pb unchanged
  Problem clear = scout_and_walker(-3.0, -0.4, -1.2, 0.0);
  EXPECT_FALSE(bound_turn_passively(p, &clear));
  EXPECT_TRUE(clear.omega_lo.empty());
}

}  // namespace
}  // namespace evade::planning
