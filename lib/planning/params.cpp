#include "planning/params.h"

#include <cmath>
#include <stdexcept>

namespace evade::planning {

double PlannerParams::constraint_decay() const {
  const ModeSpec& m = mode_spec(mode);
  if (m.constraint == ConstraintForm::kDistance) return 0.0;
  return 1.0 - (m.gamma == GammaKey::kEvade ? evade_gamma : gamma);
}

PlannerParams PlannerParams::from_config(const config::Node& root) {
  PlannerParams p;
  // shared robot limits (the robot section belongs to everyone: read, not closed)
  const config::Node robot = root.section("robot");
  p.limits.v_max = robot.get_positive("max_v_mps");
  p.limits.v_min = robot.get_double("min_v_mps", 0.0, p.limits.v_max);
  p.limits.omega_max = robot.get_positive("max_omega_radps");
  p.limits.accel = robot.get_positive("max_accel_mps2");
  p.limits.decel = robot.get_positive("max_decel_mps2");
  p.limits.alpha = robot.get_positive("max_alpha_radps2");
  const double length_m = robot.get_positive("footprint_length_m");
  const double width_m = robot.get_positive("footprint_width_m");

  const config::Node s = root.section("planner");
  p.mode = parse_mode(s.get_choice("mode", mode_names()));
  p.paper_fallback = s.get_choice("paper_fallback", {"brake", "last_plan"}) == "brake" ? PaperFallback::kBrake
                                                                                       : PaperFallback::kLastPlan;
  p.rate_hz = s.get_positive("rate_hz");
  p.horizon_steps = s.get_int("horizon_steps", 2, 64);
  p.dt_s = s.get_positive("dt_s");
  p.gamma = s.get_double("gamma", 1e-6, 1.0);  // 0 < gamma <= 1 (paper, discrete D-CBF)
  p.evade_gamma = s.get_double("evade_gamma", 1e-6, 1.0);
  p.d_safe_m = s.get_double("d_safe_m", 0.0, 10.0);
  p.footprint_discs = s.get_int("footprint_discs", 1, 16);
  p.footprint = Footprint::covering(length_m, width_m, p.footprint_discs);
  p.reference_speed_mps = s.get_double("reference_speed_mps", 0.0, p.limits.v_max);
  p.route_end_decel_mps2 = s.get_positive("route_end_decel_mps2");
  p.goal_tolerance_m = s.get_positive("goal_tolerance_m");
  p.route_search_window_m = s.get_positive("route_search_window_m");
  p.blocked_after_s = s.get_positive("blocked_after_s");
  p.blocked_progress_m = s.get_positive("blocked_progress_m");
  p.obstacle_consider_radius_m = s.get_positive("obstacle_consider_radius_m");
  p.max_obstacles = s.get_int("max_obstacles", 0, 256);
  p.odometry_max_age_s = s.get_positive("odometry_max_age_s");
  p.predictions_max_age_s = s.get_positive("predictions_max_age_s");
  p.obstacles_max_age_s = s.get_positive("obstacles_max_age_s");
  p.require_obstacles = s.get<bool>("require_obstacles");

  const config::Node w = s.section("weights");
  p.weights.q_xy = w.get_double("q_xy", 0, 1e6);
  p.weights.q_yaw = w.get_double("q_yaw", 0, 1e6);
  p.weights.p_xy = w.get_double("p_xy", 0, 1e6);
  p.weights.p_yaw = w.get_double("p_yaw", 0, 1e6);
  p.weights.r_v = w.get_double("r_v", 0, 1e6);
  p.weights.r_omega = w.get_double("r_omega", 0, 1e6);
  p.weights.s_v = w.get_double("s_v", 0, 1e6);
  p.weights.s_omega = w.get_double("s_omega", 0, 1e6);
  w.close();

  const config::Node c = s.section("curvefit");
  p.curvefit_degree = c.get_int("degree", 0, 5);
  p.curvefit_window_s = c.get_positive("window_s");
  c.close();

  const config::Node e = s.section("escape");
  p.escape_enabled = e.get<bool>("enabled");
  p.escape_min_progress_m = e.get_double("min_progress_m", 0.0, 10.0);
  p.escape_near_m = e.get_double("near_m", -10.0, 10.0);
  p.escape_cone_half_angle_rad = e.get_double("cone_half_angle_deg", 0.0, 89.0) * M_PI / 180.0;
  e.close();

  const config::Node d = s.section("detour");
  p.detour.enabled = d.get<bool>("enabled");
  p.detour.lookahead_m = d.get_double("lookahead_m", 0.0, 100.0);
  p.detour.cell_m = d.get_double("cell_m", 0.01, 1.0);
  p.detour.margin_m = d.get_double("margin_m", 0.0, 10.0);
  p.detour.comfort_m = d.get_double("comfort_m", p.detour.margin_m + 1e-3, 20.0);
  p.detour.proximity_cost = d.get_double("proximity_cost", 0.0, 1e3);
  p.detour.deviation_cost = d.get_double("deviation_cost", 0.0, 1e3);
  p.detour.rejoin_m = d.get_double("rejoin_m", 0.0, 100.0);
  p.detour.pad_m = d.get_double("pad_m", 0.0, 100.0);
  p.detour.max_obstacle_speed_mps = d.get_double("max_obstacle_speed_mps", 0.0, 100.0);
  p.detour.min_track_age_s = d.get_double("min_track_age_s", 0.0, 3600.0);
  p.detour.blocked_cost = d.get_double("blocked_cost", 1.0, 1e6);
  p.detour.keep_side_discount = d.get_double("keep_side_discount", 0.01, 1.0);
  p.detour.smoothing_m = d.get_double("smoothing_m", 0.0, 10.0);
  p.detour.max_cells = d.get_int("max_cells", 1, 10000000);
  p.detour.min_offset_m = d.get_double("min_offset_m", 0.0, 100.0);
  p.detour.memory_s = d.get_double("memory_s", 0.0, 3600.0);
  p.detour.leader_max_speed_mps = d.get_double("leader_max_speed_mps", 0.0, 100.0);
  p.detour.leader_max_angle_rad = d.get_double("leader_max_angle_deg", 0.0, 90.0) * M_PI / 180.0;
  p.detour.leader_sweep_s = d.get_double("leader_sweep_s", 0.0, 60.0);
  p.detour.oncoming_max_angle_rad = d.get_double("oncoming_max_angle_deg", 0.0, 90.0) * M_PI / 180.0;
  p.detour.oncoming_sweep_s = d.get_double("oncoming_sweep_s", 0.0, 60.0);
  p.detour.oncoming_max_sigma_m = d.get_double("oncoming_max_sigma_m", 0.0, 100.0);
  p.detour.min_mover_age_s = d.get_double("min_mover_age_s", 0.0, 3600.0);
  d.close();

  const config::Node g = s.section("guidance");
  p.guidance.enabled = g.get<bool>("enabled");
  p.guidance.max_classes = g.get_int("max_classes", 0, 16);
  p.guidance.threads = g.get_int("threads", 1, 64);
  p.guidance.layer_steps = g.get_int("layer_steps", 1, 64);
  p.guidance.lateral_step_m = g.get_double("lateral_step_m", 0.05, 2.0);
  p.guidance.lateral_max_m = g.get_double("lateral_max_m", 0.0, 10.0);
  p.guidance.longitudinal_step_m = g.get_double("longitudinal_step_m", 0.05, 2.0);
  p.guidance.switch_cost_factor = g.get_double("switch_cost_factor", 1.0, 100.0);
  p.guidance.fallback = g.get_choice("fallback", {"least_violating", "recovery"}) == "recovery"
                            ? GuidanceParams::Fallback::kRecovery
                            : GuidanceParams::Fallback::kLeastViolating;
  g.close();

  const config::Node o = s.section("solver");
  p.solver.max_outer_iterations = o.get_int("max_outer_iterations", 1, 1000);
  p.solver.max_inner_iterations = o.get_int("max_inner_iterations", 1, 1000);
  p.solver.max_total_iterations = o.get_int("max_total_iterations", 1, 100000);
  p.max_cycle_iterations = o.get_int("max_cycle_iterations", 1, 1000000);
  p.solver.constraint_tolerance = o.get_positive("constraint_tolerance");
  p.solver.target_violation = o.get_double("target_violation", 0.0, p.solver.constraint_tolerance);
  p.solver.min_trust_radius = o.get_positive("min_trust_radius");
  p.solver.penalty_initial = o.get_positive("penalty_initial");
  p.solver.warm_penalty_max = o.get_double("warm_penalty_max", p.solver.penalty_initial, 1e12);
  p.solver.penalty_growth = o.get_double("penalty_growth", 1.0, 1e3);
  p.solver.penalty_max = o.get_positive("penalty_max");
  p.solver.violation_shrink = o.get_double("violation_shrink", 0.0, 1.0);
  p.solver.active_margin = o.get_double("active_margin_m", 0.0, 100.0);
  p.solver.complementarity_tolerance = o.get_double("complementarity_tolerance_m", 0.0, 10.0);
  p.solver.inner_function_tolerance = o.get_positive("inner_function_tolerance");
  p.solver.inner_parameter_tolerance = o.get_positive("inner_parameter_tolerance");
  p.warm_multipliers = o.get<bool>("warm_multipliers");
  p.solver.projection_iterations = o.get_int("projection_iterations", 0, 1000);
  p.solver.projection_target = o.get_double("projection_target_m", 0.0, p.solver.target_violation);
  p.solver.projection_damping = o.get_double("projection_damping", 0.0, 1.0);
  p.solver.projection_candidates = o.get_int("projection_candidates", 0, 1000);
  p.solver.projection_candidate_violation = o.get_double("projection_candidate_violation_m", 0.0, 10.0);
  p.solver.estimate_multipliers = o.get<bool>("estimate_multipliers");
  p.solver.estimate_margin = o.get_double("estimate_margin_m", 0.0, 10.0);
  p.solver.relax_max_obstacle_speed = o.get_double("relax_max_obstacle_speed_mps", 0.0, 100.0);
  p.solver.relax_min_obstacle_age = o.get_double("relax_min_track_age_s", 0.0, 3600.0);
  p.solver.recovery_switch_ratio = o.get_double("recovery_switch_ratio", 0.0, 1.0);
  p.solver.dense_qr = o.get_choice("linear_solver", {"dense_normal_cholesky", "dense_qr"}) == "dense_qr";
  const std::string ls = o.get_choice("line_search_interpolation", {"bisection", "quadratic", "cubic"});
  p.solver.line_search = ls == "bisection"   ? LineSearchInterpolation::kBisection
                         : ls == "quadratic" ? LineSearchInterpolation::kQuadratic
                                             : LineSearchInterpolation::kCubic;
  o.close();
  s.close();
  return p;
}

}  // namespace evade::planning
