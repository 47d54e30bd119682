// The end of a scenario run, decided from the bus alone: SIM_TRUTH gives
// the robot, the goal and the scenario's duration, PLAN the planner's
// status. The same rule ends live runs (tools/run-monitor) and lockstep
// runs (closed_loop.h).
//
// Result codes: 0 the robot stayed within the goal tolerance for margin_s;
// 1 the scenario's duration passed first; 3 SIM_TRUTH stopped arriving for
// stall_s of bus time (live only: in lockstep the simulator never stalls).
#pragma once

#include <cstdint>
#include <string>

#include "bus/core.h"
#include "evade/sim_truth_t.hpp"

namespace evade::closedloop {

struct RunMonitorParams {
  double margin_s = 0.5;  // keep watching this long after the goal is reached
  double stall_s = 5.0;   // give up when SIM_TRUTH is silent this long
  bool quiet = false;     // no progress line
  bool tty = false;       // progress rewritten in place (a terminal) or a line every 2 s
};

class RunMonitor : public bus::Core {
 public:
  static constexpr int kRunning = -1, kGoal = 0, kDuration = 1, kStalled = 3;
  explicit RunMonitor(const RunMonitorParams& params);

  int result() const { return result_; }
  double elapsed_s() const { return elapsed_s_; }  // scenario time of the last SIM_TRUTH
  double min_clearance_m() const { return min_clear_; }

 private:
  void on_truth(const evade::sim_truth_t& t);
  void check_stall();
  void print_progress(const evade::sim_truth_t& t, double to_goal, double clear);
  void finish(int code, const std::string& why);

  RunMonitorParams p_;
  int result_ = kRunning;
  int64_t t0_ = -1, last_print_ = 0, goal_at_ = -1, last_truth_now_ = -1;
  double min_clear_ = 1e9, solve_ms_ = 0, elapsed_s_ = 0;
  int plan_status_ = -1;
};

// The clearance between the robot's footprint and the nearest obstacle of
// one SIM_TRUTH message (m; negative when they overlap).
double truth_clearance(const evade::sim_truth_t& t);

}  // namespace evade::closedloop
