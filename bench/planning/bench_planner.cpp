// Ceres (augmented Lagrangian, the planner's solver) against IPOPT on the
// same fixed MPC problems with k = 0, 4, 8, 16 obstacles, both from the
// same start:
//   solve/ceres/<k>       warm, as the planner runs (planner.solver.warm_multipliers: false): the
//                         previous cycle's (0.1 s earlier) controls shifted one step; the
//                         solver estimates the multipliers at that warm start
//   solve/ipopt_warm/<k>  IPOPT from the same controls (states rolled out from them), exact
//                         Hessian, its stopping rule matched to Ceres' (ipopt_options)
//   solve/ipopt_warm_lbfgs/<k>  the same with L-BFGS instead of the exact Hessian
//   solve/ceres_cold/<k>  Ceres from zero controls
//   solve/ipopt/<k>       IPOPT from zero controls (states rolled out: the robot standing)
//   solve/ipopt_lbfgs/<k> the same with L-BFGS
//   solve/ceres_warm_multipliers/<k>  also the previous cycle's multipliers (shifted) with its
//                         penalty (capped by warm_penalty_max), for the record
//   loop/ceres/<k>        30 planner cycles (robot and obstacles moving), per-cycle counters
//   static_field/<k>      the distance field of a 16 x 16 m map at 0.1 m (a wall with a door)
//                         less k movers' cells (static_field.h), per planning cycle
//   static_field_log/<w>  StaticStructure::update over every ELEVATION_MAP of a recorded log
//                         with its OBSTACLE_PREDICTIONS, OBSTACLES and ODOMETRY, per map;
//                         w = 0: the field over the whole map, 1: within the planner's reach
//                         (static_field_reach_m) of the odometry, 2: that grown to hold the point
//                         detour.lookahead_m + cell_m ahead along the heading (the planner's window
//                         on a straight route)
//                         (the log: $EVADE_BENCH_FIELD_LOG, else the golden case's 240 x 240
//                         maps, logs/street_pedestrians/refs/elevation_map.lcmlog: no tracks)
//   detour/<k>            the way round k settled obstacles, one of them wide on the route
//                         (detour.h, config/robot.yaml planner.detour), per planning cycle
//   guidance/<k>          the distinct ways through the k obstacles of the fixed problem
//                         (guidance.h, config/robot.yaml planner.guidance), per planning cycle
//   cycle/guidance/<k>    guidance, the local solves side by side (planner.guidance.threads)
//                         and the choice (topology_planner.h): mode evade's whole cycle
//   outcome/<k>           the recovery's judgement of its 17 open-loop candidates (2 dashes,
//                         10 pull-overs, 2 swerves, the failed solve's, the last plan shifted,
//                         braking) against the k obstacles: each projected on the limits,
//                         rolled out, its least h, shortfall and plan_outcome over 2N steps
//                         (planner_recovery.cpp's most_clearance, planner.solver.rank_outcome)
// After the runs a table gives, per start, each solver's CPU time per solve
// (the thread's CPU clock, so that other programs on the machine change it
// less), the ratio IPOPT / Ceres against the faster IPOPT variant, and each
// solution's cost against IPOPT's run to tol 1e-8 from the same start.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <map>
#include <string>

#include "bus/core.h"
#include "bus/log.h"
#include "config/config.h"
#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/ceres_solver.h"
#include "planning/detour.h"
#include "planning/guidance.h"
#include "planning/ipopt_solver.h"
#include "planning/manoeuvres.h"
#include "planning/outcome.h"
#include "planning/params.h"
#include "planning/passive_safety.h"
#include "planning/planner_core.h"
#include "planning/reference.h"
#include "planning/static_field.h"
#include "planning/static_structure.h"
#include "planning/topology_planner.h"
#include "test_problems.h"

namespace {

using evade::planning::CeresMpcSolver;
using evade::planning::IpoptResult;
using evade::planning::Problem;
using evade::planning::SolveResult;
using evade::planning::SolverOptions;

struct Warm {
  std::vector<double> u, lambda;
  double penalty = 0;
};

// The previous cycle (0.1 s earlier) solved, its solution shifted one step.
Warm warm_start(int k, const CeresMpcSolver& solver) {
  const Problem prev = evade::planning::testing::bench_problem(k, -0.1);
  const SolveResult r = solver.solve(prev, std::vector<double>(2 * prev.N, 0.0));
  Warm w;
  const int N = prev.N, R = prev.num_rate_constraints();
  w.u.resize(r.u.size());
  for (int s = 0; s < N; ++s) {
    const int src = std::min(s + 1, N - 1);
    w.u[2 * s] = r.u[2 * src];
    w.u[2 * s + 1] = r.u[2 * src + 1];
  }
  w.penalty = r.penalty;
  w.lambda.assign(r.multipliers.size(), 0.0);
  for (int j = 4; j + 4 < R; ++j) w.lambda[j] = r.multipliers[j + 4];
  for (int i = 0; i < k; ++i)
    for (int s = 0; s + 1 < N; ++s) w.lambda[R + i * N + s] = r.multipliers[R + i * N + s + 1];
  return w;
}

// One solver's last result on one problem: cost, violation, CPU ms per
// solve, iterations.
struct Row {
  double cost = 0, viol = 0, cpu_ms = 0, iters = 0;
  double outer = 0;  // Ceres' outer (AL) iterations; 0 for IPOPT
  bool ok = false;   // Ceres: feasible; IPOPT: solved
};
// by (solver, start) and k
std::map<std::string, std::map<int, Row>> g_rows;

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Runs `solve` (returning cost, violation and iterations) for the
// benchmark's iterations; records the counters and g_rows[name][k].
template <class F>
void run_solves(benchmark::State& state, const std::string& name, int k, F solve) {
  Row row;
  long solves = 0;
  const double t0 = thread_cpu_s();
  for (auto _ : state) {
    row = solve();
    benchmark::DoNotOptimize(row.cost);
    ++solves;
  }
  row.cpu_ms = 1e3 * (thread_cpu_s() - t0) / static_cast<double>(std::max(1L, solves));
  state.counters["cost"] = row.cost;
  state.counters["viol"] = row.viol;
  state.counters["iters"] = row.iters;
  if (row.outer > 0) state.counters["outer"] = row.outer;
  state.counters[row.outer > 0 ? "feasible" : "solved"] = row.ok;
  g_rows[name][k] = row;
}

Row ceres_row(const SolveResult& r) {
  return {r.cost,    r.max_violation, 0, static_cast<double>(r.iterations), static_cast<double>(r.outer_iterations),
          r.feasible};
}
Row ipopt_row(const IpoptResult& r) {
  return {r.cost, r.max_violation, 0, static_cast<double>(r.iterations), 0, r.solved};
}

void BM_Ceres(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  CeresMpcSolver solver{SolverOptions{}};
  const Warm w = warm_start(k, solver);
  run_solves(state, "ceres warm", k, [&] { return ceres_row(solver.solve(pb, w.u)); });
}

void BM_CeresCold(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  CeresMpcSolver solver{SolverOptions{}};
  const std::vector<double> zeros(2 * pb.N, 0.0);
  run_solves(state, "ceres cold", k, [&] { return ceres_row(solver.solve(pb, zeros)); });
}

// IPOPT's warm-start settings (see ipopt_options); the environment's
// EVADE_BENCH_IPOPT_WARM_MU_INIT replaces the first.
constexpr double kWarmMuInit = 0.1;
constexpr double kWarmBoundPush = 1e-6;

// IPOPT with its stopping rule matched to Ceres': constraint violation at
// most Ceres' target_violation, the scaled optimality error at most Ceres'
// relative cost tolerance of an inner solve. From a warm start the barrier
// parameter starts low and the start is pushed little into the bounds
// (IPOPT's usual warm-start settings; its defaults assume a start far from
// the answer).
evade::planning::IpoptOptions ipopt_options(bool warm, bool lbfgs, const std::vector<double>& start_u) {
  const SolverOptions c;
  evade::planning::IpoptOptions o;
  o.tol = c.inner_function_tolerance;
  o.constr_viol_tol = c.target_violation;
  o.limited_memory = lbfgs;
  o.start_u = start_u;
  if (warm) {
    const char* mu = std::getenv("EVADE_BENCH_IPOPT_WARM_MU_INIT");
    o.mu_init = mu ? std::atof(mu) : kWarmMuInit;
    o.bound_push = kWarmBoundPush;
  }
  return o;
}

// IPOPT from the start Ceres has (warm: the same shifted controls; cold:
// zeros), the exact Hessian or L-BFGS.
void BM_Ipopt(benchmark::State& state, bool warm, bool lbfgs) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  const std::vector<double> start = warm ? warm_start(k, CeresMpcSolver{SolverOptions{}}).u : std::vector<double>{};
  const evade::planning::IpoptOptions o = ipopt_options(warm, lbfgs, start);
  const std::string name = std::string("ipopt") + (lbfgs ? " lbfgs" : "") + (warm ? " warm" : " cold");
  run_solves(state, name, k, [&] { return ipopt_row(evade::planning::solve_with_ipopt(pb, o)); });
  // the reference: IPOPT to tol 1e-8 from the same start (not timed)
  if (!lbfgs) {
    evade::planning::IpoptOptions tight = o;
    tight.tol = 1e-8;
    g_rows[std::string("reference") + (warm ? " warm" : " cold")][k] = ipopt_row(solve_with_ipopt(pb, tight));
  }
}

// planner.solver.warm_multipliers: true. Measured no faster overall and
// less predictable (the previous cycle's multipliers may belong to another
// active set), so the planner's default is false.
void BM_CeresWarmMultipliers(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const Problem pb = evade::planning::testing::bench_problem(k);
  CeresMpcSolver solver{SolverOptions{}};
  const Warm w = warm_start(k, solver);
  SolveResult r;
  for (auto _ : state) {
    r = solver.solve(pb, w.u, &w.lambda, w.penalty);
    benchmark::DoNotOptimize(r.cost);
  }
  state.counters["cost"] = r.cost;
  state.counters["viol"] = r.max_violation;
  state.counters["iters"] = r.iterations;
  state.counters["outer"] = r.outer_iterations;
  state.counters["feasible"] = r.feasible;
}

// The planner's loop in miniature: every 0.1 s the robot applies the first
// control of the plan, the obstacles move on, and the next solve starts from
// the previous solution shifted one step (restarts from zero controls when
// a solve fails, as the planner's fallbacks would). One benchmark iteration
// is `kLoopCycles` cycles; counters give the per-cycle mean and worst time
// and the number of infeasible cycles.
constexpr int kLoopCycles = 30;

void BM_CeresClosedLoop(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  SolverOptions opts;
  if (const char* budget = std::getenv("EVADE_BENCH_MAX_TOTAL_ITERATIONS"))
    opts.max_total_iterations = std::atoi(budget);
  CeresMpcSolver solver{opts};
  double worst_ms = 0, total_ms = 0;
  int infeasible = 0, cycles = 0, total_iters = 0;
  int missed = 0;  // cycles Ceres found infeasible but IPOPT solved (a miss, not an infeasible problem)
  for (auto _ : state) {
    Problem pb = evade::planning::testing::bench_problem(k);
    std::vector<double> warm(2 * pb.N, 0.0);
    double x = pb.x0, y = pb.y0, yaw = pb.yaw0, v = pb.v_prev, w = pb.omega_prev;
    for (int c = 0; c < kLoopCycles; ++c) {
      const double t = 0.1 * c;
      pb = evade::planning::testing::bench_problem(k, t);
      // the robot's actual state (the bench problem's reference starts at the robot's x)
      pb.x0 = x;
      pb.y0 = y;
      pb.yaw0 = yaw;
      pb.v_prev = v;
      pb.omega_prev = w;
      const auto t0 = std::chrono::steady_clock::now();
      const SolveResult r = solver.solve(pb, warm);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      worst_ms = std::max(worst_ms, ms);
      total_ms += ms;
      total_iters += r.iterations;
      ++cycles;
      if (!(r.feasible && r.finite)) {
        ++infeasible;
        const IpoptResult ip = evade::planning::solve_with_ipopt(pb);
        if (ip.solved && ip.max_violation <= 1e-3) ++missed;
        warm.assign(2 * pb.N, 0.0);
        v = std::max(0.0, v - pb.lim.decel * pb.dt);
        w = 0;
      } else {
        v = r.u[0];
        w = r.u[1];
        for (int s = 0; s < pb.N; ++s) {
          const int src = std::min(s + 1, pb.N - 1);
          warm[2 * s] = r.u[2 * src];
          warm[2 * s + 1] = r.u[2 * src + 1];
        }
      }
      x += v * std::cos(yaw) * pb.dt;
      y += v * std::sin(yaw) * pb.dt;
      yaw += w * pb.dt;
    }
  }
  state.counters["cycle_mean_ms"] = total_ms / std::max(1, cycles);
  state.counters["cycle_worst_ms"] = worst_ms;
  state.counters["cycle_iters"] = static_cast<double>(total_iters) / std::max(1, cycles);
  state.counters["ipopt_solved_those"] = static_cast<double>(missed) / std::max(1.0, cycles / double(kLoopCycles));
  state.counters["infeasible_cycles"] = static_cast<double>(infeasible) / std::max(1.0, cycles / double(kLoopCycles));
}

// A planter-sized obstacle on a straight route and k - 1 smaller ones
// scattered beside it within 6 m (fixed positions), as the planner sees them each
// cycle; the previous way round is kept between iterations, as in the
// planner.
void BM_Detour(benchmark::State& state) {
  using namespace evade::planning;
  const int k = static_cast<int>(state.range(0));
  const PlannerParams p =
      PlannerParams::from_config(evade::config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
  DetourPlanner detour(p.detour, p.d_safe_m);
  RouteFollower route;
  route.set_route({0.0, 20.0}, {0.0, 0.0});
  route.update_progress(0.0, 0.0, p.route_search_window_m);
  std::vector<Ellipse> obs = {{4.0, 0.1, 1.0, 1.0, 0.0}};
  for (int i = 1; i < k; ++i) {
    const double ang = 2.399963 * i;  // golden angle: spread without overlap
    const double r = 2.0 + 4.0 * i / k;
    double y = r * std::sin(ang);
    if (std::fabs(y) < 1.6) y = std::copysign(1.6 + std::fabs(y), y);  // beside the route, not on it
    obs.push_back({4.0 + r * std::cos(ang), y, 0.35, 0.25, ang});
  }
  std::vector<double> x, y;
  int detours = 0, no_way = 0, cycles = 0;
  long expanded = 0;
  for (auto _ : state) {
    const DetourPlanner::Result r = detour.plan(route, 0.0, 0.0, obs, &x, &y);
    detours += r == DetourPlanner::Result::kDetour ? 1 : 0;
    no_way += r == DetourPlanner::Result::kNoWay ? 1 : 0;
    expanded += detour.last_expanded();
    ++cycles;
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["detour_found"] = static_cast<double>(detours) / std::max(1, cycles);
  state.counters["no_way"] = static_cast<double>(no_way) / std::max(1, cycles);
  state.counters["cells_expanded"] = static_cast<double>(expanded) / std::max(1, cycles);
}

evade::planning::PlannerParams config_params() {
  return evade::planning::PlannerParams::from_config(
      evade::config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
}

void BM_Guidance(benchmark::State& state) {
  using namespace evade::planning;
  const int k = static_cast<int>(state.range(0));
  const PlannerParams p = config_params();
  const Problem pb = evade::planning::testing::bench_problem(k);
  size_t classes = 0;
  for (auto _ : state) {
    const std::vector<GuidancePath> ways = find_guidance(pb, p.guidance);
    classes = ways.size();
    benchmark::DoNotOptimize(ways.data());
  }
  state.counters["classes"] = static_cast<double>(classes);
}

void BM_GuidanceCycle(benchmark::State& state) {
  using namespace evade::planning;
  const int k = static_cast<int>(state.range(0));
  const PlannerParams p = config_params();
  const Problem pb = evade::planning::testing::bench_problem(k);
  const Warm w = warm_start(k, CeresMpcSolver(p.solver));
  TopologyPlanner planner(
      p.guidance, p.solver,
      local_solves_budget(p.guidance, p.solver.max_total_iterations, p.solver.max_cycle_iterations));
  TopologyOutcome o;
  for (auto _ : state) {
    planner.reset();
    o = planner.plan(pb, {w.u}, std::vector<double>(2 * pb.N, 0.0));
    benchmark::DoNotOptimize(o.u.data());
  }
  state.counters["solves"] = o.solves;
  state.counters["iterations"] = o.iterations;
  state.counters["critical_iterations"] = o.critical_iterations;
  state.counters["feasible"] = o.feasible ? 1 : 0;
}

// What most_clearance does per candidate when the hard solve has failed: the
// same 17 candidates as planner_recovery.cpp's chain (the ones made from the
// fixed problem here; the failed solve's and the last plan shifted are both
// stood in for by the warm start, braking by zero controls projected on the
// rate limits).
void BM_Outcome(benchmark::State& state) {
  using namespace evade::planning;
  const int k = static_cast<int>(state.range(0));
  const Problem pb = testing::bench_problem(k);
  const std::vector<double> warm = warm_start(k, CeresMpcSolver{SolverOptions{}}).u;
  std::vector<std::vector<double>> candidates{warm, warm, std::vector<double>(2 * pb.N, 0.0)};
  for (double side : {1.0, -1.0}) {
    candidates.push_back(dash_controls(pb, side));
    candidates.push_back(swerve_controls(pb, side));
    for (double offset : {0.2, 0.35, 0.45, 0.55, 0.65}) candidates.push_back(pull_over_controls(pb, side, offset, 1.0));
  }
  std::vector<double> states(3 * (pb.N + 1));
  int clear = 0;
  for (auto _ : state) {
    clear = 0;
    for (std::vector<double> u : candidates) {
      project_controls(pb, &u);
      rollout(pb, u.data(), states.data());
      benchmark::DoNotOptimize(min_barrier(pb, states, 1));
      clear += plan_outcome(pb, states, 1e-3, pb.N).kind == Outcome::kClear;
    }
  }
  state.counters["candidates"] = static_cast<double>(candidates.size());
  state.counters["clear"] = clear;
}

// passive_turn_bounds (turn_bound, on for the Scout) at k walkers 0.85 m
// and out from the standing Scout 2.0, at 1.3 m/s: walking at it (every
// way meets the standing robot, both turns bind, and the exemption
// searches its angles for every walker: the worst case) or going round
// it (the bounds alone).
void BM_TurnBound(benchmark::State& state, bool at_it) {
  using namespace evade::planning;
  const int k = static_cast<int>(state.range(0));
  Problem pb = testing::straight_problem(0, 0, 0.0, 0.0, 0.5);
  pb.footprint = Footprint::covering(0.93, 0.70, 3);
  pb.lim.omega_max = 0.5;
  for (int i = 0; i < k; ++i) {
    const double a = 2 * M_PI * i / k, r = 0.85 + 0.03 * i, c = std::cos(a), s = std::sin(a);
    const double vx = at_it ? -1.3 * c : -1.3 * s, vy = at_it ? -1.3 * s : 1.3 * c;
    ObstacleTrack w = testing::moving_obstacle(i, r * c, r * s, vx, vy, 0.3, 0.3, 0.0, 0.9, pb.N, pb.dt);
    w.age_s = 3.0;
    pb.obstacles.push_back(w);
  }
  PassiveSafetyParams p;
  p.turn_bound = true;
  TurnBounds t{};
  for (auto _ : state) benchmark::DoNotOptimize(t = passive_turn_bounds(p, pb));
  state.counters["bound"] = (t.lo > -pb.lim.omega_max || t.hi < pb.lim.omega_max) ? 1 : 0;
}

void BM_StaticField(benchmark::State& state) {
  using namespace evade::planning;
  const int k = static_cast<int>(state.range(0));
  const StaticFieldParams sp;
  evade::grid_map_t m{};
  m.resolution = 0.1;
  m.width = m.height = 160;
  m.origin[0] = m.origin[1] = -8.0;
  m.elevation.assign(160, std::vector<float>(160, 0.0f));
  m.obstacle.assign(160, std::vector<int8_t>(160, 0));
  for (int r = 0; r < 160; ++r)
    if (r < 76 || r > 84) m.obstacle[r][110] = m.obstacle[r][111] = 1;  // a wall at x = 3 m, a 0.9 m door
  std::vector<Ellipse> movers;
  for (int i = 0; i < k; ++i) {
    const double ang = 2.399963 * i, r = 1.0 + 5.0 * i / std::max(k, 1);
    movers.push_back({r * std::cos(ang), r * std::sin(ang), 0.3, 0.3, 0.0});
    const int c = static_cast<int>((movers.back().x + 8.0) / 0.1),
              row = static_cast<int>((movers.back().y + 8.0) / 0.1);
    for (int dr = -2; dr <= 2; ++dr)
      for (int dc = -2; dc <= 2; ++dc) m.obstacle[row + dr][c + dc] = 1;
  }
  for (auto _ : state) benchmark::DoNotOptimize(StaticField::build(m, movers, {}, sp));
}

// The planner's static-structure inputs of one cycle, from a log.
struct FieldCycle {
  evade::grid_map_t map;
  evade::prediction_list_t predictions;
  evade::obstacle_list_t observed;
  evade::odometry_t odometry;
};

// Each ELEVATION_MAP of the log with the last predictions, obstacles and
// odometry before it (none in the log: no tracks, and the robot at the
// map's centre, where the elevation map puts it).
std::vector<FieldCycle> field_cycles(const std::string& path) {
  std::vector<FieldCycle> out;
  FieldCycle cur;
  bool have_odom = false;
  evade::bus::for_each_event(path, [&](const evade::bus::LogEvent& e) {
    const auto decode = [&](auto* out) { return evade::bus::decode(e.data.data(), e.data.size(), out); };
    if (e.channel == "OBSTACLE_PREDICTIONS") decode(&cur.predictions);
    if (e.channel == "OBSTACLES") decode(&cur.observed);
    if (e.channel == "ODOMETRY") have_odom = decode(&cur.odometry) || have_odom;
    if (e.channel != "ELEVATION_MAP" || !decode(&cur.map)) return;
    if (!have_odom) {
      cur.odometry.x = cur.map.origin[0] + 0.5 * cur.map.width * cur.map.resolution;
      cur.odometry.y = cur.map.origin[1] + 0.5 * cur.map.height * cur.map.resolution;
    }
    out.push_back(cur);
  });
  return out;
}

void BM_StaticFieldLog(benchmark::State& state) {
  using namespace evade::planning;
  const char* env = std::getenv("EVADE_BENCH_FIELD_LOG");
  const std::string path = env ? env : EVADE_SOURCE_DIR "/logs/street_pedestrians/refs/elevation_map.lcmlog";
  const std::vector<FieldCycle> cycles = field_cycles(path);
  if (cycles.empty()) {
    state.SkipWithError(("no ELEVATION_MAP in " + path).c_str());
    return;
  }
  const PlannerParams pp = PlannerParams::from_config(evade::config::load_file(EVADE_SOURCE_DIR "/config/robot.yaml"));
  const double reach = state.range(0) ? static_field_reach_m(pp) : std::numeric_limits<double>::infinity();
  size_t i = 0, cells = 0;
  for (auto _ : state) {
    const FieldCycle& c = cycles[i++ % cycles.size()];
    StaticStructure s(pp.static_field);
    s.keep_map(c.map);
    StaticStructure::Inputs in;
    in.odometry_utime = c.map.utime;
    if (state.range(0)) in.window = FieldWindow::around(c.odometry.x, c.odometry.y, reach);
    if (state.range(0) == 2) {
      const double ahead = pp.detour.lookahead_m + pp.detour.cell_m;
      in.window.include(c.odometry.x + ahead * std::cos(c.odometry.yaw),
                        c.odometry.y + ahead * std::sin(c.odometry.yaw));
    }
    in.predictions = &c.predictions;
    in.observed = &c.observed;
    in.track_age_s = [](int64_t) { return 10.0; };
    benchmark::DoNotOptimize(s.update(in));
    cells += static_cast<size_t>(s.field() ? s.field()->static_cells() : 0);
  }
  state.counters["maps"] = static_cast<double>(cycles.size());
  state.counters["static_cells"] = static_cast<double>(cells) / static_cast<double>(std::max<size_t>(1, i));
  state.counters["map_cells"] = static_cast<double>(cycles[0].map.width) * cycles[0].map.height;
}

BENCHMARK(BM_Guidance)->Name("guidance")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GuidanceCycle)->Name("cycle/guidance")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Outcome)->Name("outcome")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StaticField)->Name("static_field")->Arg(0)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StaticFieldLog)->Name("static_field_log")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TurnBound, at_it, true)
    ->Name("turn_bound/at_it")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TurnBound, round_it, false)
    ->Name("turn_bound/round_it")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Detour)->Name("detour")->Arg(1)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ceres)->Name("solve/ceres")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CeresWarmMultipliers)
    ->Name("solve/ceres_warm_multipliers")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CeresClosedLoop)->Name("loop/ceres")->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CeresCold)->Name("solve/ceres_cold")->Arg(0)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ipopt, cold, false, false)
    ->Name("solve/ipopt")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ipopt, cold_lbfgs, false, true)
    ->Name("solve/ipopt_lbfgs")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ipopt, warm, true, false)
    ->Name("solve/ipopt_warm")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ipopt, warm_lbfgs, true, true)
    ->Name("solve/ipopt_warm_lbfgs")
    ->Arg(0)
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Unit(benchmark::kMillisecond);

}  // namespace

// The comparison from one start: Ceres against the faster IPOPT variant,
// CPU ms per solve, and each cost against the reference (IPOPT to 1e-8).
void print_comparison(const std::string& start) {
  const auto& ceres = g_rows["ceres " + start];
  if (ceres.empty()) return;
  std::printf("\nfrom the %s start: CPU ms per solve (iterations; -1: not run), cost vs IPOPT to tol 1e-8\n",
              start.c_str());
  std::printf("%-3s %16s %16s %16s %7s %10s %10s\n", "k", "ceres", "ipopt", "ipopt_lbfgs", "ratio", "ceres_%",
              "ipopt_%");
  for (const auto& [k, c] : ceres) {
    auto find = [&](const std::string& name) {
      const auto it = g_rows.find(name);
      return it == g_rows.end() || !it->second.count(k) ? Row{-1, -1, -1, -1, 0, false} : it->second.at(k);
    };
    const Row ex = find("ipopt " + start), lb = find("ipopt lbfgs " + start), ref = find("reference " + start);
    const Row& fast = lb.cpu_ms > 0 && (ex.cpu_ms <= 0 || lb.cpu_ms < ex.cpu_ms) ? lb : ex;
    if (fast.cpu_ms <= 0) continue;  // no IPOPT run from this start
    auto pct = [&](const Row& r) { return ref.cost > 0 ? 100.0 * (r.cost - ref.cost) / ref.cost : 0.0; };
    std::printf("%-3d %9.3f (%4.0f) %9.3f (%4.0f) %9.3f (%4.0f) %6.1fx %+10.3f %+10.3f\n", k, c.cpu_ms, c.iters,
                ex.cpu_ms, ex.iters, lb.cpu_ms, lb.iters, fast.cpu_ms / std::max(1e-9, c.cpu_ms), pct(c), pct(fast));
  }
}

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  for (const char* start : {"cold", "warm"}) print_comparison(start);
  return 0;
}
