#include "planning/recovery_rank.h"

#include <cmath>

namespace evade::planning {

bool ranks_before(const RecoveryRank& c, const RecoveryRank& b, double tie, bool clear_by_cost) {
  const RecoveryJudgement &cj = c.judged, &bj = b.judged;
  if (cj.into != bj.into) return !cj.into;
  if (std::fabs(cj.contact - bj.contact) > tie) return cj.contact < bj.contact;
  if (cj.outcome.kind != bj.outcome.kind) return cj.outcome.kind < bj.outcome.kind;
  if (cj.outcome.kind != Outcome::kClear && std::fabs(cj.outcome.clearance - bj.outcome.clearance) > tie)
    return cj.outcome.clearance > bj.outcome.clearance;
  if (clear_by_cost && cj.outcome.kind == Outcome::kClear && c.h >= -tie && b.h >= -tie) return c.cost < b.cost;
  return c.h > b.h + tie || (c.h > b.h - tie && c.shortfall < b.shortfall - 1e-9);
}

bool slowed_is_worse(const RecoveryJudgement& slowed, const RecoveryJudgement& chosen, double tie, SlowedRefusal rule) {
  if ((slowed.into && !chosen.into) || slowed.contact > chosen.contact + tie) return true;
  switch (rule) {
    case SlowedRefusal::kWorseOutcome:
      return slowed.outcome.kind > chosen.outcome.kind;
    case SlowedRefusal::kDrivesInto:
      return slowed.outcome.kind == Outcome::kOurs && chosen.outcome.kind != Outcome::kOurs;
    case SlowedRefusal::kStructure:
      return false;
  }
  return false;
}

}  // namespace evade::planning
