#include "soak/live_report.h"

#include <gtest/gtest.h>

namespace evade::soak {
namespace {

LiveFiles files(int at_fault, const std::string& planner_status) {
  LiveFiles f;
  f.exit_status_tsv = "# process exit_status exited_early\nsim 0 yes\nplanner " + planner_status + " no\n";
  f.rss_tsv = "0 11 1000 1\n100 11 1000 1\n0 12 2000 1\n100 12 3024 1\n";
  f.pids_tsv = "# pid name\n11 sim\n12 planner\n";
  f.metrics_json = R"({"collisions_at_fault": )" + std::to_string(at_fault) +
                   R"(, "collisions_not_at_fault": 1, "reached_goal": false, "min_dist_m": 0.5, "duration_s": 300})";
  f.netem_json = R"({"loss": 0.05, "delay_s": 0.02, "jitter_s": 0.02, "reorder": true, "channels": {
      "ODOMETRY": {"packets": 100, "packets_dropped": 5, "messages": 100, "messages_lost": 5, "mean_delay_ms": 20,
                   "exempt": false},
      "SIM_TRUTH": {"packets": 10, "packets_dropped": 0, "messages": 10, "messages_lost": 0, "mean_delay_ms": 0,
                    "exempt": true}}})";
  f.health_jsonl = R"({"channel":"HEALTH","msg":{"name":"planner","inputs":[{"channel":"ODOMETRY","received":50}]}})"
                   "\n"
                   R"({"channel":"HEALTH","msg":{"name":"planner","inputs":[{"channel":"ODOMETRY","received":94}]}})"
                   "\n";
  return f;
}

TEST(LiveReport, ACrashIsAnExitOtherThanZeroOrTheEndsSigterm) {
  EXPECT_FALSE(is_crash({"sim", 0, true}));
  EXPECT_FALSE(is_crash({"planner", 143, false}));
  EXPECT_TRUE(is_crash({"planner", 139, true}));
  EXPECT_TRUE(is_crash({"planner", 137, false}));
  EXPECT_TRUE(is_crash({"planner", -1, false}));
  EXPECT_EQ(parse_exits("a unknown no\n").at(0).status, -1);
  EXPECT_THROW(parse_exits("planner 0 maybe\n"), std::runtime_error);
}

TEST(LiveReport, PassesACleanRunAndCountsWhatTheBusLost) {
  const auto r = make_live_report(files(0, "143"), 50);
  EXPECT_TRUE(r.failures.empty()) << r.failures.front();
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_EQ(r.channels[0].channel, "ODOMETRY");
  EXPECT_EQ(r.channels[0].sent, 100);
  EXPECT_EQ(r.channels[0].dropped, 5);
  EXPECT_EQ(r.channels[0].received.at("planner"), 94);  // the last HEALTH
  EXPECT_TRUE(r.channels[1].exempt);
  ASSERT_EQ(r.rss.size(), 2u);
  EXPECT_EQ(r.rss[1].first, "planner");
  EXPECT_NEAR(r.rss[1].second.end_mib, 3024 / 1024.0, 1e-9);
  EXPECT_NE(live_report_text(r).find("planner got 94 (94.0 %)"), std::string::npos) << live_report_text(r);
}

TEST(LiveReport, FailsOnACrashOrACollisionAtFault) {
  auto r = make_live_report(files(0, "139"), 50);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("planner ended with exit status 139"), std::string::npos) << r.failures[0];
  r = make_live_report(files(2, "0"), 50);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("2 collision(s) at fault"), std::string::npos);
  auto bad = files(0, "0");
  bad.metrics_json = "{}";
  EXPECT_THROW(make_live_report(bad, 50), std::runtime_error);
}

}  // namespace
}  // namespace evade::soak
