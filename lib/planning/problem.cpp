#include "planning/problem.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace evade::planning {

double fastest_predicted_speed(const ObstacleTrack& o, double dt) {
  double v = 0.0;
  if (!(dt > 0.0)) return v;
  const size_t n = std::min(o.x.size(), o.y.size());
  for (size_t k = 1; k < n; ++k) {
    const double step = std::hypot(o.x[k] - o.x[k - 1], o.y[k] - o.y[k - 1]) / dt;
    if (std::isfinite(step)) v = std::max(v, step);
  }
  return v;
}

double mean_predicted_speed(const ObstacleTrack& o, int N, double dt) {
  if (N <= 0 || !(dt > 0) || o.x.size() <= static_cast<size_t>(N) || o.y.size() <= static_cast<size_t>(N)) return 0.0;
  double path = 0.0;
  for (int k = 1; k <= N; ++k) path += std::hypot(o.x[k] - o.x[k - 1], o.y[k] - o.y[k - 1]);
  return std::isfinite(path) ? path / (N * dt) : 0.0;
}

double objective(const Problem& pb, const double* u) {
  std::vector<double> states(3 * (pb.N + 1));
  rollout(pb, u, states.data());
  return objective(pb, u, states);
}

double objective(const Problem& pb, const double* u, const std::vector<double>& states) {
  std::vector<double> r(num_cost_residuals(pb));
  cost_residuals(pb, states.data(), u, r.data());
  double J = 0;
  for (double v : r) J += v * v;
  // stage k = 0: fixed by the start state, part of the paper's J all the same
  const double ex = pb.x0 - pb.ref_x[0], ey = pb.y0 - pb.ref_y[0], eyaw = wrap_angle(pb.yaw0 - pb.ref_yaw[0]);
  J += pb.w.q_xy * (ex * ex + ey * ey) + pb.w.q_yaw * eyaw * eyaw;
  if (pb.penetration_weight > 0) J += pb.penetration_weight * squared_penetration(pb, states);
  return J;
}

double squared_penetration(const Problem& pb, const std::vector<double>& states) {
  double sum = 0;
  for (const auto& o : pb.obstacles)
    for (int k = 1; k <= pb.N; ++k) {
      const double h = barrier_h_at(pb, o, k, &states[3 * k]);
      if (h < 0) sum += h * h;
    }
  return sum;
}

namespace {

// The barrier constraints of constraint<double> (j = R + i N + k) into g,
// each h computed once although two links use it: the same values.
void barrier_constraints(const Problem& pb, const double* states, double* g) {
  const int N = pb.N, R = pb.num_rate_constraints();
  const bool point = is_point(pb.footprint);
  std::vector<double> cyaw(N + 1), syaw(N + 1), h(N + 1);
  for (int k = 0; k <= N; ++k) {
    cyaw[k] = point ? 1.0 : std::cos(states[3 * k + 2]);
    syaw[k] = point ? 0.0 : std::sin(states[3 * k + 2]);
  }
  for (size_t i = 0; i < pb.obstacles.size(); ++i) {
    const ObstacleTrack& o = pb.obstacles[i];
    for (int k = 0; k <= N; ++k) h[k] = barrier_h_trig(pb, o, k, states + 3 * k, cyaw[k], syaw[k]);
    for (int k = 0; k < N; ++k) {
      const int j = R + static_cast<int>(i) * N + k;
      double v = h[k + 1];
      if (o.decay != 0.0 || pb.own_motion) {
        // the own-motion form's first term is the state at k against the obstacle at k + 1
        const double h0 = pb.own_motion ? barrier_h_trig(pb, o, k + 1, states + 3 * k, cyaw[k], syaw[k]) : h[k];
        const double decay = pb.own_motion && h0 <= 0.0 ? 1.0 : o.decay;
        v = v - decay * h0;
      }
      if (!pb.relax.empty()) v = v + pb.relax[j];
      g[j] = v;
    }
  }
}

}  // namespace

void evaluate_constraints(const Problem& pb, const double* u, std::vector<double>* states, std::vector<double>* g) {
  states->assign(3 * (pb.N + 1), 0.0);
  rollout(pb, u, states->data());
  g->resize(pb.num_constraints());
  const int R = pb.num_rate_constraints(), B = pb.num_barrier_constraints();
  for (int j = 0; j < R; ++j) (*g)[j] = constraint(pb, states->data(), u, j);
  barrier_constraints(pb, states->data(), g->data());
  for (int j = R + B; j < pb.num_constraints(); ++j) (*g)[j] = constraint(pb, states->data(), u, j);
}

double max_violation(const Problem& pb, const double* u) {
  std::vector<double> states, g;
  evaluate_constraints(pb, u, &states, &g);
  double worst = 0;
  for (double v : g) worst = std::max(worst, -v);
  return worst;
}

double min_barrier(const Problem& pb, const std::vector<double>& states, int first_step) {
  double best = kNoObstacleBarrier;
  for (const auto& o : pb.obstacles)
    for (int k = first_step; k <= pb.N; ++k) best = std::min(best, barrier_h_at(pb, o, k, &states[3 * k]));
  return best;
}

double barrier_slack(const Problem& pb, const ObstacleTrack& o, const std::vector<double>& states) {
  double slack = std::numeric_limits<double>::infinity();
  for (int k = 0; k < pb.N; ++k) {
    const double h0 = barrier_h_at(pb, o, k, &states[3 * k]);
    const double h1 = barrier_h_at(pb, o, k + 1, &states[3 * (k + 1)]);
    slack = std::min(slack, h1 - o.decay * h0);
  }
  return slack;
}

}  // namespace evade::planning
