#include "planning/outcome.h"

#include <algorithm>
#include <cmath>

#include "planning/fallback.h"

namespace evade::planning {
namespace {

// The rollout's first N + 1 states, then `extra` more as the robot goes at
// step N (its last step's displacement, its heading held).
std::vector<double> extended_states(const std::vector<double>& states, int N, int extra) {
  std::vector<double> s(states.begin(), states.begin() + 3 * (N + 1));
  const size_t last = 3 * static_cast<size_t>(N);
  const double dx = N > 0 ? s[last] - s[last - 3] : 0.0;
  const double dy = N > 0 ? s[last + 1] - s[last - 2] : 0.0;
  for (int j = 1; j <= extra; ++j) s.insert(s.end(), {s[last] + j * dx, s[last + 1] + j * dy, s[last + 2]});
  return s;
}

// o carried on for `extra` steps as it goes at step N, its ellipse held.
void extend(int N, int extra, ObstacleTrack* o) {
  const double ox = N > 0 ? o->x[N] - o->x[N - 1] : 0.0, oy = N > 0 ? o->y[N] - o->y[N - 1] : 0.0;
  for (int j = 1; j <= extra; ++j) {
    o->x.push_back(o->x[N] + j * ox);
    o->y.push_back(o->y[N] + j * oy);
    o->a.push_back(o->a[N]);
    o->b.push_back(o->b[N]);
    o->theta.push_back(o->theta[N]);
  }
}

}  // namespace

double OutcomeMargin::at(double t_s, double speed_mps) const {
  const double m = share * speed_mps * t_s;
  return std::isfinite(m) ? std::clamp(m, 0.0, std::max(max_m, 0.0)) : 0.0;
}

Outcome plan_outcome(const Problem& pb, const std::vector<double>& states, double tolerance, int extend_steps,
                     const OutcomeMargin& margin) {
  // the footprint without the margin (barrier_h_at reads only these of a
  // Problem for an ellipse obstacle)
  Problem body;
  body.footprint = pb.footprint;
  body.d_safe = 0.0;
  const std::vector<double> s = extended_states(states, pb.N, extend_steps);
  Outcome out;
  for (const ObstacleTrack& track : pb.obstacles) {
    if (track.field) continue;
    const double speed = mean_predicted_speed(track, pb.N, pb.dt);
    ObstacleTrack o = track;
    remove_inflation(&o);
    extend(pb.N, extend_steps, &o);
    const double start = std::max(barrier_h_at(body, o, 0, &s[0]), 0.0);
    for (int k = 1; k <= pb.N + extend_steps; ++k) {
      const double now = barrier_h_at(body, o, k, &s[3 * k]);
      out.clearance = std::min(out.clearance, now);
      // a NaN distance is no meeting, as before the margin
      if (!(now < std::min(margin.at(k * pb.dt, speed), start) || now < 0.0)) continue;
      if (out.first_contact < 0 || k < out.first_contact) out.first_contact = k;
      out.kind = std::max(out.kind, Outcome::kTheirs);
      const double before = barrier_h_at(body, o, k, &s[3 * (k - 1)]);
      if (std::isfinite(before) && before - now > tolerance) out.kind = Outcome::kOurs;
    }
  }
  return out;
}

}  // namespace evade::planning
