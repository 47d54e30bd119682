#include "benchmark/benchmark_summary.h"

#include <cairo.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "benchmark/episode_row.h"
#include "benchmark/summary_plot.h"

namespace evade::benchmark {
namespace {

// Newcombe (1998), "Two-sided confidence intervals for the single
// proportion", Table I, method 3 (Wilson score, no continuity correction).
TEST(Wilson, PublishedValues) {
  struct Case {
    int k, n;
    double lo, hi;
  } cases[] = {{81, 263, 0.2553, 0.3662}, {15, 148, 0.0624, 0.1605}, {0, 20, 0.0, 0.1611}, {1, 29, 0.0061, 0.1718}};
  for (const auto& c : cases) {
    Interval i = wilson_interval(c.k, c.n);
    EXPECT_NEAR(i.lo, c.lo, 5e-5) << c.k << "/" << c.n;
    EXPECT_NEAR(i.hi, c.hi, 5e-5) << c.k << "/" << c.n;
  }
}

TEST(Wilson, SymmetricAndBounded) {
  Interval half = wilson_interval(5, 10);
  EXPECT_NEAR(half.lo + half.hi, 1.0, 1e-12);  // centred on 1/2
  EXPECT_NEAR(half.lo, 0.2366, 5e-5);
  Interval all = wilson_interval(10, 10), none = wilson_interval(0, 10);
  EXPECT_DOUBLE_EQ(all.hi, 1.0);
  EXPECT_NEAR(all.lo, 1.0 - none.hi, 1e-12);
  EXPECT_NEAR(none.hi, 0.2775, 5e-5);
  Interval empty = wilson_interval(0, 0);
  EXPECT_EQ(empty.lo, 0.0);
  EXPECT_EQ(empty.hi, 1.0);
  EXPECT_THROW(wilson_interval(3, 2), std::invalid_argument);
  EXPECT_THROW(wilson_interval(-1, 2), std::invalid_argument);
}

TEST(Percentile, LinearBetweenClosestRanks) {
  std::vector<double> v{5, 1, 4, 2, 3};  // sorted 1..5
  EXPECT_DOUBLE_EQ(percentile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.5), 3.0);
  EXPECT_DOUBLE_EQ(percentile(v, 1.0), 5.0);
  EXPECT_DOUBLE_EQ(percentile(v, 0.05), 1.2);  // position 0.2
  EXPECT_DOUBLE_EQ(percentile({1, 2}, 0.5), 1.5);
  EXPECT_DOUBLE_EQ(percentile({7}, 0.05), 7.0);
  EXPECT_THROW(percentile({}, 0.5), std::invalid_argument);
  EXPECT_THROW(percentile({1}, 1.5), std::invalid_argument);
}

TEST(MeanSd, SampleStandardDeviation) {
  auto s = mean_sd({2, 4, 4, 4, 5, 5, 7, 9});
  ASSERT_TRUE(s);
  EXPECT_EQ(s->n, 8);
  EXPECT_DOUBLE_EQ(s->mean, 5.0);
  EXPECT_NEAR(s->sd, std::sqrt(32.0 / 7.0), 1e-12);
  EXPECT_DOUBLE_EQ(mean_sd({3})->sd, 0.0);
  EXPECT_FALSE(mean_sd({}));
}

// A metrics.json as the metrics tool writes it (SPEC "Metrics").
std::string metrics(bool success, bool at_fault, int not_at_fault, bool timed_out, double min_dist,
                    const char* time = "20.0") {
  char b[1024];
  std::snprintf(b, sizeof b,
                R"({"scenario": "s", "mode": "m", "success": %s, "reached_goal": %s, "collided": %s,
                    "at_fault": %s, "collisions_at_fault": %d, "collisions_not_at_fault": %d,
                    "timed_out": %s, "contacts": [], "min_dist_m": %.3f, "time_to_goal_s": %s,
                    "reaction_time_s": 0.4, "speed_var": 0.02, "planner_cycle_ms_p99": 15.0})",
                success ? "true" : "false", timed_out ? "false" : "true", (at_fault || not_at_fault) ? "true" : "false",
                at_fault ? "true" : "false", at_fault ? 1 : 0, not_at_fault, timed_out ? "true" : "false", min_dist,
                timed_out ? "null" : time);
  return b;
}

EpisodeId id(const std::string& family, int seed, const std::string& mode, const std::string& sha = "") {
  EpisodeId i;
  i.family = family;
  i.seed = seed;
  i.mode = mode;
  i.scenario_sha256 = sha.empty() ? family + std::to_string(seed) : sha;
  return i;
}

TEST(Row, CarriesTheContractKeysAndRoundTrips) {
  std::string row = make_row(id("crossing", 7, "evade"), metrics(false, true, 0, false, -0.12));
  EXPECT_EQ(row.find('\n'), std::string::npos);  // one line
  auto j = nlohmann::json::parse(row);
  for (const char* k : {"family", "seed", "mode", "reached_goal", "collided", "at_fault", "min_dist_m",
                        "time_to_goal_s", "planner_cycle_ms_p99", "success", "timed_out", "collisions_at_fault",
                        "collisions_not_at_fault", "scenario_sha256"})
    EXPECT_TRUE(j.contains(k)) << k;
  Episode e = parse_row(row);
  EXPECT_EQ(e.id.family, "crossing");
  EXPECT_EQ(e.id.seed, 7);
  EXPECT_EQ(e.id.mode, "evade");
  EXPECT_FALSE(e.success);
  EXPECT_TRUE(e.at_fault);
  EXPECT_EQ(e.collisions_at_fault, 1);
  EXPECT_DOUBLE_EQ(*e.min_dist_m, -0.12);
  EXPECT_DOUBLE_EQ(*e.time_to_goal_s, 20.0);
  EXPECT_DOUBLE_EQ(*e.reaction_time_s, 0.4);
}

TEST(Row, MissingOrMistypedMetricsKeyIsNamed) {
  std::string m = metrics(true, false, 0, false, 0.5);
  auto j = nlohmann::json::parse(m);
  j.erase("at_fault");
  try {
    make_row(id("f", 1, "m"), j.dump());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("at_fault"), std::string::npos) << e.what();
  }
  j = nlohmann::json::parse(m);
  j["collisions_not_at_fault"] = "2";
  EXPECT_THROW(make_row(id("f", 1, "m"), j.dump()), std::runtime_error);
  EXPECT_THROW(make_row(id("f", 1, "m"), "{not json"), std::runtime_error);
  EXPECT_THROW(parse_row(R"({"family": "f", "mode": "m"})"), std::runtime_error);  // no seed
}

// A perception-metrics JSON with the given counts (two horizon steps of 1.25 s).
std::string perception(int objects, int misses, int fp, int switches, double track_s, double ade, int predictions,
                       int inside1, int n1) {
  char b[1024];
  std::snprintf(
      b, sizeof b,
      R"({"objects": %d, "matches": %d, "misses": %d, "false_positives": %d, "splits": 1, "merges": 2, "id_switches": %d,
                    "fragmentations": 1, "mota": 0.5, "motp_m": 0.2, "track_s": %.1f, "predictions": %d,
                    "ade_1s_m": %.2f, "fde_2_5s_m": 1.0, "walker_ade_1s_m": null, "walker_predictions": 0,
                    "step_dt_s": 1.25, "coverage_inside": [%d, %d, 0], "coverage_n": [%d, %d, 0]})",
      objects, objects - misses, misses, fp, switches, track_s, predictions, ade, n1, inside1, n1, n1);
  return b;
}

TEST(Row, PerceptionCountsArePooledPerGroup) {
  const std::string m = metrics(true, false, 0, false, 0.5);
  Episode a = parse_row(make_row(id("crowd", 1, "evade"), m, perception(100, 10, 5, 1, 50.0, 0.2, 30, 9, 10)));
  Episode b = parse_row(make_row(id("crowd", 2, "evade"), m, perception(300, 0, 5, 3, 150.0, 0.4, 10, 5, 10)));
  Episode c = parse_row(make_row(id("crowd", 3, "evade"), m));  // without perception
  ASSERT_TRUE(a.perception && b.perception);
  EXPECT_FALSE(c.perception);
  EXPECT_EQ(a.perception->objects, 100);
  EXPECT_DOUBLE_EQ(a.perception->centre_error_sum_m, 0.2 * 90);
  auto pool = pool_perception({&a, &b, &c});
  ASSERT_TRUE(pool);
  EXPECT_EQ(pool->episodes, 2);
  EXPECT_DOUBLE_EQ(pool->mota(), 1.0 - (10.0 + 10.0 + 4.0) / 400.0);
  EXPECT_EQ(pool->sum.splits, 2);
  EXPECT_EQ(pool->sum.merges, 4);
  EXPECT_DOUBLE_EQ(*pool->id_switches_per_100_track_s(), 100.0 * 4.0 / 200.0);
  EXPECT_DOUBLE_EQ(*pool->sum.ade_1s_m, (0.2 * 30 + 0.4 * 10) / 40.0);  // weighted by predictions
  EXPECT_DOUBLE_EQ(*pool->coverage_min(2.5), 14.0 / 20.0);              // step 1 (1.25 s); step 2 has none
  const std::string md = perception_markdown_table(summarize({a, b, c}));
  EXPECT_NE(md.find("| crowd | evade | 2 | 0.940 |"), std::string::npos) << md;
  EXPECT_TRUE(perception_markdown_table(summarize({c})).empty());
  // A perception JSON without a key is named.
  EXPECT_THROW(make_row(id("crowd", 4, "evade"), m, R"({"objects": 1})"), std::runtime_error);
}

// Static structure's false motion pools from the counts; rows from before
// these keys carry none and count nothing.
TEST(Row, StaticMotionIsPooledAndOptional) {
  const std::string m = metrics(true, false, 0, false, 0.5);
  auto with_static = [](int frames, int moving, double speed) {
    nlohmann::json j = nlohmann::json::parse(perception(10, 0, 0, 0, 1.0, 0.2, 3, 1, 1));
    j["static_track_frames"] = frames;
    j["static_moving_frames"] = moving;
    j["static_speed_mean_mps"] = speed;
    return j.dump();
  };
  Episode a = parse_row(make_row(id("doorway", 1, "evade"), m, with_static(100, 10, 0.1)));
  Episode b = parse_row(make_row(id("doorway", 2, "evade"), m, with_static(300, 0, 0.02)));
  Episode c = parse_row(make_row(id("doorway", 3, "evade"), m, perception(10, 0, 0, 0, 1.0, 0.2, 3, 1, 1)));
  EXPECT_EQ(c.perception->static_track_frames, 0);
  auto pool = pool_perception({&a, &b, &c});
  ASSERT_TRUE(pool);
  EXPECT_DOUBLE_EQ(*pool->static_moving_fraction(), 10.0 / 400.0);
  EXPECT_NEAR(*pool->static_speed_mean_mps(), (100 * 0.1 + 300 * 0.02) / 400.0, 1e-12);
  EXPECT_FALSE(pool_perception({&c})->static_moving_fraction());
}

TEST(Row, ErrorRowsCountAsErrorsNotEpisodes) {
  std::vector<Episode> rows{parse_row(make_row(id("f", 1, "m"), metrics(true, false, 0, false, 0.5))),
                            parse_row(make_error_row(id("f", 2, "m"), "run_scenario exit 2"))};
  EXPECT_EQ(rows[1].error, "run_scenario exit 2");
  auto g = summarize(rows);
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g[0].episodes, 1);
  EXPECT_EQ(g[0].errors, 1);
  EXPECT_EQ(g[0].successes, 1);
}

std::vector<Episode> synthetic_rows() {
  // crossing x {evade, mpc} x seeds 1..4, headon x evade x seeds 1..2.
  std::vector<Episode> rows;
  auto add = [&](const std::string& f, int seed, const std::string& mode, const std::string& m) {
    rows.push_back(parse_row(make_row(id(f, seed, mode), m)));
  };
  add("crossing", 1, "evade", metrics(true, false, 0, false, 0.40, "20.0"));
  add("crossing", 1, "mpc", metrics(false, true, 0, false, -0.10));
  add("crossing", 2, "evade", metrics(true, false, 1, false, 0.30, "24.0"));  // hit while standing: still success
  add("crossing", 2, "mpc", metrics(true, false, 0, false, 0.10, "30.0"));
  add("crossing", 3, "evade", metrics(false, false, 0, true, 0.10));
  add("crossing", 3, "mpc", metrics(false, true, 0, false, -0.20));
  add("crossing", 4, "evade", metrics(true, false, 0, false, 0.50, "22.0"));
  add("crossing", 4, "mpc", metrics(true, false, 0, false, 0.60, "26.0"));
  add("headon", 1, "evade", metrics(true, false, 0, false, 0.90, "18.0"));
  add("headon", 2, "evade", metrics(false, true, 1, false, -0.05));
  return rows;
}

TEST(Summary, GroupsByFamilyAndModeThenAll) {
  auto g = summarize(synthetic_rows());
  ASSERT_EQ(g.size(), 5u);
  EXPECT_EQ(g[0].family + "/" + g[0].mode, "crossing/evade");
  EXPECT_EQ(g[1].family + "/" + g[1].mode, "crossing/mpc");
  EXPECT_EQ(g[2].family + "/" + g[2].mode, "headon/evade");
  EXPECT_EQ(g[3].family + "/" + g[3].mode, "all/evade");
  EXPECT_EQ(g[4].family + "/" + g[4].mode, "all/mpc");

  const GroupSummary& ce = g[0];
  EXPECT_EQ(ce.episodes, 4);
  EXPECT_EQ(ce.successes, 3);
  EXPECT_NEAR(ce.success_ci.lo, wilson_interval(3, 4).lo, 1e-12);
  EXPECT_EQ(ce.at_fault, 0);
  EXPECT_EQ(ce.not_at_fault, 1);
  EXPECT_EQ(ce.timeouts, 1);
  EXPECT_NEAR(*ce.min_dist_p50_m, 0.35, 1e-12);             // 0.1 0.3 | 0.4 0.5
  EXPECT_NEAR(*ce.min_dist_p5_m, 0.1 + 0.15 * 0.2, 1e-12);  // position 0.15
  EXPECT_NEAR(*ce.mean_time_to_goal_s, 22.0, 1e-12);        // 20, 24, 22 (the timeout has none)
  EXPECT_DOUBLE_EQ(*ce.planner_cycle_ms_p99_max, 15.0);

  const GroupSummary& cm = g[1];
  EXPECT_EQ(cm.successes, 2);
  EXPECT_EQ(cm.at_fault, 2);
  EXPECT_EQ(cm.contacts_at_fault, 2);
  EXPECT_NEAR(*cm.mean_time_to_goal_s, (20.0 + 30.0 + 20.0 + 26.0) / 4, 1e-12);  // collided runs reached the goal

  const GroupSummary& all_evade = g[3];
  EXPECT_EQ(all_evade.episodes, 6);
  EXPECT_EQ(all_evade.successes, 4);
  EXPECT_EQ(all_evade.at_fault, 1);
  EXPECT_EQ(all_evade.not_at_fault, 2);
}

TEST(Summary, OneFamilyHasNoAllGroup) {
  auto rows = synthetic_rows();
  rows.resize(8);
  EXPECT_EQ(summarize(rows).size(), 2u);
}

TEST(Summary, RejectsDuplicatesAndUnpairedScenarios) {
  auto rows = synthetic_rows();
  EXPECT_NO_THROW(check_rows(rows));
  auto dup = rows;
  dup.push_back(rows[0]);
  EXPECT_THROW(check_rows(dup), std::runtime_error);
  auto unpaired = rows;
  unpaired[1].id.scenario_sha256 = "another";
  try {
    check_rows(unpaired);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not paired"), std::string::npos) << e.what();
  }
}

TEST(Summary, JsonAndMarkdownCarryTheFigures) {
  auto g = summarize(synthetic_rows());
  auto j = nlohmann::json::parse(summary_json(g));
  ASSERT_EQ(j["groups"].size(), 5u);
  const auto& ce = j["groups"][0];
  EXPECT_EQ(ce["successes"], 3);
  EXPECT_DOUBLE_EQ(ce["success_rate"].get<double>(), 0.75);
  EXPECT_NEAR(ce["success_ci95"][0].get<double>(), wilson_interval(3, 4).lo, 1e-12);
  EXPECT_DOUBLE_EQ(j["groups"][1]["at_fault_rate"].get<double>(), 0.5);
  std::string md = markdown_table(g);
  EXPECT_NE(md.find("| crossing | evade | 4 | 75 % (30-95 %) | 0 (0 %) | 1 (25 %) | 1 (25 %) | 0.13 / 0.35 | 22.0 |"),
            std::string::npos)
      << md;
}

TEST(Summary, ModeStatsForTableOne) {
  auto s = mode_stats(synthetic_rows());
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].mode, "evade");
  EXPECT_EQ(s[0].runs, 6);
  EXPECT_EQ(s[0].runs_at_fault, 1);
  EXPECT_EQ(s[0].runs_not_at_fault, 2);
  ASSERT_TRUE(s[1].min_dist_m);
  EXPECT_NEAR(s[1].min_dist_m->mean, (-0.1 + 0.1 - 0.2 + 0.6) / 4, 1e-12);
  EXPECT_EQ(s[1].time_to_goal_s->n, 4);
  EXPECT_DOUBLE_EQ(s[1].reaction_time_s->sd, 0.0);
}

TEST(Summary, ReadResultsNamesTheBadLine) {
  std::string path = ::testing::TempDir() + "/results.jsonl";
  {
    std::ofstream f(path);
    f << make_row(id("f", 1, "m"), metrics(true, false, 0, false, 0.5)) << "\n\n{\"family\": 3}\n";
  }
  try {
    read_results(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("results.jsonl:3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_results(path + ".missing"), std::runtime_error);
}

TEST(SummaryPlot, OnePanelPerFamily) {
  std::string path = ::testing::TempDir() + "/summary.png";
  std::remove(path.c_str());
  plot_summary(summarize(synthetic_rows()), path);  // three panels: crossing, headon, all
  cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(s), 3 * 480);
  cairo_surface_destroy(s);
  auto one = synthetic_rows();
  one.resize(8);
  plot_summary(summarize(one), path);
  s = cairo_image_surface_create_from_png(path.c_str());
  EXPECT_EQ(cairo_image_surface_get_width(s), 480);
  cairo_surface_destroy(s);
  EXPECT_THROW(plot_summary({}, path), std::runtime_error);
  EXPECT_THROW(plot_summary(summarize(one), "/nonexistent/dir/x.png"), std::runtime_error);
}

}  // namespace
}  // namespace evade::benchmark
