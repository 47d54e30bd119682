// How much faster than real time the lockstep closed loop runs a whole
// scenario on one core: simulated seconds per CPU second of this thread
// (counter x_real_time_cpu; the goal is at least 10x for
// paper_sim). The log is not written, so that the figure is the stack's
// and the simulator's, not the disk's. The planner's local solves run on
// threads of their own (planner.guidance.threads): x_real_time_process
// counts the CPU of every thread of the process.
//   build/bin/bench_lockstep --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include <ctime>
#include <string>

#include "closedloop/closed_loop.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "sim/scenario.h"

namespace {

double cpu_s_of(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
double thread_cpu_s() { return cpu_s_of(CLOCK_THREAD_CPUTIME_ID); }
double process_cpu_s() { return cpu_s_of(CLOCK_PROCESS_CPUTIME_ID); }

void run_scenario(benchmark::State& state, const std::string& file) {
  const std::string src = EVADE_SOURCE_DIR;
  const std::string path = src + "/config/scenarios/" + file;  // its robot: robot.yaml <- profile <- the scenario's
  const evade::config::Node root = evade::config::load_robot_config(src + "/config/robot.yaml", {"", path});
  evade::sim::Scenario scenario = evade::sim::load_scenario(path);
  evade::sim::resolve_robot(&scenario, root);
  double sim_s = 0.0, cpu_s = 0.0, process_s = 0.0;
  for (auto _ : state) {
    evade::closedloop::ClosedLoop loop(root, scenario, evade::closedloop::LockstepRun{});
    const double c0 = thread_cpu_s(), p0 = process_cpu_s();
    const evade::closedloop::LockstepResult r = loop.run(nullptr);
    cpu_s += thread_cpu_s() - c0;
    process_s += process_cpu_s() - p0;
    sim_s += r.sim_s;
    benchmark::DoNotOptimize(r.events);
  }
  state.counters["sim_s"] = sim_s / static_cast<double>(state.iterations());
  state.counters["x_real_time_cpu"] = cpu_s > 0 ? sim_s / cpu_s : 0.0;
  state.counters["x_real_time_process"] = process_s > 0 ? sim_s / process_s : 0.0;
}

void BM_LockstepPaperSim(benchmark::State& state) { run_scenario(state, "paper_sim.yaml"); }
void BM_LockstepMixedStreet(benchmark::State& state) { run_scenario(state, "mixed_street.yaml"); }

BENCHMARK(BM_LockstepPaperSim)->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK(BM_LockstepMixedStreet)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
