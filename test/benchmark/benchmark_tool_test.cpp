// tools/benchmark end to end with test doubles for run_scenario and
// scenario-gen (test/benchmark/fake_*): the job list, GNU parallel on this
// machine and over "ssh" to two hosts (fake_ssh runs each host in its own
// directory, so parallel's transfer, return and cleanup run as for real
// hosts), the rows, the kept and pruned files and the summary.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "benchmark/episode_row.h"

namespace evade::benchmark {
namespace {

namespace fs = std::filesystem;
const std::string kRoot = EVADE_SOURCE_DIR;
const std::string kFakes = " --run-scenario " + kRoot + "/test/benchmark/fake_run_scenario --scenario-gen " + kRoot +
                           "/test/benchmark/fake_scenario_gen";

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Runs cmd; its output goes to a file that is printed when the exit code is
// not 0 or 2 (the codes the tests expect), so a failure explains itself.
int run(const std::string& cmd) {
  fs::path log = fs::path(::testing::TempDir()) / ("benchmark_tool_output_" + std::to_string(::getpid()));
  int status = std::system((cmd + " > " + log.string() + " 2>&1").c_str());
  int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code != 0 && code != 2) std::cerr << "exit " << code << " from: " << cmd << "\n" << slurp(log);
  fs::remove(log);
  return code;
}

fs::path fresh_dir(const std::string& name) {
  fs::path d = fs::path(::testing::TempDir()) / ("benchmark_tool_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string benchmark(const fs::path& out, const std::string& args) {
  return kRoot + "/tools/benchmark --out " + out.string() + " " + args + kFakes;
}

// The fake's rule: (seed + length of mode) % 4 == 0 collides at fault, 1 times out.
bool fake_success(int64_t seed, const std::string& mode) { return (seed + mode.size()) % 4 > 1; }

TEST(BenchmarkTool, RunsEveryEpisodeAndKeepsOnlyFailedLogs) {
  fs::path out = fresh_dir("local");
  ASSERT_EQ(run(benchmark(out, "--families crossing,headon --episodes 3 --modes evade,mpc --seed-base 5 --jobs 2")), 0);
  auto rows = read_results((out / "results.jsonl").string());
  ASSERT_EQ(rows.size(), 12u);
  // In the order of the jobs: family, then seed, then mode.
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].id.family, i < 6 ? "crossing" : "headon") << i;
    EXPECT_EQ(rows[i].id.seed, static_cast<int64_t>(5 + (i % 6) / 2)) << i;
    EXPECT_EQ(rows[i].id.mode, i % 2 == 0 ? "evade" : "mpc") << i;
  }
  std::set<std::string> seen;
  std::map<std::pair<std::string, int64_t>, std::set<std::string>> hashes;
  for (const Episode& e : rows) {
    SCOPED_TRACE(e.id.family + " " + std::to_string(e.id.seed) + " " + e.id.mode);
    EXPECT_TRUE(seen.insert(e.id.family + std::to_string(e.id.seed) + e.id.mode).second);
    EXPECT_GE(e.id.seed, 5);
    EXPECT_LE(e.id.seed, 7);
    EXPECT_TRUE(e.error.empty());
    EXPECT_EQ(e.success, fake_success(e.id.seed, e.id.mode));
    EXPECT_EQ(e.id.exit_code, e.success ? 0 : 1);
    EXPECT_EQ(e.id.host, ":");
    hashes[{e.id.family, e.id.seed}].insert(e.id.scenario_sha256);
    fs::path dir = out / e.id.dir;
    std::string args = slurp(dir / "run/args.txt");
    EXPECT_NE(args.find("--seed " + std::to_string(e.id.seed) + " --mode " + e.id.mode), std::string::npos) << args;
    EXPECT_TRUE(fs::exists(dir / "run/metrics.json"));
    EXPECT_TRUE(fs::exists(dir / "scenario.yaml"));
    if (e.success) {
      EXPECT_EQ(e.id.dir, "episodes/" + e.id.family + "/" + e.id.mode + "/" + std::to_string(e.id.seed));
      EXPECT_FALSE(fs::exists(dir / "run/run.lcmlog"));
      EXPECT_FALSE(fs::exists(dir / "run/logs"));
    } else {
      EXPECT_EQ(e.id.dir, "failed/" + e.id.family + "/" + e.id.mode + "/" + std::to_string(e.id.seed));
      EXPECT_EQ(fs::file_size(dir / "run/run.lcmlog"), 1000u);
      EXPECT_TRUE(fs::exists(dir / "run/logs/planner.log"));
      std::string replay = slurp(dir / "REPLAY");
      EXPECT_NE(replay.find("tools/run_scenario " + (out / e.id.dir).string() + "/scenario.yaml"), std::string::npos)
          << replay;
      EXPECT_NE(replay.find("--lockstep --seed " + std::to_string(e.id.seed) + " --mode " + e.id.mode),
                std::string::npos)
          << replay;
      EXPECT_FALSE(fs::exists(dir / "FAILED"));
    }
  }
  // Paired: one scenario per family and seed whatever the mode; seeds differ.
  std::set<std::string> all;
  for (const auto& [key, h] : hashes) {
    EXPECT_EQ(h.size(), 1u) << key.first << " " << key.second;
    all.insert(*h.begin());
  }
  EXPECT_EQ(all.size(), 6u);

  auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  ASSERT_EQ(summary["groups"].size(), 6u);  // 2 families x 2 modes + all x 2 modes
  int successes = 0;
  for (const Episode& e : rows) successes += e.success;
  EXPECT_EQ(summary["groups"][4]["successes"].get<int>() + summary["groups"][5]["successes"].get<int>(), successes);
  EXPECT_GT(fs::file_size(out / "summary.png"), 1000u);
  EXPECT_NE(slurp(out / "summary.md").find("| crossing | evade | 3 |"), std::string::npos);
  EXPECT_NE(slurp(out / "command.txt").find("commit: "), std::string::npos);
}

std::string output_of(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

// metrics --stats: Table I over the rows, mean ± sd per mode beside the paper.
TEST(BenchmarkTool, MetricsStatsOverTheRows) {
  fs::path out = fresh_dir("stats");
  // Seeds 1..4, mode mpc (length 3): seed 1 collides at fault, 2 times out.
  ASSERT_EQ(run(benchmark(out, "--families crossing --episodes 4 --modes mpc,dcbf")), 0);
  std::string table = output_of(kRoot + "/build/bin/metrics --stats " + (out / "results.jsonl").string());
  std::istringstream lines(table);
  std::string line, mpc, dcbf;
  while (std::getline(lines, line)) {
    if (line.rfind("MPC ", 0) == 0) mpc = line;
    if (line.find("/ 0.828") != std::string::npos) dcbf = line;  // the paper's MPC-D-CBF min dist
  }
  // min dist: 1.25, 2.25, 3.25, 4.25 -> 2.750 ± 1.291; time over the 3 that
  // reached the goal: 21.5, 23.5, 24.5 -> 23.17 ± 1.53; 3 reached, 1 at fault.
  EXPECT_NE(mpc.find("| 4    | 2.750 ± 1.291 / 0 (collided)"), std::string::npos) << table;
  EXPECT_NE(mpc.find("23.17 ± 1.53 / -"), std::string::npos) << table;
  EXPECT_NE(mpc.find("| 3/4       | 1 / 0"), std::string::npos) << table;
  // dcbf (length 4): seed 4 collides at fault, seed 1 times out.
  EXPECT_NE(dcbf.find("| 4    | 2.750 ± 1.291 / 0.828"), std::string::npos) << table;
  EXPECT_NE(dcbf.find("| 3/4       | 1 / 0"), std::string::npos) << table;
}

TEST(BenchmarkTool, FailOnAtFaultAndErrors) {
  fs::path out = fresh_dir("fail");
  // Seeds 1..2 with mode "mpc" (length 3): seed 1 collides at fault.
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 2 --modes mpc")), 0);
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 2 --modes mpc --fail-on-at-fault --force")), 1);
  // Seed 2 alone: no collision at fault.
  EXPECT_EQ(
      run(benchmark(out, "--families crossing --episodes 1 --seed-base 2 --modes mpc --fail-on-at-fault --force")), 0);
  // An episode without metrics is an error row, kept, and the exit is 1.
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 1 --modes crash,mpc --force")), 1);
  auto rows = read_results((out / "results.jsonl").string());
  ASSERT_EQ(rows.size(), 2u);
  const Episode& crash = rows[0].id.mode == "crash" ? rows[0] : rows[1];
  EXPECT_NE(crash.error.find("run_scenario exit 2"), std::string::npos) << crash.error;
  EXPECT_TRUE(fs::exists(out / crash.id.dir / "run_scenario.out"));
  EXPECT_EQ(run(benchmark(out, "--families broken --episodes 1 --force")), 1);
  rows = read_results((out / "results.jsonl").string());
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NE(rows[0].error.find("scenario-gen"), std::string::npos) << rows[0].error;
}

TEST(BenchmarkTool, UsageErrors) {
  fs::path out = fresh_dir("usage");
  EXPECT_EQ(run(benchmark(out, "--families crossing")), 2);  // no --episodes
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 0")), 2);
  EXPECT_EQ(run(benchmark(out, "--families 'a b' --episodes 1")), 2);
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 1 --config /nonexistent.yaml")), 2);
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 1 --bogus")), 2);
  ASSERT_EQ(run(benchmark(out, "--families crossing --episodes 1")), 0);
  EXPECT_EQ(run(benchmark(out, "--families crossing --episodes 1")), 2);  // results.jsonl exists
  EXPECT_EQ(read_results((out / "results.jsonl").string()).size(), 1u);   // and is left alone
}

TEST(BenchmarkTool, FixedScenarioRunsTheSameFileForEverySeed) {
  fs::path out = fresh_dir("scenario");
  fs::path scenario = out.parent_path() / "benchmark_tool_paper.yaml";
  std::ofstream(scenario) << "name: paper\n";
  ASSERT_EQ(run(benchmark(out, "--scenario " + scenario.string() + " --episodes 3 --modes evade --keep-logs")), 0);
  auto rows = read_results((out / "results.jsonl").string());
  ASSERT_EQ(rows.size(), 3u);
  for (const Episode& e : rows) {
    EXPECT_EQ(e.id.family, "benchmark_tool_paper");
    EXPECT_EQ(e.id.scenario_sha256, rows[0].id.scenario_sha256);
    EXPECT_TRUE(fs::exists(out / e.id.dir / "run/run.lcmlog"));  // --keep-logs
  }
}

// Two "hosts" through GNU parallel's ssh path: the jobs run in
// FAKE_SSH_ROOT/hostA and hostB, the config goes there as a basefile and the
// episodes' folders come back by rsync.
TEST(BenchmarkTool, TwoHostsOverSsh) {
  fs::path out = fresh_dir("hosts");
  fs::path hosts = fresh_dir("hosts_root");
  // Without SHELL (as under some CI runners), which GNU parallel would
  // otherwise use to run the remote jobs.
  std::string env = "env -u SHELL FAKE_SSH_ROOT=" + hosts.string() + " ";
  ASSERT_EQ(run(env + benchmark(out,
                                "--families crossing,headon --episodes 3 --modes evade,mpc --seed-base 5 "
                                "--hosts 1/hostA,1/hostB --ssh " +
                                    kRoot + "/test/benchmark/fake_ssh")),
            0);
  auto rows = read_results((out / "results.jsonl").string());
  ASSERT_EQ(rows.size(), 12u);
  std::map<std::string, int> per_host;
  for (const Episode& e : rows) {
    SCOPED_TRACE(e.id.dir);
    ++per_host[e.id.host];
    EXPECT_EQ(e.success, fake_success(e.id.seed, e.id.mode));
    std::string where = slurp(out / e.id.dir / "run/where.txt");  // returned from the host
    EXPECT_EQ(where.rfind((hosts / e.id.host).string() + "/.evade-benchmark/", 0), 0u) << where;
    EXPECT_NE(slurp(out / e.id.dir / "run/args.txt").find("--config robot.yaml"), std::string::npos);
    if (!e.success) {
      EXPECT_EQ(fs::file_size(out / e.id.dir / "run/run.lcmlog"), 1000u);
    }
  }
  EXPECT_EQ(per_host.size(), 2u);
  EXPECT_GT(per_host["hostA"], 0);
  EXPECT_GT(per_host["hostB"], 0);
  // The hosts keep nothing of the run.
  for (const char* h : {"hostA", "hostB"}) EXPECT_FALSE(fs::exists(hosts / h / ".evade-benchmark")) << h;

  // The same rows as on this machine, apart from where and how long.
  fs::path local = fresh_dir("hosts_local");
  ASSERT_EQ(run(benchmark(local, "--families crossing,headon --episodes 3 --modes evade,mpc --seed-base 5")), 0);
  auto strip = [](const fs::path& p) {
    std::set<std::string> s;
    std::ifstream f(p);
    for (std::string line; std::getline(f, line);) {
      auto j = nlohmann::json::parse(line);
      j.erase("host");
      j.erase("wall_s");
      s.insert(j.dump());
    }
    return s;
  };
  EXPECT_EQ(strip(out / "results.jsonl"), strip(local / "results.jsonl"));
}

}  // namespace
}  // namespace evade::benchmark
