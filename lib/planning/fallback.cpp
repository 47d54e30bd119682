#include "planning/fallback.h"

#include <algorithm>
#include <cmath>

#include "planning/manoeuvres.h"

namespace evade::planning {

void remove_inflation(ObstacleTrack* o) {
  if (o->sigma.size() != o->a.size()) return;
  for (size_t k = 0; k < o->a.size(); ++k) {
    // a degenerate ellipse (1 mm) at the least, never larger than given
    o->a[k] = std::min(o->a[k], std::max(o->a[k] - o->sigma[k], 1e-3));
    o->b[k] = std::min(o->b[k], std::max(o->b[k] - o->sigma[k], 1e-3));
  }
}

Problem fallback_problem(const Problem& pb, const std::vector<double>& brake_u, const SolverOptions& opts) {
  Problem out = pb;
  out.own_motion = true;
  out.penetration_weight = opts.fallback_penetration_weight;
  for (ObstacleTrack& o : out.obstacles) {
    o.decay = 1.0 - opts.fallback_gamma;
    if (opts.fallback_true_extent && settled_obstacle(pb, o, opts)) remove_inflation(&o);
  }
  out.relax.assign(out.num_constraints(), 0.0);
  std::vector<double> states, g;
  evaluate_constraints(out, brake_u.data(), &states, &g);
  // braking meets every link: each relaxed by what braking misses of it
  int last_closing = -1;  // the last step at which braking's own motion closes in
  const int R = out.num_rate_constraints();
  for (int j = R; j < out.num_constraints(); ++j)
    if (std::isfinite(g[j]) && g[j] < 0) {
      out.relax[j] = -g[j];
      if (-g[j] > opts.constraint_tolerance) last_closing = std::max(last_closing, (j - R) % out.N);
    }
  // the allowance is braking's: up to that step no plan is faster than it
  if (opts.fallback_brake_while_closing && last_closing >= 0) {
    out.v_cap.resize(out.N, out.lim.v_max);
    for (int k = 0; k <= last_closing; ++k) out.v_cap[k] = std::min(out.v_cap[k], std::max(0.0, brake_u[2 * k]));
  }
  return out;
}

std::vector<std::vector<double>> fallback_starts(const Problem& pb, const std::vector<double>& warm_u,
                                                 const std::vector<double>& brake_u) {
  std::vector<std::vector<double>> starts = {warm_u, brake_u};
  for (double side : {1.0, -1.0}) starts.push_back(dash_controls(pb, side));
  if (pb.lim.v_min < 0) {
    std::vector<double> back(pb.num_controls(), 0.0);
    for (int k = 0; k < pb.N; ++k) back[2 * k] = pb.lim.v_min;
    starts.push_back(back);
  }
  for (auto& s : starts) project_controls(pb, &s);
  return starts;
}

SolveResult solve_fallback(const CeresMpcSolver& solver, const Problem& pb, const std::vector<double>& warm_u,
                           const std::vector<double>& brake_u) {
  const SolverOptions& opts = solver.options();
  const Problem relaxed = fallback_problem(pb, brake_u, opts);
  std::vector<std::vector<double>> starts = fallback_starts(relaxed, warm_u, brake_u);
  const MultiStartResult m = solve_from_starts(opts, relaxed, std::move(starts), /*least_violating=*/false);
  SolveResult out = m.best;
  if (!m.found) out.u = brake_u;
  const bool have = m.found;
  evaluate_result(pb, opts, &out);
  out.feasible = have;
  return out;
}

}  // namespace evade::planning
