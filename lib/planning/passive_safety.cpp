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

double passive_speed_bound(const PassiveSafetyParams& p, const Problem& pb) {
  double bound = pb.lim.v_max;
  if (pb.footprint.offsets.empty()) return bound;
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
    ObstacleTrack body = track;
    remove_inflation(&body);
    const double gap = barrier_h_at(front, body, 0, start);
    if (!std::isfinite(gap)) continue;
    bound = std::min(bound, passive_safe_speed(gap, speed, p.reaction_s, pb.lim.decel));
  }
  return bound;
}

bool bound_passively(const PassiveSafetyParams& p, Problem* pb) {
  const double bound = passive_speed_bound(p, *pb);
  if (!(bound < pb->lim.v_max)) return false;
  pb->v_cap.resize(static_cast<size_t>(std::max(pb->N, 0)), pb->lim.v_max);
  for (double& cap : pb->v_cap) cap = std::min(cap, bound);
  return true;
}

}  // namespace evade::planning
