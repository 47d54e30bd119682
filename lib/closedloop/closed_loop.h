// The whole evade stack and its simulator in one process, in simulated
// time ("lockstep"). The same cores as the live stack, built from the same
// configuration: sim (VLP-16 or RS-Helios packets, the Scout's UART),
// lidar_driver, elevation_map, tracker, predictor, route, planner, base_driver, plus the
// run monitor that ends a run as tools/run-monitor does live.
//
// What each core sees is what it would see live, in order, at the times it
// would arrive:
// - LCM messages reach every subscriber (the publisher too, as on LCM)
//   bus_latency_s after they leave their process;
// - each process runs one callback at a time and is charged a compute time
//   (LockstepParams; ProcessNode): its outputs leave when that time has
//   passed, and what arrives meanwhile waits (the planner conflates
//   PlannerCore::conflated_inputs(), as procs/planner does);
// - LiDAR packets reach the driver udp_latency_s after the simulator makes
//   them; Scout frames cross an emulated UART at its baud rate, both ways.
// Everything but the planner's `measured` compute model is deterministic:
// the same scenario, seed and configuration give the same messages at the
// same times, byte for byte.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "bus/log.h"
#include "config/config.h"
#include "sim/scenario.h"

namespace evade::closedloop {

struct LockstepRun {
  std::optional<uint64_t> seed;                 // overrides the scenario's seed (the simulator's sensor noise)
  std::string planner_mode;                     // empty: the configuration's
  std::string planner_compute;                  // empty: the configuration's (fixed | iterations | measured)
  std::optional<double> cpu_cores;              // overrides lockstep.cpu_cores
  std::optional<double> background_load_cores;  // overrides lockstep.background_load_cores
  bool quiet = true;                            // no progress lines from the run monitor
  // Channels not written to the log (LIDAR_SCAN holds the packets the
  // point clouds are decoded from, as in a live run_scenario log).
  std::set<std::string> unlogged = {"LIDAR_POINTS"};
  // Profiling: when set, read before and after every callback (the tool
  // passes the thread's CPU clock, s); ProcessStats then holds the samples
  // that calibrate lockstep.costs (cost_profile.h). Never changes a run.
  std::function<double()> cpu_clock;
};

// One profiled callback: its size k (1 if it published, 0 if not; the
// simulator: the packets it made; the planner's PLAN cycles: the Ceres
// iterations) and the CPU time it took here.
struct CpuSample {
  double k = 0.0;
  double cpu_s = 0.0;
};

struct ProcessStats {
  int64_t callbacks = 0;
  double compute_s = 0.0;               // simulated compute time charged
  std::vector<CpuSample> samples;       // profiled callbacks (the planner's PLAN cycles aside)
  std::vector<CpuSample> plan_samples;  // the planner's PLAN cycles, k = iterations
};

struct LockstepResult {
  int outcome = -1;         // RunMonitor::kGoal, kDuration (or -1: stopped at the safety cap)
  double sim_s = 0.0;       // simulated time from start to end
  int64_t events = 0;       // callbacks run by the event queue
  double cpu_work_s = 0.0;  // CPU time the shared cores handed out (0 without contention)
  std::map<std::string, ProcessStats> processes;
};

class ClosedLoop {
 public:
  // Throws config::ConfigError on bad configuration, std::invalid_argument
  // on a bad mode or compute model name.
  ClosedLoop(const config::Node& root, const sim::Scenario& scenario, const LockstepRun& run);
  ~ClosedLoop();
  ClosedLoop(const ClosedLoop&) = delete;
  ClosedLoop& operator=(const ClosedLoop&) = delete;

  // Runs until the run monitor ends the run (goal reached and held for
  // goal_margin_s, or the scenario's duration passed); every message that
  // crossed the bus goes to `log` (if given) stamped with its arrival time.
  LockstepResult run(bus::LogWriter* log);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace evade::closedloop
