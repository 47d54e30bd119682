// Planner parameters: the `planner:` section of config/robot.yaml plus the
// shared limits of the `robot:` section. The field list (fields()) names
// every key of `planner:` once; its sub-sections go into the structs the
// solver, the detour grid and the guidance take (ceres_solver.h, detour.h,
// guidance.h), whose member names are theirs (the list maps each key). The
// defaults are robot.yaml's (test_config_sections checks it).
#pragma once

#include <string>

#include "config/config.h"
#include "config/fields.h"
#include "planning/ceres_solver.h"
#include "planning/detour.h"
#include "planning/guidance.h"
#include "planning/modes.h"
#include "planning/occlusion_speed.h"
#include "planning/problem.h"
#include "planning/static_field.h"

namespace evade::planning {

// What the paper's modes do when the solve ends outside the constraints.
enum class PaperFallback {
  kBrake,     // brake at the deceleration limits (STATUS_STOPPING)
  kLastPlan,  // the last solved plan shifted, its tail braking (STATUS_FALLBACK), else brake; what
              // the paper's released code does (it replays its last solution)
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
  double goal_tolerance_m = 0.3;
  double route_search_window_m = 3.0;
  double blocked_after_s = 5.0;     // PLAN.status BLOCKED after this long without blocked_progress_m ...
  double blocked_progress_m = 0.2;  // ... of progress along the route
  double obstacle_consider_radius_m = 4.0;
  int max_obstacles = 16;
  double odometry_max_age_s = 0.3;
  double predictions_max_age_s = 0.25;  // modes reading OBSTACLE_PREDICTIONS
  double obstacles_max_age_s = 0.25;    // modes reading OBSTACLES
  bool require_obstacles = true;        // no message yet from the mode's obstacle input counts as stale
  bool warm_multipliers = false;
  int curvefit_degree = 2;
  double curvefit_window_s = 1.0;
  Weights weights = default_weights();
  Limits limits;  // robot: (config/robot_params.h), not in the field list
  SolverOptions solver;
  // Ceres iterations of one planning cycle, all its solves together (the
  // hard solve, the swerve restarts, the relaxed solve): a cycle in which
  // the hard problem fails otherwise runs up to four solves' budgets
  // (solver.max_total_iterations each). The restarts leave the relaxed
  // solve its budget when it applies. Counted in iterations, not time, so
  // that a replay plans exactly as the live run did.
  int max_cycle_iterations = 900;
  DetourParams detour = default_detour();
  // Mode evade: static structure by the elevation map's cells (static_field.h).
  StaticFieldParams static_field;
  // Mode evade: guidance classes solved side by side and the choice among
  // them (guidance.h, topology_planner.h); off: one solve from the warm
  // start and evade's recovery chain.
  GuidanceParams guidance = default_guidance();
  // Mode evade: the speed bound near hidden regions (occlusion_speed.h).
  OcclusionSpeedParams occlusion;
  // Inside d_safe of an obstacle that stands ahead and to one side, the
  // relaxed problem keeps h from falling (at its edge the D-CBF lets it fall
  // by only gamma h per step), and a robot that must turn on the spot for
  // longer than the horizon before any motion raises h finds no plan better
  // than standing, every cycle. Then it turns on the spot (h
  // unchanged) towards the heading nearest the route's that moves away.
  bool escape_enabled = true;
  double escape_min_progress_m = 0.1;  // a relaxed plan ending nearer its start than this makes no headway
  double escape_near_m = 0.1;          // ...while some obstacle's h at the start is below this (m beyond d_safe)
  double escape_cone_half_angle_rad = M_PI / 4;  // the escape heading is at most this far from the way out (grad h)

  // The decay of this mode's constraints: 1 - gamma (its GammaKey) for a
  // CBF, 0 for a distance constraint.
  double constraint_decay() const;

  // The `planner:` section (limits and footprint come from `robot:`, read
  // first by from_config: reference_speed_mps is bounded by the speed limit).
  template <class V>
  void fields(V& v);

  // root = the whole configuration (reads `planner:` and the limits in `robot:`).
  static PlannerParams from_config(const config::Node& root);

  // robot.yaml's values of the sub-sections whose structs are the
  // planner's modules' own (their defaults are a bare module's).
  static Weights default_weights();
  static config::Choices<Mode> mode_choices();  // modes.h's names
  static DetourParams default_detour();
  static GuidanceParams default_guidance();
};

// The sub-sections of `planner:` whose keys are members of PlannerParams
// itself or of several structs: views that list them.
struct CurvefitKeys {
  PlannerParams& p;
  template <class V>
  void fields(V& v) {
    v.field("degree", p.curvefit_degree, config::between(0, 5));
    v.field("window_s", p.curvefit_window_s, config::positive());
  }
};

struct EscapeKeys {
  PlannerParams& p;
  template <class V>
  void fields(V& v) {
    v.field("enabled", p.escape_enabled);
    v.field("min_progress_m", p.escape_min_progress_m, config::between(0.0, 10.0));
    v.field("near_m", p.escape_near_m, config::between(-10.0, 10.0));
    v.convert("cone_half_angle_deg", p.escape_cone_half_angle_rad,
              config::degrees_as_radians(config::between(0.0, 89.0)));
  }
};

struct WeightKeys {
  Weights& w;
  template <class V>
  void fields(V& v) {
    const config::Range r = config::between(0, 1e6);
    v.field("q_xy", w.q_xy, r);
    v.field("q_yaw", w.q_yaw, r);
    v.field("p_xy", w.p_xy, r);
    v.field("p_yaw", w.p_yaw, r);
    v.field("r_v", w.r_v, r);
    v.field("r_omega", w.r_omega, r);
    v.field("s_v", w.s_v, r);
    v.field("s_omega", w.s_omega, r);
  }
};

struct DetourKeys {
  DetourParams& d;
  template <class V>
  void fields(V& v) {
    v.field("enabled", d.enabled);
    v.field("lookahead_m", d.lookahead_m, config::between(0.0, 100.0));
    v.field("cell_m", d.cell_m, config::between(0.01, 1.0));
    v.field("margin_m", d.margin_m, config::between(0.0, 10.0));
    v.field("comfort_m", d.comfort_m, config::between(d.margin_m + 1e-3, 20.0));
    v.field("proximity_cost", d.proximity_cost, config::between(0.0, 1e3));
    v.field("deviation_cost", d.deviation_cost, config::between(0.0, 1e3));
    v.field("rejoin_m", d.rejoin_m, config::between(0.0, 100.0));
    v.field("pad_m", d.pad_m, config::between(0.0, 100.0));
    v.field("max_obstacle_speed_mps", d.max_obstacle_speed_mps, config::between(0.0, 100.0));
    v.field("min_track_age_s", d.min_track_age_s, config::between(0.0, 3600.0));
    v.field("blocked_cost", d.blocked_cost, config::between(1.0, 1e6));
    v.field("keep_side_discount", d.keep_side_discount, config::between(0.01, 1.0));
    v.field("smoothing_m", d.smoothing_m, config::between(0.0, 10.0));
    v.field("max_cells", d.max_cells, config::between(1, 10000000));
    v.field("min_offset_m", d.min_offset_m, config::between(0.0, 100.0));
    v.field("leader_max_speed_mps", d.leader_max_speed_mps, config::between(0.0, 100.0));
    v.convert("leader_max_angle_deg", d.leader_max_angle_rad, config::degrees_as_radians(config::between(0.0, 90.0)));
    v.field("leader_sweep_s", d.leader_sweep_s, config::between(0.0, 60.0));
    v.convert("oncoming_max_angle_deg", d.oncoming_max_angle_rad,
              config::degrees_as_radians(config::between(0.0, 90.0)));
    v.field("oncoming_sweep_s", d.oncoming_sweep_s, config::between(0.0, 60.0));
    v.field("oncoming_max_sigma_m", d.oncoming_max_sigma_m, config::between(0.0, 100.0));
    v.field("min_mover_age_s", d.min_mover_age_s, config::between(0.0, 3600.0));
    v.field("memory_s", d.memory_s, config::between(0.0, 3600.0));
  }
};

struct GuidanceKeys {
  GuidanceParams& g;
  template <class V>
  void fields(V& v) {
    v.field("enabled", g.enabled);
    v.field("max_classes", g.max_classes, config::between(0, 16));
    v.field("threads", g.threads, config::between(1, 64));
    v.field("layer_steps", g.layer_steps, config::between(1, 64));
    v.field("lateral_step_m", g.lateral_step_m, config::between(0.05, 2.0));
    v.field("lateral_max_m", g.lateral_max_m, config::between(0.0, 10.0));
    v.field("longitudinal_step_m", g.longitudinal_step_m, config::between(0.05, 2.0));
    v.field("switch_cost_factor", g.switch_cost_factor, config::between(1.0, 100.0));
    v.choice("fallback", g.fallback,
             config::Choices<GuidanceParams::Fallback>{{"least_violating", GuidanceParams::Fallback::kLeastViolating},
                                                       {"recovery", GuidanceParams::Fallback::kRecovery}});
  }
};

// `planner.solver`: the solver's options plus the planner's own per-cycle
// budget and warm-start choice.
struct SolverKeys {
  PlannerParams& p;
  template <class V>
  void fields(V& v);
};

}  // namespace evade::planning

namespace evade::planning {

template <class V>
void SolverKeys::fields(V& v) {
  SolverOptions& o = p.solver;
  v.field("max_outer_iterations", o.max_outer_iterations, config::between(1, 1000));
  v.field("max_inner_iterations", o.max_inner_iterations, config::between(1, 1000));
  v.field("max_total_iterations", o.max_total_iterations, config::between(1, 100000));
  v.field("max_cycle_iterations", p.max_cycle_iterations, config::between(1, 1000000));
  v.field("constraint_tolerance", o.constraint_tolerance, config::positive());
  v.field("target_violation", o.target_violation, config::between(0.0, o.constraint_tolerance));
  v.field("complementarity_tolerance_m", o.complementarity_tolerance, config::between(0.0, 10.0));
  v.field("min_trust_radius", o.min_trust_radius, config::positive());
  v.field("penalty_initial", o.penalty_initial, config::positive());
  v.field("warm_penalty_max", o.warm_penalty_max, config::between(o.penalty_initial, 1e12));
  v.field("penalty_growth", o.penalty_growth, config::between(1.0, 1e3));
  v.field("penalty_max", o.penalty_max, config::positive());
  v.field("violation_shrink", o.violation_shrink, config::between(0.0, 1.0));
  v.field("active_margin_m", o.active_margin, config::between(0.0, 100.0));
  v.field("inner_function_tolerance", o.inner_function_tolerance, config::positive());
  v.field("inner_parameter_tolerance", o.inner_parameter_tolerance, config::positive());
  v.choice("linear_solver", o.dense_qr, config::Choices<bool>{{"dense_normal_cholesky", false}, {"dense_qr", true}});
  v.choice("line_search_interpolation", o.line_search,
           config::Choices<LineSearchInterpolation>{{"bisection", LineSearchInterpolation::kBisection},
                                                    {"quadratic", LineSearchInterpolation::kQuadratic},
                                                    {"cubic", LineSearchInterpolation::kCubic}});
  v.field("projection_iterations", o.projection_iterations, config::between(0, 1000));
  v.field("projection_target_m", o.projection_target, config::between(0.0, o.target_violation));
  v.field("projection_damping", o.projection_damping, config::between(0.0, 1.0));
  v.field("projection_candidates", o.projection_candidates, config::between(0, 1000));
  v.field("projection_candidate_violation_m", o.projection_candidate_violation, config::between(0.0, 10.0));
  v.field("warm_multipliers", p.warm_multipliers);
  v.field("estimate_multipliers", o.estimate_multipliers);
  v.field("relax_max_obstacle_speed_mps", o.relax_max_obstacle_speed, config::between(0.0, 100.0));
  v.field("relax_min_track_age_s", o.relax_min_obstacle_age, config::between(0.0, 3600.0));
  v.choice("fallback", o.fallback,
           config::Choices<Fallback>{{"chain", Fallback::kChain}, {"own_motion", Fallback::kOwnMotion}});
  v.field("fallback_gamma", o.fallback_gamma, config::between(1e-6, 1.0));
  v.field("fallback_penetration_weight", o.fallback_penetration_weight, config::between(0.0, 1e9));
  v.field("recovery_switch_ratio", o.recovery_switch_ratio, config::between(0.0, 1.0));
  v.field("estimate_margin_m", o.estimate_margin, config::between(0.0, 10.0));
}

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
  WeightKeys w{weights};
  v.section("weights", w);
  CurvefitKeys c{*this};
  v.section("curvefit", c);
  EscapeKeys e{*this};
  v.section("escape", e);
  DetourKeys d{detour};
  v.section("detour", d);
  v.section("static_field", static_field);
  GuidanceKeys g{guidance};
  v.section("guidance", g);
  v.section("occlusion", occlusion);
  SolverKeys o{*this};
  v.section("solver", o);
}

}  // namespace evade::planning
