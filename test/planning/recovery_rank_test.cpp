// The recovery's order of candidate plans (recovery_rank.h): each
// criterion decides only on a tie of those before it, and clear_by_cost
// changes the last one only between plans clear of the bodies that both
// keep h >= 0. A plan slowed onto passive safety's reach bounds is worse
// than the chosen one where it goes into structure, or (without
// walked_into_ok) meets a mover of a worse kind.
#include "planning/recovery_rank.h"

#include <gtest/gtest.h>

namespace evade::planning {
namespace {

constexpr double kTie = 1e-3;

RecoveryRank clear(double h, double cost) {
  RecoveryRank r;
  r.h = h;
  r.cost = cost;
  return r;
}

TEST(RecoveryRank, StructureFirstThenTheMoversThenClearance) {
  RecoveryRank into_wall = clear(2.0, 0.0), drives_into = clear(1.0, 0.0), walked_into = clear(0.5, 0.0);
  into_wall.judged.into = true;
  drives_into.judged.outcome.kind = Outcome::kOurs;
  walked_into.judged.outcome.kind = Outcome::kTheirs;
  const RecoveryRank open = clear(0.1, 50.0);
  for (bool by_cost : {false, true}) {
    EXPECT_TRUE(ranks_before(drives_into, into_wall, kTie, by_cost));
    EXPECT_TRUE(ranks_before(walked_into, drives_into, kTie, by_cost));
    EXPECT_TRUE(ranks_before(open, walked_into, kTie, by_cost));
    EXPECT_FALSE(ranks_before(into_wall, open, kTie, by_cost));
  }
  RecoveryRank shallower = into_wall;
  shallower.judged.contact = 0.01;
  into_wall.judged.contact = 0.05;
  EXPECT_TRUE(ranks_before(shallower, into_wall, kTie, false));
  RecoveryRank nearer = walked_into;
  nearer.judged.outcome.clearance = -0.2;
  walked_into.judged.outcome.clearance = -0.1;
  EXPECT_TRUE(ranks_before(walked_into, nearer, kTie, true));
}

TEST(RecoveryRank, ClearByCostPrefersTheCheaperOfTwoPlansOutsideEveryEllipse) {
  const RecoveryRank away = clear(0.6, 900.0), along = clear(0.05, 300.0);
  EXPECT_TRUE(ranks_before(away, along, kTie, false));  // most clearance
  EXPECT_FALSE(ranks_before(along, away, kTie, false));
  EXPECT_TRUE(ranks_before(along, away, kTie, true));  // lower J
  EXPECT_FALSE(ranks_before(away, along, kTie, true));
}

TEST(RecoveryRank, InsideAnEllipseClearanceStillDecides) {
  // one plan with h < 0: the larger h ranks first, whatever its cost
  const RecoveryRank inside = clear(-0.1, 10.0), outside = clear(0.2, 900.0);
  EXPECT_TRUE(ranks_before(outside, inside, kTie, true));
  EXPECT_FALSE(ranks_before(inside, outside, kTie, true));
  // both inside: most clearance as without the switch
  const RecoveryRank deeper = clear(-0.3, 1.0), shallow = clear(-0.05, 800.0);
  EXPECT_TRUE(ranks_before(shallow, deeper, kTie, true));
  // both clear of the ellipses but one walked into: the outcome decides
  RecoveryRank cheap_hit = clear(0.3, 1.0);
  cheap_hit.judged.outcome.kind = Outcome::kTheirs;
  EXPECT_TRUE(ranks_before(outside, cheap_hit, kTie, true));
}

TEST(RecoveryRank, TiesKeepTheEarlierPlan) {
  const RecoveryRank a = clear(0.3, 100.0), b = clear(0.3 + kTie / 2, 100.0);
  EXPECT_FALSE(ranks_before(b, a, kTie, false));
  EXPECT_FALSE(ranks_before(a, b, kTie, false));
  EXPECT_FALSE(ranks_before(a, a, kTie, true));
  RecoveryRank less_short = a;
  less_short.shortfall = -1.0;
  EXPECT_TRUE(ranks_before(less_short, a, kTie, false));
}

constexpr SlowedRefusal kRules[] = {SlowedRefusal::kWorseOutcome, SlowedRefusal::kDrivesInto,
                                    SlowedRefusal::kStructure};

TEST(SlowedIsWorse, StructureAlwaysMoversAsTheRuleSays) {
  RecoveryJudgement chosen;  // clear of structure and of every mover
  RecoveryJudgement slowed = chosen;
  for (SlowedRefusal rule : kRules) EXPECT_FALSE(slowed_is_worse(slowed, chosen, kTie, rule)) << "the same: no worse";
  // into structure's margin, or deeper into it: worse by every rule
  RecoveryJudgement into = chosen;
  into.into = true;
  RecoveryJudgement deeper = into;
  deeper.contact = 0.05;
  for (SlowedRefusal rule : kRules) {
    EXPECT_TRUE(slowed_is_worse(into, chosen, kTie, rule));
    EXPECT_TRUE(slowed_is_worse(deeper, into, kTie, rule));
    EXPECT_FALSE(slowed_is_worse(into, deeper, kTie, rule));
  }
  // walked into where the chosen plan was clear: worse only by the outcome
  RecoveryJudgement walked_into = chosen;
  walked_into.outcome.kind = Outcome::kTheirs;
  EXPECT_TRUE(slowed_is_worse(walked_into, chosen, kTie, SlowedRefusal::kWorseOutcome));
  EXPECT_FALSE(slowed_is_worse(walked_into, chosen, kTie, SlowedRefusal::kDrivesInto));
  EXPECT_FALSE(slowed_is_worse(walked_into, chosen, kTie, SlowedRefusal::kStructure));
  // driving into a mover where the chosen plan did not: worse unless only
  // structure counts
  RecoveryJudgement drives_into = chosen;
  drives_into.outcome.kind = Outcome::kOurs;
  for (SlowedRefusal rule : {SlowedRefusal::kWorseOutcome, SlowedRefusal::kDrivesInto}) {
    EXPECT_TRUE(slowed_is_worse(drives_into, chosen, kTie, rule));
    EXPECT_TRUE(slowed_is_worse(drives_into, walked_into, kTie, rule));
  }
  EXPECT_FALSE(slowed_is_worse(drives_into, chosen, kTie, SlowedRefusal::kStructure));
  EXPECT_FALSE(slowed_is_worse(drives_into, walked_into, kTie, SlowedRefusal::kStructure));
  for (SlowedRefusal rule : kRules) {
    EXPECT_FALSE(slowed_is_worse(drives_into, drives_into, kTie, rule)) << "it drove into one already";
    EXPECT_FALSE(slowed_is_worse(walked_into, drives_into, kTie, rule));
  }
}

}  // namespace
}  // namespace evade::planning
