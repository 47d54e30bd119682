#include "planning/selection.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::planning {

Candidate check_plan(const Problem& pb, const RouteFrame& f, const std::vector<double>& u, double tolerance) {
  Candidate c;
  c.u = u;
  std::vector<double> states, g;
  evaluate_constraints(pb, u.data(), &states, &g);
  double worst = 0.0;
  bool finite = std::all_of(u.begin(), u.end(), [](double x) { return std::isfinite(x); });
  for (double gj : g) {
    if (!std::isfinite(gj)) finite = false;
    worst = std::max(worst, -gj);
  }
  c.violation = finite ? worst : std::numeric_limits<double>::infinity();
  c.cost = finite ? objective(pb, u.data()) : std::numeric_limits<double>::infinity();
  c.feasible = finite && std::isfinite(c.cost) && c.violation <= tolerance;
  if (finite) c.signature = states_signature(pb, f, states);
  return c;
}

int select_plan(const std::vector<Candidate>& c, const std::optional<Signature>& previous, double switch_cost_factor) {
  int best = -1;
  double best_score = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < c.size(); ++i) {
    if (!c[i].feasible) continue;
    const bool keeps = !previous || compatible(c[i].signature, *previous);
    const double score = keeps ? c[i].cost : c[i].cost * switch_cost_factor;
    if (score < best_score) {
      best_score = score;
      best = static_cast<int>(i);
    }
  }
  return best;
}

int least_violating(const std::vector<Candidate>& c) {
  int best = -1;
  for (size_t i = 0; i < c.size(); ++i)
    if (best < 0 || c[i].violation < c[best].violation) best = static_cast<int>(i);
  return best;
}

}  // namespace evade::planning
