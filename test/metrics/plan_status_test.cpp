// Every PLAN status code has its own name; an unknown code says so.
#include "metrics/plan_status.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "evade/plan_t.hpp"

TEST(PlanStatus, EveryCodeHasItsOwnName) {
  using P = evade::plan_t;
  const int codes[] = {P::STATUS_OK,       P::STATUS_FALLBACK, P::STATUS_STOPPING,  P::STATUS_STALE_INPUT,
                       P::STATUS_NO_ROUTE, P::STATUS_GOAL,     P::STATUS_RECOVERING};
  std::set<std::string> names;
  for (int c : codes) {
    const std::string name = evade::metrics::plan_status_name(c);
    EXPECT_NE(name, "unknown") << "code " << c;
    EXPECT_EQ(name.find(' '), std::string::npos) << name;
    names.insert(name);
  }
  EXPECT_EQ(names.size(), std::size(codes));
  EXPECT_STREQ(evade::metrics::plan_status_name(-1), "unknown");
  EXPECT_STREQ(evade::metrics::plan_status_name(127), "unknown");
}
