// Planner parameters: the `planner:` section of config/robot.yaml plus the
// shared limits of the `robot:` section. Each struct's field list (fields())
// names its keys once, members named as the keys and nested as the YAML
// nests them; the sub-sections are the structs of the modules that take
// them (Weights, problem.h; DetourParams, detour.h; GuidanceParams,
// guidance.h; SolverOptions, ceres_solver.h; ...). The defaults are
// robot.yaml's (test_config_sections checks it).
#pragma once

#include <cmath>
#include <string>

#include "config/config.h"
#include "config/fields.h"
#include "planning/ceres_solver.h"
#include "planning/detour.h"
#include "planning/goal_approach.h"
#include "planning/guidance.h"
#include "planning/modes.h"
#include "planning/occlusion_speed.h"
#include "planning/passive_safety.h"
#include "planning/problem.h"
#include "planning/static_field.h"

namespace evade::planning {

// What the paper's modes do when the solve ends outside the constraints.
enum class PaperFallback {
  kBrake,     // brake at the deceleration limits (STATUS_STOPPING)
  kLastPlan,  // the last solved plan shifted, its tail braking (STATUS_FALLBACK), else brake; what
              // the paper's released code does (it replays its last solution)
};

// `planner.curvefit`: mode cbf_curvefit's fit of each track's observed
// centres (CurveFitHistory, obstacles.h).
struct CurvefitParams {
  int degree = 2;         // of the polynomial fit of each centre coordinate over time
  double window_s = 1.0;  // observed centres of this long the fit uses
  template <class V>
  void fields(V& v) {
    v.field("degree", degree, config::between(0, 5));
    v.field("window_s", window_s, config::positive());
  }
};

// `planner.escape` (mode evade). Inside d_safe of an obstacle that stands
// ahead and to one side, the relaxed problem keeps h from falling (at its
// edge the D-CBF lets it fall by only gamma h per step), and a robot that
// must turn on the spot for longer than the horizon before any motion
// raises h finds no plan better than standing, every cycle. Then it turns
// on the spot (h unchanged) towards the heading nearest the route's that
// moves away.
struct EscapeParams {
  bool enabled = true;
  double min_progress_m = 0.1;            // a relaxed plan ending nearer its start than this makes no headway
  double near_m = 0.1;                    // ...while some obstacle's h at the start is below this (m beyond d_safe)
  double cone_half_angle_rad = M_PI / 4;  // the escape heading is at most this far from the way out (grad h);
                                          // config: degrees
  template <class V>
  void fields(V& v) {
    v.field("enabled", enabled);
    v.field("min_progress_m", min_progress_m, config::between(0.0, 10.0));
    v.field("near_m", near_m, config::between(-10.0, 10.0));
    v.convert("cone_half_angle_deg", cone_half_angle_rad, config::degrees_as_radians(config::between(0.0, 89.0)));
  }
};

// `planner.solver`: the solver's options (SolverOptions, the base: what
// CeresMpcSolver takes) and the planner's own per-cycle budget and
// warm-start choice.
struct PlannerSolverParams : SolverOptions {
  // Ceres iterations of one planning cycle, all its solves together (the
  // hard solve, the swerve restarts, the relaxed solve): a cycle in which
  // the hard problem fails otherwise runs up to four solves' budgets
  // (max_total_iterations each); the restarts leave the relaxed solve its
  // budget when it applies. With split_budget, split before solving: a
  // recovery solve that would follow a failed hard solve keeps its share
  // from the hard solve and the restarts (PlannerCore::recovery_reserve). Counted in
  // iterations, not time, so that a replay plans exactly as the live run did.
  int max_cycle_iterations = 900;
  bool warm_multipliers = false;  // the last cycle's multipliers start the solve (else estimate_multipliers)
  bool swerves = true;            // chain: swerve restarts and swerve candidates (off: neither)
  bool dashes = true;             // chain: the dash candidates (off: none)
  template <class V>
  void fields(V& v) {
    v.field("max_cycle_iterations", max_cycle_iterations, config::between(1, 1000000));
    v.field("warm_multipliers", warm_multipliers);
    v.field("swerves", swerves);
    v.field("dashes", dashes);
    SolverOptions::fields(v);
  }
};

struct PlannerParams {
  Mode mode = Mode::kEvade;  // modes.h
  PaperFallback paper_fallback = PaperFallback::kLastPlan;
  double rate_hz = 8;  // least rate: cycles run on each new obstacle list, on ODOMETRY after 1/rate_hz without
  int horizon_steps = 25;
  double dt_s = 0.1;
  double gamma = 0.15;       // the paper's D-CBF decay (its Section IV), modes with GammaKey::kPaper
  double evade_gamma = 0.1;  // evade's own (GammaKey::kEvade)
  double d_safe_m = 0.15;    // margin beyond the footprint's covering discs
  int footprint_discs = 3;   // discs covering robot.footprint_length_m x footprint_width_m
  Footprint footprint;       // made from those (problem.h); the default: a point
  double reference_speed_mps = 0.8;
  double route_end_decel_mps2 = 0.5;
  double goal_tolerance_m = 0.2;
  double route_search_window_m = 3.0;
  double blocked_after_s = 5.0;     // PLAN.status BLOCKED after this long without blocked_progress_m ...
  double blocked_progress_m = 0.2;  // ... of progress along the route
  double obstacle_consider_radius_m = 4.0;
  int max_obstacles = 16;
  double odometry_max_age_s = 0.3;
  double predictions_max_age_s = 0.25;  // modes reading OBSTACLE_PREDICTIONS
  double obstacles_max_age_s = 0.25;    // modes reading OBSTACLES
  bool require_obstacles = true;        // no message yet from the mode's obstacle input counts as stale
  // Mode evade: a plan whose second step brakes at the deceleration limit
  // sends that step's speed, not its first (commanded_speed,
  // planner_core.cpp).
  bool brake_ahead = true;
  CurvefitParams curvefit;
  Weights weights;
  Limits limits;  // robot: (config/robot_params.h), not in the field list
  PlannerSolverParams solver;
  DetourParams detour;
  // Mode evade: static structure by the elevation map's cells (static_field.h).
  StaticFieldParams static_field;
  // Mode evade: guidance classes solved side by side and the choice among
  // them (guidance.h, topology_planner.h); off: one solve from the warm
  // start and evade's recovery chain.
  GuidanceParams guidance;
  // Mode evade: the speed bound near hidden regions (occlusion_speed.h).
  OcclusionSpeedParams occlusion;
  // Mode evade: the speed bound near the route's end (goal_approach.h).
  GoalApproachParams goal_approach;
  // Mode evade, no plan certified: the recovery's speed bound (passive_safety.h).
  PassiveSafetyParams passive_safety;
  EscapeParams escape;  // mode evade: the turn on the spot out of d_safe

  // The decay of this mode's constraints: 1 - gamma (its GammaKey) for a
  // CBF, 0 for a distance constraint.
  double constraint_decay() const;

  // The `planner:` section (limits and footprint come from `robot:`, read
  // first by from_config: reference_speed_mps is bounded by the speed limit).
  template <class V>
  void fields(V& v);

  // root = the whole configuration (reads `planner:` and the limits in `robot:`).
  static PlannerParams from_config(const config::Node& root);

  static config::Choices<Mode> mode_choices();  // modes.h's names
};

template <class V>
void PlannerParams::fields(V& v) {
  v.choice("mode", mode, mode_choices());
  v.choice("paper_fallback", paper_fallback,
           config::Choices<PaperFallback>{{"last_plan", PaperFallback::kLastPlan}, {"brake", PaperFallback::kBrake}});
  v.field("rate_hz", rate_hz, config::positive());
  v.field("horizon_steps", horizon_steps, config::between(2, 64));
  v.field("dt_s", dt_s, config::positive());
  v.field("gamma", gamma, config::between(1e-6, 1.0));  // 0 < gamma <= 1 (paper, discrete D-CBF)
  v.field("evade_gamma", evade_gamma, config::between(1e-6, 1.0));
  v.field("d_safe_m", d_safe_m, config::between(0.0, 10.0));
  v.field("footprint_discs", footprint_discs, config::between(1, 16));
  v.field("reference_speed_mps", reference_speed_mps, config::between(0.0, limits.v_max));
  v.field("route_end_decel_mps2", route_end_decel_mps2, config::positive());
  v.field("goal_tolerance_m", goal_tolerance_m, config::positive());
  v.field("route_search_window_m", route_search_window_m, config::positive());
  v.field("blocked_after_s", blocked_after_s, config::positive());
  v.field("blocked_progress_m", blocked_progress_m, config::positive());
  v.field("obstacle_consider_radius_m", obstacle_consider_radius_m, config::positive());
  v.field("max_obstacles", max_obstacles, config::between(0, 256));
  v.field("odometry_max_age_s", odometry_max_age_s, config::positive());
  v.field("predictions_max_age_s", predictions_max_age_s, config::positive());
  v.field("obstacles_max_age_s", obstacles_max_age_s, config::positive());
  v.field("require_obstacles", require_obstacles);
  v.field("brake_ahead", brake_ahead);
  v.section("weights", weights);
  v.section("curvefit", curvefit);
  v.section("escape", escape);
  v.section("detour", detour);
  v.section("static_field", static_field);
  v.section("guidance", guidance);
  v.section("occlusion", occlusion);
  v.section("goal_approach", goal_approach);
  v.section("passive_safety", passive_safety);
  v.section("solver", solver);
}

}  // namespace evade::planning
