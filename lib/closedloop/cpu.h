// The robot computer's cores in simulated time, shared by the processes of
// a lockstep run by processor sharing: while n jobs (callbacks being
// computed) are runnable beside a background load of b always-runnable
// threads, each job gets min(1, cores / (n + b)) of a core, so a job of w
// microseconds of CPU time takes w / that rate of simulated time. This is
// the fluid model Linux's fair schedulers (CFS, EEVDF) approximate for
// threads of equal weight (why, and its limits: lib/closedloop/README.md). Deterministic: completions come from
// the event queue in time order, jobs that finish together in the order
// they started.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "closedloop/event_queue.h"

namespace evade::closedloop {

class Cpu {
 public:
  // cores > 0; background_cores >= 0 (threads of the stack's weight that
  // never sleep: other programs on the computer).
  Cpu(EventQueue& queue, double cores, double background_cores);

  // Starts a job of work_us (>= 0) of CPU time now; `done` runs (from the
  // event queue) when it has had that much. A job of 0 completes now.
  void run(int64_t work_us, std::function<void()> done);

  // Jobs started and not yet done.
  int running() const { return static_cast<int>(jobs_.size()); }
  // The share of a core each running job gets now (0 when none runs).
  double rate() const;
  // CPU time handed out so far (us).
  double work_done_us() const { return work_done_us_; }

 private:
  struct Job {
    double remaining_us;
    std::function<void()> done;
  };
  void advance();
  void schedule_next();
  void complete();

  EventQueue& q_;
  double cores_;
  double background_;
  std::vector<Job> jobs_;  // in the order they started
  int64_t last_ = 0;       // bus time up to which remaining_us is counted down
  uint64_t gen_ = 0;       // the scheduled completion event that is still valid
  double work_done_us_ = 0.0;
};

}  // namespace evade::closedloop
