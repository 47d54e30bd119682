// Runs cores live on LCM (udpm multicast). The bus time is microseconds
// since the epoch: the host's wall clock read once, at the process's first
// reading, then advanced by the monotonic clock (bus_utime). A wall-clock
// step (NTP, an operator) therefore neither stops timers nor makes ages
// negative; processes started on either side of a step disagree by the
// step, see each other's messages as too old or from the future, refuse
// them and stop the robot (restart the stack after a step). This is the
// only place where a process core's time comes from a clock. Extra file descriptors (a UDP
// socket, a serial port) are polled in the same loop, so a process stays
// single-threaded and its core never sees concurrency.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bus/core.h"

namespace lcm {
class LCM;
class ReceiveBuffer;
}  // namespace lcm

namespace evade::bus {

// The URL every process uses unless told otherwise: $LCM_DEFAULT_URL, else
// host-local multicast (ttl=0) with a receive buffer large enough for
// point clouds.
std::string default_lcm_url();
inline constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608";

// The clocks the bus time is made of; tests inject their own (set_clock).
class Clock {
 public:
  virtual ~Clock() = default;
  virtual int64_t wall_us() const = 0;       // may step
  virtual int64_t monotonic_us() const = 0;  // never steps
};
// The process's bus time (see above).
int64_t bus_utime();
// The former name of bus_utime.
inline int64_t wall_utime() { return bus_utime(); }
// Replaces the clock bus_utime reads (nullptr: the system's) and anchors
// the bus time again at the new clock's wall time. For tests.
void set_clock(const Clock* clock);

class LiveBus : public Sink {
 public:
  explicit LiveBus(const std::string& url);  // throws std::runtime_error if LCM cannot start
  ~LiveBus() override;

  void add(Core& core);
  // Messages on this channel that queue up while a core is busy are
  // conflated: of those handled in one go, only the newest is delivered
  // (a queue of one). For inputs where only the latest matters, e.g. the
  // planner's ODOMETRY after a long solve: acting on each queued pose would
  // plan from the past and judge every one of them stale.
  void conflate(const std::string& channel);
  // Calls fn(now) whenever fd is readable.
  void add_fd(int fd, std::function<void(int64_t now)> fn);
  void remove_fd(int fd);
  // Wakes the loop at `utime` even when nothing arrives (e.g. a pacing sender).
  void wake_at(int64_t utime);
  // Runs until `stop` becomes true (checked at least every 50 ms).
  void run(const std::atomic<bool>& stop);
  // Handles what is ready now and returns after at most timeout_ms.
  void spin_once(int timeout_ms);

  void publish(const std::string& channel, int64_t now, std::vector<uint8_t> data) override;

 private:
  void on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel);
  std::unique_ptr<lcm::LCM> lcm_;
  std::vector<Core*> cores_;
  std::map<std::string, std::vector<uint8_t>> conflated_;  // channel -> newest message held back
  bool draining_ = false;
  void deliver(const std::string& channel, const uint8_t* data, size_t size);
  std::map<int, std::function<void(int64_t)>> fds_;
  int64_t wake_at_ = kNever;
};

// Installs SIGINT/SIGTERM handlers that set the returned flag.
const std::atomic<bool>& stop_on_signals();

}  // namespace evade::bus
