// soak-lockstep run --out DIR [--family F] [--seed-base K] [--wall-s T]
//                   [--config FILE] [--families FILE] [--mode M]
// soak-lockstep report --dir DIR [--max-growth-mib-per-h X] [--warmup-s W]
//
// run: episodes of family F (seeds K, K+1, ...) back to back in this one
// process (lib/soak/soak_episode.h), until T seconds of wall time have
// passed (checked before each episode). Before each episode it writes the
// seed to DIR/current_seed; after it, a line to DIR/episodes.jsonl with the
// episode's wall time and this process's VmRSS once freed memory is handed
// back (malloc_trim). An episode with a
// collision at fault leaves DIR/at_fault/F-K.yaml (its scenario) and
// F-K.lcmlog (its log). Exit 0 when the time is up, 2 on a usage or
// configuration error; anything else is a crash (tools/soak).
//
// report: the verdict (lib/soak/soak_report.h) over DIR/episodes.jsonl,
// DIR/rss.tsv (the sampler's) and DIR/crashes.tsv (if any): prints it,
// writes DIR/report.json. Exit 0 pass, 1 fail, 2 unreadable files.
#include <malloc.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bus/process_main.h"
#include "config/config.h"
#include "sim/scenario_gen_params.h"
#include "soak/soak_report.h"

namespace fs = std::filesystem;

namespace {

const std::chrono::steady_clock::time_point g_process_start = std::chrono::steady_clock::now();

struct RunArgs {
  std::string out, family = "mixed", families, mode;
  evade::bus::CommonOptions robot;  // --config, --robot
  uint64_t seed_base = 1;
  double wall_s = 1200.0;
};

struct ReportArgs {
  std::string dir;
  double max_growth_mib_per_h = 16.0;
  double warmup_s = 120.0;
};

double self_rss_kib() {
  std::ifstream f("/proc/self/status");
  std::string key;
  double v = 0;
  while (f >> key) {
    if (key == "VmRSS:") {
      f >> v;
      return v;
    }
    f.ignore(4096, '\n');
  }
  return 0;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream f(p);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + p.string());
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  if (!f) throw std::runtime_error("cannot read " + p.string());
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// One episode: its line in episodes.jsonl, its files when at fault.
void soak_one(const evade::soak::EpisodeInputs& in, const RunArgs& a, uint64_t seed, std::ofstream& jsonl) {
  using Clock = std::chrono::steady_clock;
  const fs::path dir(a.out);
  write_text(dir / "current_seed", std::to_string(seed) + "\n");
  const std::string log = (dir / "episode.lcmlog").string();
  evade::soak::EpisodeLine line;
  line.result.family = a.family;
  line.result.seed = seed;
  const auto t0 = Clock::now();
  try {
    line.result = evade::soak::run_episode(in, a.family, seed, log);
  } catch (const std::exception& e) {
    line.error = e.what();
  }
  line.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  // Freed memory back to the system first, so that the reading is what is
  // still in use (and fragmentation), not the allocator's high-water mark.
  malloc_trim(0);
  line.rss_kib = self_rss_kib();
  line.pid = getpid();
  line.t_s = std::chrono::duration<double>(Clock::now() - g_process_start).count();
  if (line.error.empty() && line.result.collisions_at_fault > 0) {
    const std::string name = a.family + "-" + std::to_string(seed);
    fs::create_directories(dir / "at_fault");
    write_text(dir / "at_fault" / (name + ".yaml"), line.result.scenario_yaml);
    fs::rename(log, dir / "at_fault" / (name + ".lcmlog"));
  }
  jsonl << evade::soak::episode_line_json(line) << "\n" << std::flush;
  const auto& r = line.result;
  std::fprintf(stderr, "soak-lockstep: %s seed %llu: %s, %.1f s simulated, %.1f s wall, at fault %d, RSS %.1f MiB\n",
               a.family.c_str(), static_cast<unsigned long long>(seed),
               line.error.empty() ? r.outcome.c_str() : ("error: " + line.error).c_str(), r.sim_s, line.wall_s,
               r.collisions_at_fault, line.rss_kib / 1024.0);
}

int run(const RunArgs& a) {
  namespace gen = evade::sim::gen;
  evade::soak::EpisodeInputs in;
  try {
    in = evade::soak::EpisodeInputs::load(
        a.robot.config_path.empty() ? evade::config::default_config_path() : a.robot.config_path,
        a.families.empty() ? gen::default_families_path() : a.families, a.mode, a.robot.robot);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soak-lockstep: %s\n", e.what());
    return 2;
  }
  fs::create_directories(a.out);
  std::ofstream jsonl(fs::path(a.out) / "episodes.jsonl", std::ios::app);
  if (!jsonl) {
    std::fprintf(stderr, "soak-lockstep: cannot write %s/episodes.jsonl\n", a.out.c_str());
    return 2;
  }
  const auto t0 = std::chrono::steady_clock::now();
  for (uint64_t seed = a.seed_base;; ++seed) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >= a.wall_s) break;
    soak_one(in, a, seed, jsonl);
  }
  fs::remove(fs::path(a.out) / "current_seed");
  fs::remove(fs::path(a.out) / "episode.lcmlog");
  return 0;
}

int report(const ReportArgs& a) {
  const fs::path dir(a.dir);
  try {
    const auto episodes = evade::soak::parse_episode_lines(read_text(dir / "episodes.jsonl"));
    const auto rss = evade::soak::parse_rss_samples(read_text(dir / "rss.tsv"));
    std::vector<evade::soak::Crash> crashes;
    if (fs::exists(dir / "crashes.tsv")) crashes = evade::soak::parse_crashes(read_text(dir / "crashes.tsv"));
    const auto r = evade::soak::make_report(episodes, crashes, rss, {a.max_growth_mib_per_h, a.warmup_s});
    write_text(dir / "report.json", evade::soak::report_json(r) + "\n");
    std::fputs(evade::soak::report_text(r).c_str(), stdout);
    return r.failures.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "soak-lockstep report: %s\n", e.what());
    return 2;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade soak: many lockstep episodes in one process, and their verdict"};
  app.require_subcommand(1);
  RunArgs r;
  auto* run_cmd = app.add_subcommand("run", "run episodes back to back for a wall time");
  run_cmd->add_option("--out", r.out, "directory for episodes.jsonl and at_fault/")->required();
  run_cmd->add_option("--family", r.family, "scenario family (default mixed)");
  run_cmd->add_option("--seed-base", r.seed_base, "first seed (default 1)");
  run_cmd->add_option("--wall-s", r.wall_s, "wall seconds before no new episode starts (default 1200)")
      ->check(CLI::PositiveNumber);
  evade::bus::add_robot_options(*run_cmd, r.robot, false);  // --config, --robot
  run_cmd->add_option("--families", r.families, "family ranges (default config/scenario_families.yaml)");
  run_cmd->add_option("--mode", r.mode, "planner mode (default: the configuration's)");
  ReportArgs p;
  auto* rep_cmd = app.add_subcommand("report", "judge a soak's files");
  rep_cmd->add_option("--dir", p.dir, "the soak's directory")->required();
  rep_cmd->add_option("--max-growth-mib-per-h", p.max_growth_mib_per_h, "memory growth bound (default 16)")
      ->check(CLI::NonNegativeNumber);
  rep_cmd->add_option("--warmup-s", p.warmup_s, "samples before this are not fitted (default 120)")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // 2: a usage error, never taken for a crash
  }
  return run_cmd->parsed() ? run(r) : report(p);
}
