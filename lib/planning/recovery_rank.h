// The order of the recovery's last resort (PlannerCore::most_clearance,
// planner_recovery.cpp): when no plan meets every D-CBF constraint, which
// of two candidate plans is sent. Each criterion decides only when the one
// before it ties:
//  1. a plan that goes no deeper into static structure's margin than it
//     starts (`into` false) ranks first; of two that both do, the one whose
//     body goes less far into the structure itself (`contact`);
//  2. what the plan comes to against what moves (`outcome`, outcome.h):
//     clear of every mover's body, then walked into, then driving into one;
//     of two that meet a mover, the larger least body distance;
//  3. the larger h, the least barrier value over the horizon against the
//     inflated ellipses (most clearance), then the smaller D-CBF shortfall.
//     With `clear_by_cost`, of two plans clear of the bodies that both keep
//     h >= 0 (outside every inflated ellipse grown by d_safe for the whole
//     horizon), the one of lower cost J (the MPC's own objective) instead:
//     a dash away from every walker costs the turns back to the route.
//     Off: against movers predicted poorly (fast, new, zig-zagging) the
//     extra clearance is what covers the prediction's error
//     (docs/experiments/2026-11-30-clear-by-cost.md).
// Differences within `tie` (m) are ties.
#pragma once

#include "planning/outcome.h"

namespace evade::planning {

// What a candidate's rollout comes to against structure and movers
// (PlannerCore::judge_recovery_plan); passive_safety.slow_chosen compares
// a slowed plan's with it.
struct RecoveryJudgement {
  bool into = false;     // deeper into structure's margin than the tolerance (structure_depth's margin)
  double contact = 0.0;  // m, how far the body goes into structure beyond its start (structure_depth's body)
  Outcome outcome{};     // against the movers' predicted bodies (plan_outcome; kClear without the outcome rank)
};

struct RecoveryRank {
  RecoveryJudgement judged{};
  double h = 0.0;          // m, the least barrier value over steps 1..N
  double shortfall = 0.0;  // the D-CBF chain's worst shortfall
  double cost = 0.0;       // J (used with clear_by_cost only)
};

// Whether c ranks before b.
bool ranks_before(const RecoveryRank& c, const RecoveryRank& b, double tie, bool clear_by_cost);

// passive_safety.slowed_refused_if: what makes the chosen plan slowed onto
// passive safety's reach bounds worse than the chosen plan as it was, so
// that the chosen plan is sent unslowed. Always: going into structure's
// margin where the chosen did not, or its body deeper (beyond the tie).
enum class SlowedRefusal {
  kWorseOutcome,  // also: an outcome against the movers of a worse kind
  kDrivesInto,    // also: driving into a mover where the chosen did not (walked into is no worse:
                  // a contact the robot does not make, passive safety's point)
  kStructure,     // structure only: against movers the reach bounds decide (passive safety kept)
};

// Whether the slowed plan (judged `slowed`) is worse than the chosen plan
// (`chosen`) by `rule`.
bool slowed_is_worse(const RecoveryJudgement& slowed, const RecoveryJudgement& chosen, double tie, SlowedRefusal rule);

}  // namespace evade::planning
