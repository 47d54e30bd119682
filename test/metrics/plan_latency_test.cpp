// plan_latency (lib/metrics/plan_latency.h): from a prediction list's
// arrival to the CMD_VEL of the plan made from it, on hand-made logs.
#include "metrics/plan_latency.h"

#include <gtest/gtest.h>

#include "bus/core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"

namespace evade::metrics {
namespace {

bus::LogEvent list_at(int64_t t, int64_t utime) {
  evade::prediction_list_t m{};
  m.utime = utime;
  m.dt = 0.1;
  return {t, "OBSTACLE_PREDICTIONS", bus::encode(m)};
}

// A PLAN (from odometry `odom_utime`, naming list `list_utime`) at t and
// its CMD_VEL right after it.
void plan_at(std::vector<bus::LogEvent>* log, int64_t t, int64_t odom_utime, int64_t list_utime) {
  evade::plan_t p{};
  p.utime = odom_utime;
  p.predictions_utime = list_utime;
  evade::cmd_vel_t c{};
  c.utime = odom_utime;
  log->push_back({t, "PLAN", bus::encode(p)});
  log->push_back({t + 100, "CMD_VEL", bus::encode(c)});
}

TEST(PlanLatency, FromArrivalToTheCommandOfThePlanMadeFromTheList) {
  std::vector<bus::LogEvent> log;
  // list 1 arrives at 1.000 s (stamped 0.990 s); a cycle from older
  // predictions is under way and ends at 1.004 s; then the plan from list
  // 1 at 1.020 s, its command 0.1 ms later
  log.push_back(list_at(1'000'000, 990'000));
  plan_at(&log, 1'004'000, 980'000, 890'000);
  plan_at(&log, 1'020'000, 1'000'000, 990'000);
  // a later odometry cycle naming list 1 again: not the plan made from it
  plan_at(&log, 1'060'000, 1'040'000, 990'000);
  // list 2 at 1.100 s, answered 5 ms later; list 3 at 1.200 s, never
  log.push_back(list_at(1'100'000, 1'090'000));
  plan_at(&log, 1'104'900, 1'100'000, 1'090'000);
  log.push_back(list_at(1'200'000, 1'190'000));
  const PlanLatency r = plan_latency(log);
  EXPECT_FALSE(r.by_first_cmd);
  EXPECT_EQ(r.lists, 3);
  EXPECT_EQ(r.planned, 2);
  EXPECT_EQ(r.unplanned, 1);
  ASSERT_EQ(r.latency_ms.size(), 2u);
  EXPECT_DOUBLE_EQ(r.latency_ms[0], 20.1);
  EXPECT_DOUBLE_EQ(r.latency_ms[1], 5.0);
  EXPECT_DOUBLE_EQ(r.percentile_ms(0.5), 12.55);
  EXPECT_DOUBLE_EQ(r.percentile_ms(1.0), 20.1);
}

TEST(PlanLatency, PlansNamingNoListAreMeasuredToTheFirstCommandAfterArrival) {
  std::vector<bus::LogEvent> log;
  log.push_back(list_at(1'000'000, 990'000));
  plan_at(&log, 1'004'000, 980'000, -1);  // under way when the list came: counted by this rule
  plan_at(&log, 1'020'000, 1'000'000, -1);
  log.push_back(list_at(1'100'000, 1'090'000));
  log.push_back(list_at(1'100'500, 1'090'000));  // the same list again: one list
  plan_at(&log, 1'150'000, 1'140'000, -1);
  const PlanLatency r = plan_latency(log);
  EXPECT_TRUE(r.by_first_cmd);
  EXPECT_EQ(r.lists, 2);
  ASSERT_EQ(r.latency_ms.size(), 2u);
  EXPECT_DOUBLE_EQ(r.latency_ms[0], 4.1);
  EXPECT_DOUBLE_EQ(r.latency_ms[1], 50.1);
}

TEST(PlanLatency, MalformedMessagesAndAnEmptyLogGiveNoLatency) {
  std::vector<bus::LogEvent> log;
  log.push_back({1'000'000, "OBSTACLE_PREDICTIONS", {1, 2, 3}});
  log.push_back({1'010'000, "PLAN", {4, 5, 6, 7, 8, 9, 10, 11, 12}});
  log.push_back({1'010'100, "CMD_VEL", {}});
  PlanLatency r = plan_latency(log);
  EXPECT_EQ(r.lists, 0);
  EXPECT_TRUE(r.latency_ms.empty());
  EXPECT_EQ(r.percentile_ms(0.99), 0.0);
  r = plan_latency({});
  EXPECT_EQ(r.lists, 0);
}

}  // namespace
}  // namespace evade::metrics
