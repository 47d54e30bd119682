// Simulated time for the lockstep closed loop: callbacks scheduled at bus
// times (microseconds), run in time order; callbacks at the same time run
// in the order they were scheduled, so a run is deterministic.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace evade::closedloop {

class EventQueue {
 public:
  using Fn = std::function<void()>;

  // Schedules fn at bus time t; a time before now() runs at now().
  void at(int64_t t, Fn fn);
  // Runs the earliest callback; false when none is left.
  bool run_next();
  bool empty() const { return heap_.empty(); }
  // Bus time of the callback running (or of the last one run).
  int64_t now() const { return now_; }
  void set_now(int64_t t) { now_ = t; }
  // Bus time of the next callback (kNever when empty).
  int64_t next_time() const;
  uint64_t events_run() const { return run_; }

 private:
  struct Event {
    int64_t t;
    uint64_t seq;
    Fn fn;
  };
  struct Later {
    bool operator()(const Event& a, const Event& b) const { return a.t != b.t ? a.t > b.t : a.seq > b.seq; }
  };
  std::vector<Event> heap_;
  uint64_t seq_ = 0;
  uint64_t run_ = 0;
  int64_t now_ = 0;
};

}  // namespace evade::closedloop
