#include "planning/modes.h"

#include <stdexcept>

namespace evade::planning {

const std::vector<ModeSpec>& all_modes() {
  using S = ObstacleSource;
  using M = ObstacleMotion;
  using C = ConstraintForm;
  using G = GammaKey;
  static const std::vector<ModeSpec> modes = {
      // name, Table I row, input, motion, constraint, gamma, evade's layers
      {Mode::kMpc, "mpc", "MPC", S::kObserved, M::kHeld, C::kDistance, G::kPaper, false},
      {Mode::kCbf, "cbf", "MPC-CBF", S::kObserved, M::kHeld, C::kCbf, G::kPaper, false},
      {Mode::kKf, "kf", "MPC-KF", S::kPredicted, M::kPredicted, C::kDistance, G::kPaper, false},
      {Mode::kCbfCurvefit, "cbf_curvefit", "MPC-CBF-curvefit", S::kObserved, M::kCurveFit, C::kCbf, G::kPaper, false},
      {Mode::kDcbf, "dcbf", "MPC-D-CBF", S::kPredicted, M::kPredicted, C::kCbf, G::kPaper, false},
      {Mode::kEvade, "evade", "", S::kPredicted, M::kPredicted, C::kCbf, G::kEvade, true},
  };
  return modes;
}

const ModeSpec& mode_spec(Mode m) {
  for (const ModeSpec& s : all_modes())
    if (s.mode == m) return s;
  throw std::logic_error("planner mode missing from the mode table");
}

std::vector<std::string> mode_names() {
  std::vector<std::string> out;
  for (const ModeSpec& s : all_modes()) out.emplace_back(s.name);
  return out;
}

Mode parse_mode(const std::string& name) {
  for (const ModeSpec& s : all_modes())
    if (name == s.name) return s.mode;
  std::string known;
  for (const std::string& n : mode_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown planner mode '" + name + "' (" + known + ")");
}

const char* mode_name(Mode m) { return mode_spec(m).name; }

}  // namespace evade::planning
