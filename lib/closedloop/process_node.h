// One process of the stack in simulated time. Its core runs one callback
// at a time, as the single-threaded process does live: a callback that
// starts at bus time t is charged the compute time its ComputeModel gives
// for what it published (d); its outputs leave when it has had d of CPU
// time (at t + d on a core of its own; later when it shares the Cpu with
// other processes, see cpu.h) and the process is busy until then. Messages, external inputs and timers that come due
// meanwhile wait and run when it is free, in the order they came (a timer
// before a message that arrived after its deadline); on a conflated
// channel only the newest waiting message is kept, as LiveBus does.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "bus/core.h"
#include "bus/log.h"
#include "closedloop/cpu.h"
#include "closedloop/event_queue.h"

namespace evade::closedloop {

using Bytes = std::shared_ptr<const std::vector<uint8_t>>;

class ProcessNode : public bus::Sink {
 public:
  // Compute time (us, >= 0) charged to one callback, from its outputs
  // (LogEvent::timestamp = the callback's bus time).
  using ComputeModel = std::function<int64_t(const std::vector<bus::LogEvent>& outputs)>;
  // Where an output goes: it leaves the process at t_leave.
  using Router = std::function<void(const std::string& channel, int64_t t_leave, const Bytes& data)>;

  ProcessNode(bus::Core& core, EventQueue& queue, ComputeModel model, std::set<std::string> conflated = {});

  bus::Core& core() { return core_; }
  void set_router(Router router) { router_ = std::move(router); }
  // Runs after every callback with the time its outputs leave (the base
  // driver's serial bytes go out then).
  void set_after(std::function<void(int64_t t_leave)> after) { after_ = std::move(after); }
  // The cores this process shares with others (nullptr: a core of its own).
  void set_cpu(Cpu* cpu) { cpu_ = cpu; }
  // Profiling (not deterministic, never changes what is charged): `clock`
  // is read before and after each callback and `sink` gets the callback's
  // outputs and the clock's difference (the tool passes thread CPU time).
  using Profiler = std::function<void(const std::vector<bus::LogEvent>& outputs, double clock_s)>;
  void set_profiler(std::function<double()> clock, Profiler sink) {
    clock_ = std::move(clock);
    profiler_ = std::move(sink);
  }

  // Arms the core's timers at bus time t (a process starting).
  void start(int64_t t);
  // A message on a channel the core subscribes to arrives now.
  void deliver(const std::string& channel, const Bytes& data);
  // External input (a UDP packet, serial bytes) arrives now; `source`
  // names it in HEALTH (see Core::input).
  void input(std::function<void()> fn, const std::string& source);

  void publish(const std::string& channel, int64_t now, std::vector<uint8_t> data) override;

  int64_t callbacks() const { return callbacks_; }
  int64_t compute_us() const { return compute_us_; }

 private:
  enum class Kind { kMessage, kInput, kTimer };
  struct Work {
    Kind kind;
    int64_t arrived;
    std::string channel;  // kMessage: the channel; kInput: the source
    Bytes data;
    std::function<void()> fn;
  };
  void arrive(Work w);
  void run(Work w);
  void finish();
  void on_free();
  void schedule_timer();

  bus::Core& core_;
  EventQueue& q_;
  ComputeModel model_;
  std::set<std::string> conflated_;
  Router router_;
  std::function<void(int64_t)> after_;
  Cpu* cpu_ = nullptr;
  std::function<double()> clock_;
  Profiler profiler_;
  std::vector<bus::LogEvent> outputs_;
  std::vector<bus::LogEvent> leaving_;  // the running callback's outputs, until its compute time has passed
  std::deque<Work> waiting_;
  bool busy_ = false;
  int64_t timer_at_ = bus::kNever;
  uint64_t timer_gen_ = 0;
  int64_t callbacks_ = 0;
  int64_t compute_us_ = 0;
};

}  // namespace evade::closedloop
