// What a plan comes to against what moves (mode evade's recovery,
// README, What a cycle does, item 7): when no plan meets every D-CBF
// constraint, the candidates are judged by whether the robot's body and an
// obstacle's own predicted body meet within the horizon and, if they do,
// whose motion makes the contact.
//
// The obstacle's own body is its predicted ellipse less the uncertainty
// inflation the predictor added (remove_inflation, fallback.h): the
// inflation says where the obstacle may be, not where it will be, and from
// a few metres off it covers every way past it in a narrow passage. The
// robot's body is its footprint's discs without d_safe. A contact is the
// robot's (kOurs) when at a step where the bodies meet the robot's own
// step closes on the obstacle where it is then (the metrics' rule: the
// robot's velocity towards the other at the contact); else the other's
// (kTheirs: it walks into a robot standing or moving away).
//
// The margin (OutcomeMargin, off at 0): the bodies "meet" at step k when
// their distance is below margin(t_k) = min(max_m, share v t_k), t_k = k dt
// ahead of the plan's start and v the obstacle's mean predicted speed over
// the horizon (the length of its predicted centres' path over N dt): a
// share of how far it is predicted to go by then. A prediction's error
// grows about as speed times time ahead (a walker that turns round ends up
// to 2 v t off the constant-velocity mean); an obstacle predicted to stand
// gets no margin, with no threshold. Never below where they stand at the
// start: against an obstacle already within the margin at step 0, meeting
// is coming closer than that (a start inside it does not make every plan a
// contact).
#pragma once

#include <vector>

#include "planning/problem.h"

namespace evade::planning {

struct OutcomeMargin {
  double share = 0.0;  // m of margin per m the obstacle is predicted to go (its mean speed times the time ahead)
  double max_m = 0.0;  // m, the most it grows to
  // the margin t_s ahead of the plan's start against an obstacle of mean
  // predicted speed speed_mps (0 when either is not finite)
  double at(double t_s, double speed_mps) const;
};

struct Outcome {
  enum Kind { kClear = 0, kTheirs = 1, kOurs = 2 };  // in order of preference
  Kind kind = kClear;
  int first_contact = -1;                 // the first step at which the bodies meet (-1: never)
  double clearance = kNoObstacleBarrier;  // the least body distance over the steps judged (m, < 0: overlap)
};

// The outcome of a plan's rollout (`states`, 3 (N + 1)) against the
// ellipse obstacles of pb (the static field is not judged here:
// structure_intrusion). Steps k = 1..N; the robot's own step k - 1 -> k
// closes when it lowers the body distance to the obstacle at step k by
// more than `tolerance` (m). Then `extend_steps` more steps in which both go
// on as at the horizon's end (the robot at its last step's speed and
// heading, the obstacle at its last step's velocity): a plan that stands in
// a mover's lane meets it, if not within the horizon then soon after.
Outcome plan_outcome(const Problem& pb, const std::vector<double>& states, double tolerance, int extend_steps = 0,
                     const OutcomeMargin& margin = {});

}  // namespace evade::planning
