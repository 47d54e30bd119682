// lockstep --scenario FILE --out RUN.lcmlog [--config FILE] [--robot NAME] [--seed K]
//          [--mode M] [--planner-compute fixed|iterations|measured]
//          [--cpu-cores N] [--background-load-cores B] [--profile [--samples CSV]]
//          [--progress] [--force]
// Runs a scenario through the whole stack in simulated time, in this one
// process (lib/closedloop/closed_loop.h), and writes the run's log as
// lcm-logger would have recorded it live. Prints one summary line.
// --profile measures each callback's CPU time (this thread's clock) and
// prints the lockstep.costs it suggests (lib/closedloop/cost_profile.h);
// --samples writes every profiled callback as `process,kind,k,cpu_s` (kind:
// plan for the planner's PLAN cycles, else callback), to pool runs.
// Exit: 0 the goal was reached, 1 the scenario's duration passed first,
// 2 usage, configuration or file error.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>

#include "bus/log.h"
#include "bus/process_main.h"
#include "closedloop/closed_loop.h"
#include "closedloop/cost_profile.h"
#include "closedloop/run_monitor.h"
#include "config/config.h"
#include "sim/scenario.h"

namespace {

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void print_summary(const evade::closedloop::LockstepResult& r, double wall_s) {
  const char* outcome = r.outcome == evade::closedloop::RunMonitor::kGoal       ? "goal reached"
                        : r.outcome == evade::closedloop::RunMonitor::kDuration ? "duration passed"
                                                                                : "stopped at the safety cap";
  std::fprintf(stderr, "lockstep: %s at %.2f s simulated, %.2f s wall (%.1fx real time), %lld events\n", outcome,
               r.sim_s, wall_s, wall_s > 0 ? r.sim_s / wall_s : 0.0, static_cast<long long>(r.events));
  for (const auto& [name, p] : r.processes)
    if (p.compute_s > 0)
      std::fprintf(stderr, "lockstep:   %-14s %8lld callbacks, %7.3f s compute charged (%.1f %% of the run)\n",
                   name.c_str(), static_cast<long long>(p.callbacks), p.compute_s,
                   r.sim_s > 0 ? 100.0 * p.compute_s / r.sim_s : 0.0);
  if (r.cpu_work_s > 0)
    std::fprintf(stderr, "lockstep:   shared cores: %.3f s CPU handed out (%.2f cores busy on average)\n", r.cpu_work_s,
                 r.sim_s > 0 ? r.cpu_work_s / r.sim_s : 0.0);
}

void write_samples(const evade::closedloop::LockstepResult& r, const std::string& path) {
  std::ofstream f(path);
  f << "process,kind,k,cpu_s\n";
  for (const auto& [name, p] : r.processes) {
    for (const auto& s : p.samples) f << name << ",callback," << s.k << ',' << s.cpu_s << '\n';
    for (const auto& s : p.plan_samples) f << name << ",plan," << s.k << ',' << s.cpu_s << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"evade lockstep: the whole stack and the simulator in simulated time, one process"};
  std::string scenario_path, out, mode, compute, samples;
  evade::bus::CommonOptions common;
  int64_t seed = -1;
  bool progress = false, force = false, profile = false;
  double cpu_cores = -1, background = -1;
  app.add_option("--scenario", scenario_path, "scenario YAML (docs/SPEC.md format)")->required();
  app.add_option("--out", out, "write the run's log here")->required();
  evade::bus::add_robot_options(app, common);  // --config, --robot
  app.add_option("--seed", seed, "the simulator's sensor-noise seed (default: the scenario's seed)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--mode", mode, "planner mode (default: the configuration's)");
  app.add_option("--planner-compute", compute, "planner compute model (default: lockstep.planner_compute)")
      ->check(CLI::IsMember({"fixed", "iterations", "measured"}));
  app.add_option("--cpu-cores", cpu_cores, "cores shared (default: lockstep.cpu_cores; 0: one per process)")
      ->check(CLI::Range(0.0, 256.0));
  app.add_option("--background-load-cores", background, "default: lockstep.background_load_cores")
      ->check(CLI::Range(0.0, 256.0));
  app.add_flag("--profile", profile, "measure each callback's CPU time and print the lockstep.costs it suggests");
  app.add_option("--samples", samples, "with --profile: write every profiled callback to this CSV");
  app.add_flag("--progress", progress, "print the run monitor's progress lines");
  app.add_flag("--force", force, "overwrite an existing log");
  CLI11_PARSE(app, argc, argv);

  if (std::filesystem::exists(out) && !force) {
    std::fprintf(stderr, "lockstep: %s exists; not overwriting it without --force\n", out.c_str());
    return 2;
  }
  evade::bus::robot_options_from(app, common);
  const evade::config::Node root = evade::bus::load_config_or_exit("lockstep", common);
  try {
    evade::sim::Scenario scenario = evade::sim::load_scenario(scenario_path);
    evade::sim::resolve_robot(&scenario, root);
    evade::closedloop::LockstepRun run;
    if (seed >= 0) run.seed = static_cast<uint64_t>(seed);
    run.planner_mode = mode;
    run.planner_compute = compute;
    run.quiet = !progress;
    if (cpu_cores >= 0) run.cpu_cores = cpu_cores;
    if (background >= 0) run.background_load_cores = background;
    if (profile) run.cpu_clock = thread_cpu_s;
    evade::closedloop::ClosedLoop loop(root, scenario, run);
    evade::bus::LogWriter log(out);
    const auto t0 = std::chrono::steady_clock::now();
    const evade::closedloop::LockstepResult r = loop.run(&log);
    print_summary(r, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (profile) std::printf("%s", evade::closedloop::suggested_costs(r).c_str());
    if (profile && !samples.empty()) write_samples(r, samples);
    return r.outcome == evade::closedloop::RunMonitor::kGoal ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lockstep: %s\n", e.what());
    return 2;
  }
}
