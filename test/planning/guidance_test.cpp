// Guidance (distinct ways through the predicted obstacles), the local
// solves side by side, and the choice among them (lib/planning/guidance.h,
// local_solves.h, selection.h, topology_planner.h).
#include "planning/guidance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "evade/plan_t.hpp"
#include "planning/local_solves.h"
#include "planning/selection.h"
#include "planning/topology_planner.h"
#include "test_problems.h"

namespace evade::planning {
namespace {

using testing::bench_problem;
using testing::moving_obstacle;
using testing::straight_problem;

constexpr double kDecay = 0.9;

GuidanceParams params(int max_classes = 4) {
  GuidanceParams g;
  g.max_classes = max_classes;
  return g;
}

int label_of(const Signature& s, int64_t id) {
  for (const auto& [i, l] : s.labels)
    if (i == id) return l;
  return 99;
}

// A straight line of positions at lateral offset y, ahead at speed v.
void line(const Problem& pb, double y, double v, std::vector<double>* xs, std::vector<double>* ys) {
  xs->clear();
  ys->clear();
  for (int k = 0; k <= pb.N; ++k) {
    xs->push_back(pb.x0 + v * pb.dt * k);
    ys->push_back(y * std::min(1.0, k / 5.0));
  }
}

Problem one_static_obstacle() {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.obstacles.push_back(moving_obstacle(7, 2.0, 0.0, 0, 0, 0.3, 0.3, 0, kDecay, pb.N, pb.dt));
  return pb;
}

TEST(Guidance, OneObstacleOnTheRouteGivesTwoClassesLeftAndRight) {
  const Problem pb = one_static_obstacle();
  const std::vector<GuidancePath> ways = find_guidance(pb, params());
  ASSERT_EQ(ways.size(), 3u);  // left, right, and waiting short of it
  std::set<int> labels;
  for (const auto& w : ways) labels.insert(label_of(w.signature, 7));
  EXPECT_EQ(labels, (std::set<int>{-1, 0, 1}));
  for (const GuidancePath& w : ways) {
    const int side = label_of(w.signature, 7);
    // level with the obstacle the path is on the side its label says, clear of d_safe
    for (int k = 0; k <= pb.N; ++k) {
      if (std::fabs(w.x[k] - 2.0) > 0.05) continue;
      EXPECT_GT(side * w.y[k], 0.3 + pb.d_safe - 1e-9) << "k " << k;
    }
    EXPECT_LE(ways[0].cost, w.cost);
  }
}

TEST(Guidance, TwoTrajectoriesOfTheSameClassAreOneClass) {
  const Problem pb = one_static_obstacle();
  const RouteFrame f = route_frame(pb);
  std::vector<double> xs, ys;
  line(pb, 0.8, 0.9, &xs, &ys);
  const Signature near_left = path_signature(pb, f, xs, ys);
  line(pb, 1.6, 0.95, &xs, &ys);
  const Signature far_left = path_signature(pb, f, xs, ys);
  line(pb, -0.9, 0.9, &xs, &ys);
  const Signature right = path_signature(pb, f, xs, ys);
  line(pb, 0.0, 0.1, &xs, &ys);  // never gets level with it: side undecided
  const Signature short_of_it = path_signature(pb, f, xs, ys);
  EXPECT_EQ(label_of(near_left, 7), 1);
  EXPECT_EQ(label_of(far_left, 7), 1);
  EXPECT_EQ(label_of(right, 7), -1);
  EXPECT_EQ(label_of(short_of_it, 7), 0);
  EXPECT_TRUE(same_class(near_left, far_left));
  EXPECT_FALSE(same_class(near_left, right));
  EXPECT_FALSE(same_class(short_of_it, right));  // waiting is a way of its own...
  EXPECT_TRUE(compatible(short_of_it, right));   // ...that either side may follow
  EXPECT_TRUE(compatible(short_of_it, near_left));
  EXPECT_FALSE(compatible(near_left, right));
}

TEST(Guidance, ACrossingMoverIsPassedBeforeOrBehind) {
  Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
  pb.lim.v_max = 2.0;  // fast enough to cross its way before it arrives
  // from the left, crossing the route 1.5 m ahead at 1.5 s
  pb.obstacles.push_back(moving_obstacle(3, 1.5, 1.5, 0, -1.0, 0.25, 0.25, 0, kDecay, pb.N, pb.dt));
  const std::vector<GuidancePath> ways = find_guidance(pb, params());
  ASSERT_GE(ways.size(), 2u);
  std::set<int> labels;
  for (const auto& w : ways) labels.insert(label_of(w.signature, 3));
  EXPECT_TRUE(labels.count(1) && labels.count(-1));  // behind it (on its left) and ahead of it
}

TEST(Guidance, ManyObstaclesGiveAtMostMaxClassesAllDistinct) {
  const Problem pb = bench_problem(16);
  for (int max_classes : {1, 3, 6}) {
    const std::vector<GuidancePath> ways = find_guidance(pb, params(max_classes));
    EXPECT_GE(ways.size(), 1u);
    EXPECT_LE(static_cast<int>(ways.size()), max_classes);
    for (size_t i = 0; i < ways.size(); ++i)
      for (size_t j = i + 1; j < ways.size(); ++j) EXPECT_FALSE(same_class(ways[i].signature, ways[j].signature));
  }
  EXPECT_TRUE(find_guidance(pb, params(0)).empty());
}

TEST(Guidance, TheSameProblemGivesTheSamePaths) {
  const Problem pb = bench_problem(8);
  const auto a = find_guidance(pb, params()), b = find_guidance(pb, params());
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].signature.labels, b[i].signature.labels);
  }
}

TEST(Guidance, ASolveFromEachWayEndsInItsClass) {
  const Problem pb = one_static_obstacle();
  const std::vector<GuidancePath> ways = find_guidance(pb, params());
  ASSERT_FALSE(ways.empty());
  for (const GuidancePath& w : ways) {
    std::vector<double> u = controls_along(pb, w);
    std::vector<double> projected = u;
    project_controls(pb, &projected);
    EXPECT_EQ(u, projected);  // within the bounds and rate limits already
    std::vector<double> states(3 * (pb.N + 1));
    rollout(pb, u.data(), states.data());
    // it heads the path's way (turning at the limits it lags behind it)
    if (std::fabs(w.y[pb.N]) > 0.2) {
      EXPECT_GT(states[3 * pb.N + 1] * w.y[pb.N], 0.0);
    }
    // and the local solve from it, the path as its reference, ends in the path's class
    SolverOptions o;
    const SolveResult r = CeresMpcSolver(o).solve(along_guidance(pb, w), u);
    ASSERT_TRUE(r.feasible);
    EXPECT_TRUE(same_class(states_signature(pb, route_frame(pb), r.states), w.signature));
  }
}

TEST(LocalSolves, ResultsDoNotDependOnTheNumberOfThreads) {
  const Problem pb = bench_problem(8);
  std::vector<SolveStart> starts{{std::vector<double>(2 * pb.N, 0.5)}};
  for (const GuidancePath& w : find_guidance(pb, params())) starts.push_back({controls_along(pb, w)});
  const std::vector<int> budgets = local_budgets(600, 300, static_cast<int>(starts.size()));
  const SolverOptions o;
  const auto one = solve_side_by_side(pb, starts, o, budgets, 1);
  for (int threads : {2, 3, 8}) {
    for (int repeat = 0; repeat < 3; ++repeat) {
      const auto many = solve_side_by_side(pb, starts, o, budgets, threads);
      ASSERT_EQ(many.size(), one.size());
      for (size_t i = 0; i < one.size(); ++i) {
        EXPECT_EQ(many[i].u, one[i].u) << "solve " << i << " threads " << threads;
        EXPECT_EQ(many[i].iterations, one[i].iterations);
        EXPECT_LE(many[i].iterations, budgets[i]) << "solve " << i;
      }
    }
  }
}

TEST(LocalSolves, ThePreviousPlanKeepsOneSolvesBudgetTheWaysShareTheRest) {
  // the previous plan's solve gets what the one solve of a cycle without
  // guidance gets; the ways share what is left
  EXPECT_EQ(local_budgets(600, 300, 5), (std::vector<int>{300, 75, 75, 75, 75}));
  EXPECT_EQ(local_budgets(600, 300, 3), (std::vector<int>{300, 150, 150}));
  EXPECT_EQ(local_budgets(900, 300, 2), (std::vector<int>{300, 300}));  // each at most one solve's
  EXPECT_EQ(local_budgets(600, 300, 1), (std::vector<int>{300}));
  EXPECT_EQ(local_budgets(3, 300, 3), (std::vector<int>{1, 1, 1}));  // at least 1 each
}

TEST(LocalSolves, ThreadsAreBalancedBeforeSolvingAndTheBusiestIsCharged) {
  // the previous plan's solve on one thread, the ways on the other
  const std::vector<int> t = assign_threads({300, 75, 75, 75, 75}, 2);
  EXPECT_EQ(t, (std::vector<int>{0, 1, 1, 1, 1}));
  EXPECT_EQ(assign_threads({10, 10, 10}, 8), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(assign_threads({10, 10, 10}, 1), (std::vector<int>{0, 0, 0}));
  std::vector<SolveResult> r(5);
  for (int i = 0; i < 5; ++i) r[i].iterations = 10 * (i + 1);  // 10 20 30 40 50
  EXPECT_EQ(critical_iterations(r, {0, 0, 0, 0, 0}), 150);
  EXPECT_EQ(critical_iterations(r, t), 140);  // 20 + 30 + 40 + 50
  EXPECT_EQ(critical_iterations(r, {0, 1, 2, 3, 4}), 50);
}

Candidate candidate(double cost, bool feasible, int label, double violation = 0.0) {
  Candidate c;
  c.cost = cost;
  c.feasible = feasible;
  c.violation = violation;
  c.signature.labels = {{1, label}};
  return c;
}

TEST(Selection, CheapestFeasibleWithASwitchingPenalty) {
  const std::vector<Candidate> c{candidate(10, true, 1), candidate(9, true, -1), candidate(1, false, -1, 0.5)};
  EXPECT_EQ(select_plan(c, std::nullopt, 1.3), 1);  // no previous class: the cheapest
  Signature left;
  left.labels = {{1, 1}};
  EXPECT_EQ(select_plan(c, left, 1.3), 0);   // 9 x 1.3 > 10: keep the side
  EXPECT_EQ(select_plan(c, left, 1.05), 1);  // 9 x 1.05 < 10: the other side is cheaper enough
  EXPECT_EQ(select_plan({candidate(1, false, 1, 0.2), candidate(1, false, 1, 0.1)}, left, 1.3), -1);
  EXPECT_EQ(least_violating({candidate(1, false, 1, 0.2), candidate(1, false, 1, 0.1)}), 1);
}

TEST(Selection, APlanThroughAnObstacleIsMarkedInfeasible) {
  const Problem pb = one_static_obstacle();
  std::vector<double> straight(2 * pb.N);
  for (int k = 0; k < pb.N; ++k) straight[2 * k] = 0.8;  // drives through it
  const Candidate c = check_plan(pb, route_frame(pb), straight, 1e-3);
  EXPECT_FALSE(c.feasible);
  EXPECT_GT(c.violation, 0.1);
  std::vector<double> standing(2 * pb.N, 0.0);
  Problem at_rest = pb;
  at_rest.v_prev = 0.0;
  EXPECT_TRUE(check_plan(at_rest, route_frame(pb), standing, 1e-3).feasible);
}

TEST(TopologyPlanner, EveryClassIsSolvedAndTheChoiceMeetsEveryConstraint) {
  const Problem pb = one_static_obstacle();
  SolverOptions s;
  TopologyPlanner planner(params(), s, 900);
  std::vector<double> warm(2 * pb.N, 0.0);
  for (int k = 0; k < pb.N; ++k) warm[2 * k] = 0.8;
  const TopologyOutcome o = planner.plan(pb, {warm}, std::vector<double>(2 * pb.N, 0.0));
  EXPECT_EQ(o.classes, 3);
  EXPECT_EQ(o.solves, 4);
  EXPECT_EQ(o.status, +evade::plan_t::STATUS_OK);
  EXPECT_LE(max_violation(pb, o.u.data()), s.constraint_tolerance);
  EXPECT_LE(o.iterations, 900);
  EXPECT_LE(o.critical_iterations, o.iterations);
  // the same inputs give the same plan, whatever the threads did
  for (int i = 0; i < 5; ++i) {
    TopologyPlanner again(params(), s, 900);
    EXPECT_EQ(again.plan(pb, {warm}, std::vector<double>(2 * pb.N, 0.0)).u, o.u);
  }
}

TEST(TopologyPlanner, NothingFeasibleFallsBackToTheLeastViolatingPlan) {
  Problem pb = straight_problem(0, 0, 0, 1.0, 0.8);
  // a wall of obstacles just ahead, closing in faster than the robot can brake
  for (int i = 0; i < 5; ++i)
    pb.obstacles.push_back(moving_obstacle(i, 0.7, -1.0 + 0.5 * i, -1.5, 0, 0.3, 0.3, 0, kDecay, pb.N, pb.dt));
  SolverOptions s;
  TopologyPlanner planner(params(), s, 900);
  std::vector<double> warm(2 * pb.N, 0.0);
  for (int k = 0; k < pb.N; ++k) warm[2 * k] = 1.0;
  std::vector<double> brake(2 * pb.N, 0.0);
  const TopologyOutcome o = planner.plan(pb, {warm}, brake);
  EXPECT_NE(o.status, +evade::plan_t::STATUS_OK);
  std::vector<double> projected = o.u;
  project_controls(pb, &projected);
  EXPECT_EQ(projected, o.u);  // within the bounds and rate limits
  std::vector<double> b = brake;
  project_controls(pb, &b);
  EXPECT_LE(max_violation(pb, o.u.data()), max_violation(pb, b.data()) + 1e-12);
  // the solve from the previous plan, within one solve's budget, is handed
  // on for the recovery (planner_guidance.cpp), whichever violates least
  SolverOptions one = s;
  one.max_total_iterations = local_budgets(900, s.max_total_iterations, o.solves)[0];
  const SolveResult alone = CeresMpcSolver(one).solve(pb, warm);
  EXPECT_EQ(o.previous.u, alone.u);
  EXPECT_EQ(o.previous.iterations, alone.iterations);
}

}  // namespace
}  // namespace evade::planning

namespace evade::planning {
namespace {

// The side (+1 left, -1 right, 0 neither) each of 8 cycles chooses round a
// walker coming head-on along the route whose predicted lateral position
// jitters by +-3 cm from cycle to cycle (as a tracker's estimate does):
// each cycle the other side is the cheaper one.
std::vector<int> head_on_sides(double switch_cost_factor) {
  GuidanceParams g = params();
  g.switch_cost_factor = switch_cost_factor;
  TopologyPlanner planner(g, SolverOptions{}, 600);
  std::vector<int> sides;
  std::vector<double> previous;  // the last plan: the start without guidance, as the planner has it
  for (int c = 0; c < 8; ++c) {
    Problem pb = straight_problem(0, 0, 0, 0.8, 0.8);
    const double jitter = c % 2 == 0 ? 0.03 : -0.03;
    pb.obstacles.push_back(moving_obstacle(1, 3.0, jitter, -0.5, 0, 0.3, 0.3, 0, kDecay, pb.N, pb.dt));
    if (previous.empty()) {
      previous.assign(2 * pb.N, 0.0);
      for (int k = 0; k < pb.N; ++k) previous[2 * k] = 0.8;  // straight on
    }
    const TopologyOutcome o = planner.plan(pb, {previous}, std::vector<double>(2 * pb.N, 0.0));
    previous = o.u;
    std::vector<double> states(3 * (pb.N + 1));
    rollout(pb, o.u.data(), states.data());
    const double y = states[3 * pb.N + 1];
    sides.push_back(y > 0.05 ? 1 : y < -0.05 ? -1 : 0);
  }
  return sides;
}

TEST(TopologyPlanner, ASymmetricHeadOnKeepsItsSide) {
  const std::vector<int> free = head_on_sides(1.0);
  int changes = 0;
  for (size_t i = 1; i < free.size(); ++i) changes += free[i] != free[i - 1] ? 1 : 0;
  std::string seq;
  for (int s : free) seq += std::to_string(s) + " ";
  ASSERT_GE(changes, 4) << "the premise: without a switching penalty the cheaper side alternates: " << seq;
  const std::vector<int> kept = head_on_sides(params().switch_cost_factor);
  EXPECT_NE(kept[0], 0);
  for (int s : kept) EXPECT_EQ(s, kept[0]) << "the robot alternated sides";
}

}  // namespace
}  // namespace evade::planning
