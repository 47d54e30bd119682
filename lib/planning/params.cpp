#include "planning/params.h"

#include <cmath>
#include <stdexcept>

#include "config/robot_params.h"

namespace evade::planning {

double PlannerParams::constraint_decay() const {
  const ModeSpec& m = mode_spec(mode);
  if (m.constraint == ConstraintForm::kDistance) return 0.0;
  return 1.0 - (m.gamma == GammaKey::kEvade ? evade_gamma : gamma);
}

PlannerParams PlannerParams::from_config(const config::Node& root) {
  // shared robot limits (read first: the reference speed is bounded by them)
  const config::Node robot_node = root.section("robot");
  const config::RobotParams robot = config::load<config::RobotParams>(robot_node);
  if (robot.min_v_mps < 0.0) robot_node.fail("min_v_mps", "the planner does not reverse: must be at least 0");
  PlannerParams p;
  p.limits.v_max = robot.max_v_mps;
  p.limits.v_min = robot.min_v_mps;
  p.limits.omega_max = robot.max_omega_radps;
  p.limits.accel = robot.max_accel_mps2;
  p.limits.decel = robot.max_decel_mps2;
  p.limits.alpha = robot.max_alpha_radps2;
  config::load_into(root.section("planner"), p);
  p.footprint = Footprint::covering(robot.footprint_length_m, robot.footprint_width_m, p.footprint_discs);
  return p;
}

config::Choices<Mode> PlannerParams::mode_choices() {
  config::Choices<Mode> out;
  for (const auto& name : mode_names()) out.emplace_back(name, parse_mode(name));
  return out;
}

}  // namespace evade::planning
