// Planner parameters: the `planner:` section of config/robot.yaml plus the
// shared limits of the `robot:` section.
#pragma once

#include <string>

#include "config/config.h"
#include "planning/ceres_solver.h"
#include "planning/detour.h"
#include "planning/guidance.h"
#include "planning/modes.h"
#include "planning/problem.h"

namespace evade::planning {

// What the paper's modes do when the solve ends outside the constraints.
enum class PaperFallback {
  kBrake,     // brake at the deceleration limits (STATUS_STOPPING)
  kLastPlan,  // the last solved plan shifted, its tail braking (STATUS_FALLBACK), else brake; what
              // the paper's released code does (it replays its last solution)
};

struct PlannerParams {
  Mode mode = Mode::kEvade;  // modes.h
  PaperFallback paper_fallback = PaperFallback::kBrake;
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
  double goal_tolerance_m = 0.3;
  double route_search_window_m = 3.0;
  double blocked_after_s = 5.0;         // PLAN.status BLOCKED after this long without blocked_progress_m ...
  double blocked_progress_m = 0.2;      // ... of progress along the route
  double obstacle_consider_radius_m = 4.0;
  int max_obstacles = 16;
  double odometry_max_age_s = 0.3;
  double predictions_max_age_s = 0.5;  // modes reading OBSTACLE_PREDICTIONS
  double obstacles_max_age_s = 0.5;    // modes reading OBSTACLES
  bool require_obstacles = true;       // no message yet from the mode's obstacle input counts as stale
  bool warm_multipliers = false;
  int curvefit_degree = 2;
  double curvefit_window_s = 1.0;
  Weights weights;
  Limits limits;
  SolverOptions solver;
  // Ceres iterations of one planning cycle, all its solves together (the
  // hard solve, the swerve restarts, the relaxed solve): a cycle in which
  // the hard problem fails otherwise runs up to four solves' budgets
  // (solver.max_total_iterations each). The restarts leave the relaxed
  // solve its budget when it applies. Counted in iterations, not time, so
  // that a replay plans exactly as the live run did.
  int max_cycle_iterations = 900;
  DetourParams detour;
  // Mode evade: guidance classes solved side by side and the choice among
  // them (guidance.h, topology_planner.h); off: one solve from the warm
  // start and evade's recovery chain.
  GuidanceParams guidance;
  // Inside d_safe of an obstacle that stands ahead and to one side, the
  // relaxed problem keeps h from falling (at its edge the D-CBF lets it fall
  // by only gamma h per step), and a robot that must turn on the spot for
  // longer than the horizon before any motion raises h finds no plan better
  // than standing, every cycle. Then it turns on the spot (h
  // unchanged) towards the heading nearest the route's that moves away.
  bool escape_enabled = true;
  double escape_min_progress_m = 0.1;         // a relaxed plan ending nearer its start than this makes no headway
  double escape_near_m = 0.1;                 // ...while some obstacle's h at the start is below this (m beyond d_safe)
  double escape_cone_half_angle_rad = 0.785;  // the escape heading is at most this far from the way out (grad h)

  // The decay of this mode's constraints: 1 - gamma (its GammaKey) for a
  // CBF, 0 for a distance constraint.
  double constraint_decay() const;

  // root = the whole configuration (reads `planner:` and the limits in `robot:`).
  static PlannerParams from_config(const config::Node& root);
};

}  // namespace evade::planning
