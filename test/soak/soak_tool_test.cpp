// tools/soak with a test double for `soak-lockstep run` that writes an
// episode line every 0.2 s (and can crash on a chosen seed, or grow), and
// the real `soak-lockstep report`.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace fs = std::filesystem;

namespace {

const std::string kRoot = EVADE_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

class SoakTool : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("soak_tool_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fake_ = dir_ / "fake-soak-lockstep";
    std::ofstream(fake_) << R"(#!/usr/bin/env bash
if [ "$1" = report ]; then shift; exec ")"
                         << kRoot << R"(/build/bin/soak-lockstep" report "$@"; fi
shift
while [ $# -gt 0 ]; do case "$1" in --out) out=$2 ;; --seed-base) seed=$2 ;; --wall-s) wall=$2 ;; esac; shift 2; done
start=$EPOCHREALTIME; rss=1000
while awk "BEGIN { exit !($EPOCHREALTIME - $start < $wall) }"; do
  echo "$seed" > "$out/current_seed"
  [ "$seed" = "${FAKE_CRASH_SEED:-}" ] && kill -SEGV $$
  t=$(awk "BEGIN { print $EPOCHREALTIME - $start }")
  echo "{\"family\":\"mixed\",\"seed\":$seed,\"wall_s\":0.2,\"pid\":$$,\"t_s\":$t,\"rss_kib\":$rss,\"outcome\":\"goal\",\"sim_s\":30,\"events\":1,\"reached_goal\":true,\"timed_out\":false,\"success\":true,\"collisions_at_fault\":0,\"collisions_not_at_fault\":0,\"min_dist_m\":0.5}" >> "$out/episodes.jsonl"
  rss=$((rss + ${FAKE_GROWTH_KIB:-0})); seed=$((seed + 1)); sleep 0.2
done
exit 0
)";
    fs::permissions(fake_, fs::perms::owner_all);
  }
  void TearDown() override { fs::remove_all(dir_); }

  int soak(const std::string& env, const std::string& args) {
    const std::string cmd = env + " " + kRoot + "/tools/soak --runner " + fake_.string() + " " + args + " > " +
                            (dir_ / "out.txt").string() + " 2>&1";
    const int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }
  std::string out() { return read(dir_ / "out.txt"); }

  fs::path dir_, fake_;
};

TEST_F(SoakTool, ACleanSoakPassesAndReportsSamplesAndEpisodes) {
  const fs::path o = dir_ / "run";
  ASSERT_EQ(soak("", "--out " + o.string() + " --duration-s 2 --warmup-s 0 --sample-s 0.2"), 0) << out();
  const auto r = nlohmann::json::parse(read(o / "report.json"));
  EXPECT_TRUE(r.at("pass").get<bool>());
  EXPECT_GE(r.at("episodes").get<int>(), 5);
  EXPECT_EQ(r.at("first_seed").get<int>(), 1);
  EXPECT_GE(r.at("rss_sampled").at(0).at("samples").get<int>(), 5);
  EXPECT_DOUBLE_EQ(r.at("rss_after_episodes").at(0).at("growth_mib_per_h").get<double>(), 0.0);
  EXPECT_NE(out().find("verdict: PASS"), std::string::npos) << out();
  EXPECT_NE(out().find("host load"), std::string::npos) << out();
}

TEST_F(SoakTool, ACrashIsCountedWithItsSeedAndTheSoakCarriesOn) {
  const fs::path o = dir_ / "run";
  ASSERT_EQ(soak("FAKE_CRASH_SEED=3", "--out " + o.string() + " --duration-s 3 --warmup-s 0 --sample-s 0.2"), 1)
      << out();
  const auto r = nlohmann::json::parse(read(o / "report.json"));
  ASSERT_EQ(r.at("crashes").size(), 1u);
  EXPECT_EQ(r.at("crashes").at(0).at("seed").get<int>(), 3);
  EXPECT_EQ(r.at("crashes").at(0).at("exit_status").get<int>(), 128 + 11);
  EXPECT_GE(r.at("last_seed").get<int>(), 5);  // carried on from seed 4
  EXPECT_EQ(r.at("rss_sampled").size(), 2u);   // two processes sampled
  EXPECT_NE(out().find("1 process crash(es)"), std::string::npos) << out();
}

TEST_F(SoakTool, GrowthAboveTheBoundFails) {
  const fs::path o = dir_ / "run";
  // 1 MiB per 0.2 s is far above 100 MiB/h.
  ASSERT_EQ(
      soak("FAKE_GROWTH_KIB=1024", "--out " + o.string() + " --duration-s 2 --warmup-s 0.5 --max-growth-mib-per-h 100"),
      1)
      << out();
  const auto r = nlohmann::json::parse(read(o / "report.json"));
  EXPECT_GT(r.at("rss_after_episodes").at(0).at("growth_mib_per_h").get<double>(), 1000.0);
  EXPECT_NE(out().find("above the bound 100.00"), std::string::npos) << out();
}

TEST_F(SoakTool, BadArgumentsAndAnEarlierSoakAreRefused) {
  const std::string o = (dir_ / "run").string();
  EXPECT_EQ(soak("", "--duration-s 2"), 2);
  EXPECT_EQ(soak("", "--out " + o + " --duration-s abc"), 2);
  EXPECT_NE(out().find("--duration-s takes a positive number"), std::string::npos) << out();
  EXPECT_EQ(soak("", "--out " + o + " --max-growth-mib-per-h -1"), 2);
  EXPECT_EQ(soak("", "--out " + o + " --bogus"), 2);
  ASSERT_EQ(soak("", "--out " + o + " --duration-s 0.5 --warmup-s 0"), 0) << out();
  const std::string before = read(dir_ / "run" / "episodes.jsonl");
  EXPECT_EQ(soak("", "--out " + o + " --duration-s 0.5"), 2);
  EXPECT_NE(out().find("not overwriting"), std::string::npos) << out();
  EXPECT_EQ(read(dir_ / "run" / "episodes.jsonl"), before);
  EXPECT_EQ(soak("", "--out " + o + " --duration-s 0.5 --warmup-s 0 --force"), 0) << out();
}

}  // namespace
