#include "planning/recovery_rank.h"

#include <cmath>

namespace evade::planning {

bool ranks_before(const RecoveryRank& c, const RecoveryRank& b, double tie, bool clear_by_cost) {
  if (c.into != b.into) return !c.into;
  if (std::fabs(c.contact - b.contact) > tie) return c.contact < b.contact;
  if (c.outcome.kind != b.outcome.kind) return c.outcome.kind < b.outcome.kind;
  if (c.outcome.kind != Outcome::kClear && std::fabs(c.outcome.clearance - b.outcome.clearance) > tie)
    return c.outcome.clearance > b.outcome.clearance;
  if (clear_by_cost && c.outcome.kind == Outcome::kClear && c.h >= -tie && b.h >= -tie) return c.cost < b.cost;
  return c.h > b.h + tie || (c.h > b.h - tie && c.shortfall < b.shortfall - 1e-9);
}

}  // namespace evade::planning
