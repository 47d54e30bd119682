#include "planning/passive_safety.h"

#include <algorithm>
#include <cmath>

#include "planning/fallback.h"

namespace evade::planning {

double passive_safe_speed(double gap_m, double mover_speed_mps, double reaction_s, double decel_mps2) {
  const double s = std::max(0.0, mover_speed_mps);
  const double g = gap_m - s * reaction_s;
  if (!(g > 0.0) || !(decel_mps2 > 0.0)) return 0.0;
  const double p = reaction_s + s / decel_mps2;
  return decel_mps2 * (std::sqrt(p * p + 2.0 * g / decel_mps2) - p);
}

std::vector<MoverBound> mover_bounds(const PassiveSafetyParams& p, const Problem& pb) {
  std::vector<MoverBound> out;
  if (pb.footprint.offsets.empty()) return out;
  // the front disc alone, without d_safe (barrier_h_at reads only these)
  Problem front;
  front.footprint.offsets = {*std::max_element(pb.footprint.offsets.begin(), pb.footprint.offsets.end())};
  front.footprint.radius = pb.footprint.radius;
  front.d_safe = 0.0;
  const double start[3] = {pb.x0, pb.y0, pb.yaw0};
  for (const ObstacleTrack& track : pb.obstacles) {
    if (track.field || track.x.empty()) continue;
    double speed = fastest_predicted_speed(track, pb.dt);
    if (track.age_s < p.min_track_age_s)
      speed = std::max(speed, p.unknown_speed_mps);
    else if (speed < p.min_mover_speed_mps)
      continue;
    MoverBound m{track, pb.lim.v_max};
    remove_inflation(&m.body);
    const double gap = barrier_h_at(front, m.body, 0, start);
    if (!std::isfinite(gap)) continue;
    m.speed_mps = std::min(pb.lim.v_max, passive_safe_speed(gap, speed, p.reaction_s, pb.lim.decel));
    out.push_back(std::move(m));
  }
  return out;
}

double passive_speed_bound(const PassiveSafetyParams& p, const Problem& pb) {
  double bound = pb.lim.v_max;
  for (const MoverBound& m : mover_bounds(p, pb)) bound = std::min(bound, m.speed_mps);
  return bound;
}

std::vector<ClosingBound> passive_closing_bounds(const PassiveSafetyParams& p, const Problem& pb) {
  std::vector<ClosingBound> out;
  std::vector<double> brake(static_cast<size_t>(pb.num_controls()), 0.0), states;
  bool braked = false;
  for (const MoverBound& m : mover_bounds(p, pb)) {
    if (!(m.speed_mps < pb.lim.v_max)) continue;
    if (!braked) {
      project_controls(pb, &brake);
      states.resize(3 * static_cast<size_t>(pb.N + 1));
      rollout(pb, brake.data(), states.data());
      braked = true;
    }
    ClosingBound c{m.body.id, m.body.x[0], m.body.y[0], m.body.a[0], m.body.b[0], m.body.theta[0], {}};
    c.step_m.resize(static_cast<size_t>(pb.N));
    for (int k = 0; k < pb.N; ++k) {
      const double braking_closes = closing_barrier(pb, c, &states[3 * static_cast<size_t>(k)], false).h -
                                    closing_barrier(pb, c, &states[3 * static_cast<size_t>(k + 1)], false).h;
      c.step_m[static_cast<size_t>(k)] = std::max(m.speed_mps * pb.dt, braking_closes);
    }
    out.push_back(std::move(c));
  }
  return out;
}

bool bound_passively(const PassiveSafetyParams& p, Problem* pb) {
  if (p.towards_only) {
    std::vector<ClosingBound> bounds = passive_closing_bounds(p, *pb);
    if (bounds.empty()) return false;
    for (ClosingBound& c : bounds) pb->closing.push_back(std::move(c));
    return true;
  }
  const double bound = passive_speed_bound(p, *pb);
  if (!(bound < pb->lim.v_max)) return false;
  pb->v_cap.resize(static_cast<size_t>(std::max(pb->N, 0)), pb->lim.v_max);
  for (double& cap : pb->v_cap) cap = std::min(cap, bound);
  return true;
}

}  // namespace evade::planning
