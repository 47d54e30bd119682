// Issue 20: a wall-clock step backwards of 60 s (NTP, an operator) while
// base_driver runs live must not stop its 50 Hz motion frames or its
// watchdog. The process clock is injected (bus::set_clock): the wall clock
// steps, the monotonic clock does not. The core runs on a real LiveBus
// (NETNS) with the serial side played in process.
#include <gtest/gtest.h>

#include <chrono>

#include "base/base_driver_core.h"
#include "base/scout_protocol.h"
#include "bus/live_bus.h"
#include "config/config.h"
#include "evade/cmd_vel_t.hpp"

namespace evade::base {
namespace {

int64_t steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

class SteppingClock : public bus::Clock {
 public:
  int64_t wall_us() const override {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
               .count() +
           offset_us;
  }
  int64_t monotonic_us() const override { return steady_us(); }
  int64_t offset_us = 0;
};

size_t frames_in(const std::vector<uint8_t>& tx, int* nonzero) {
  size_t n = 0;
  StreamParser p;
  p.feed(tx.data(), tx.size(), [&](const Frame& f) {
    MotionCommand c;
    if (!from_frame(f, &c)) return;
    ++n;
    if (c.linear_percent != 0) ++*nonzero;
  });
  return n;
}

TEST(BaseDriverClock, AWallClockStepBackDoesNotStopFramesOrTheWatchdog) {
  SteppingClock clock;
  bus::set_clock(&clock);
  BaseDriverParams p =
      BaseDriverParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"));
  BaseDriverCore core(p);
  bus::LiveBus live(bus::default_lcm_url());
  live.add(core);
  core.input(bus::bus_utime(), [&] { core.on_link_opened(); });

  constexpr int64_t kStepAt = 300'000, kLastCmd = 600'000, kEnd = 1'500'000;
  const int64_t t0 = steady_us();
  int64_t next_input = t0, tripped_at = -1;
  size_t frames_after_step = 0;
  int nonzero_after_step = 0, unused = 0;
  bool stepped = false;
  while (steady_us() - t0 < kEnd) {
    const int64_t elapsed = steady_us() - t0;
    if (!stepped && elapsed >= kStepAt) {
      clock.offset_us = -60'000'000;  // the wall clock jumps back a minute
      stepped = true;
    }
    if (steady_us() >= next_input) {
      next_input += 20'000;
      const int64_t now = bus::bus_utime();
      FrameBytes status = encode(SystemStatus{}, 0);  // the base is alive
      core.input(now, [&] { core.on_serial_bytes(status.data(), status.size()); });
      if (elapsed < kLastCmd) {  // the planner, until it dies at kLastCmd
        evade::cmd_vel_t c{};
        c.utime = now;
        c.v = 0.5;
        const auto bytes = bus::encode(c);
        core.deliver("CMD_VEL", bytes.data(), bytes.size(), now);
      }
    }
    live.spin_once(5);
    const auto tx = core.take_tx();
    if (stepped)
      frames_after_step += frames_in(tx, elapsed < kLastCmd ? &nonzero_after_step : &unused);
    else
      frames_in(tx, &unused);
    if (tripped_at < 0 && elapsed > kLastCmd && core.watchdog_tripped()) tripped_at = elapsed;
  }
  bus::set_clock(nullptr);
  // 50 Hz over the 1.2 s after the step: 60 frames; allow for a loaded machine.
  EXPECT_GE(frames_after_step, 45u);
  EXPECT_GT(nonzero_after_step, 5);  // still driving between the step and the planner's death
  // the watchdog trips watchdog_timeout_s (0.25 s) after the last command
  ASSERT_GT(tripped_at, 0) << "the watchdog never tripped";
  EXPECT_GE(tripped_at, kLastCmd + 200'000);
  EXPECT_LE(tripped_at, kLastCmd + 450'000);
}

}  // namespace
}  // namespace evade::base
