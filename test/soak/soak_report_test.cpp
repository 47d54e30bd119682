#include "soak/soak_report.h"

#include <gtest/gtest.h>

namespace evade::soak {
namespace {

EpisodeLine episode(uint64_t seed, double t_s, double rss_kib, int at_fault = 0) {
  EpisodeLine e;
  e.result.family = "mixed";
  e.result.seed = seed;
  e.result.outcome = "goal";
  e.result.sim_s = 30;
  e.result.reached_goal = true;
  e.result.success = at_fault == 0;
  e.result.collisions_at_fault = at_fault;
  e.wall_s = 10;
  e.pid = 7;
  e.t_s = t_s;
  e.rss_kib = rss_kib;
  return e;
}

std::vector<RssSample> flat_samples() { return {{0, 7, 20000, 1.0}, {500, 7, 30000, 3.0}}; }

TEST(SoakReport, EpisodeLinesRoundTrip) {
  EpisodeLine e = episode(12, 300.5, 23456, 2);
  e.result.min_dist_m = -0.25;
  EpisodeLine err = episode(13, 400, 23456);
  err.error = "solver exploded";
  const auto back = parse_episode_lines(episode_line_json(e) + "\n" + episode_line_json(err) + "\n");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].result.seed, 12u);
  EXPECT_EQ(back[0].result.collisions_at_fault, 2);
  EXPECT_DOUBLE_EQ(back[0].result.min_dist_m, -0.25);
  EXPECT_EQ(back[0].pid, 7);
  EXPECT_DOUBLE_EQ(back[0].t_s, 300.5);
  EXPECT_EQ(back[1].error, "solver exploded");
  EXPECT_THROW(parse_episode_lines("{\"family\":\"mixed\"}\n"), std::runtime_error);
  EXPECT_THROW(parse_episode_lines(episode_line_json(e) + "\nnot json\n"), std::runtime_error);
}

TEST(SoakReport, PassesWithoutCrashCollisionOrGrowth) {
  std::vector<EpisodeLine> eps;
  for (int i = 0; i < 10; ++i) eps.push_back(episode(i + 1, 100.0 * (i + 1), 20000));
  const auto r = make_report(eps, {}, flat_samples(), {16.0, 120.0});
  EXPECT_TRUE(r.failures.empty()) << r.failures.front();
  EXPECT_EQ(r.episodes, 10);
  EXPECT_EQ(r.goal, 10);
  EXPECT_EQ(r.first_seed, 1u);
  EXPECT_EQ(r.last_seed, 10u);
  ASSERT_EQ(r.settled.size(), 1u);
  EXPECT_NEAR(*r.settled[0].growth_mib_per_h, 0.0, 1e-9);
  ASSERT_EQ(r.rss.size(), 1u);
  EXPECT_NEAR(r.rss[0].max_mib, 30000 / 1024.0, 1e-9);
  EXPECT_DOUBLE_EQ(*r.load1_mean, 2.0);
  EXPECT_NE(report_text(r).find("verdict: PASS"), std::string::npos);
}

TEST(SoakReport, FailsOnCollisionAtFaultNamingTheSeeds) {
  std::vector<EpisodeLine> eps;
  for (int i = 0; i < 5; ++i) eps.push_back(episode(i + 1, 100.0 * (i + 1), 20000, i == 1 || i == 3));
  const auto r = make_report(eps, {}, flat_samples(), {16.0, 0.0});
  EXPECT_EQ(r.at_fault_seeds, (std::vector<uint64_t>{2, 4}));
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("seeds 2, 4"), std::string::npos) << r.failures[0];
}

TEST(SoakReport, FailsOnGrowthAboveTheBoundAndOnCrashes) {
  std::vector<EpisodeLine> eps;
  // 2 MiB per 360 s = 20 MiB/h after the warm-up.
  for (int i = 0; i < 10; ++i) eps.push_back(episode(i + 1, 360.0 * (i + 1), 20000 + 2048.0 * i));
  auto r = make_report(eps, {}, flat_samples(), {16.0, 0.0});
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("20.00 MiB/h"), std::string::npos) << r.failures[0];
  r = make_report(eps, {}, flat_samples(), {25.0, 0.0});
  EXPECT_TRUE(r.failures.empty());
  r = make_report(eps, {{50.0, 4, 139}}, flat_samples(), {25.0, 0.0});
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("crash"), std::string::npos);
  EXPECT_EQ(parse_crashes("# t seed status\n50.0 4 139\n").at(0).status, 139);
  EXPECT_THROW(parse_crashes("50.0 four 139\n"), std::runtime_error);
}

TEST(SoakReport, AnEpisodeErrorIsACrashAndTooFewSamplesFail) {
  EpisodeLine err = episode(3, 10, 20000);
  err.error = "boom";
  const auto r = make_report({episode(1, 5, 20000), err}, {}, flat_samples(), {16.0, 120.0});
  EXPECT_EQ(r.episodes, 1);
  ASSERT_EQ(r.errors.size(), 1u);
  ASSERT_EQ(r.failures.size(), 2u);
  EXPECT_NE(r.failures[0].find("error"), std::string::npos);
  EXPECT_NE(r.failures[1].find("too few"), std::string::npos);
}

}  // namespace
}  // namespace evade::soak
