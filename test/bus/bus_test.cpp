// The bus contract: decoded delivery with bus time, timers on bus time,
// HEALTH for free, malformed input counted, and identical outputs whether a
// core runs on the in-memory bus or over a log.
#include <gtest/gtest.h>

#include "bus/core.h"
#include "bus/log_replay.h"
#include "bus/memory_bus.h"
#include "echo_core.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/health_t.hpp"
#include "evade/odometry_t.hpp"

namespace evade::bus {
namespace {

// EchoCore (ODOMETRY -> CMD_VEL with doubled velocities, stamped with the
// input's utime) plus a 10 Hz timer that records its ticks.
class Doubler : public testing::EchoCore {
 public:
  Doubler() {
    every(100'000, [this] { tick_times.push_back(now()); });
  }
  std::vector<int64_t> tick_times;
};

evade::odometry_t odom(int64_t utime, double v) {
  evade::odometry_t m{};
  m.utime = utime;
  m.v = v;
  m.omega = -v;
  return m;
}

TEST(MemoryBus, DeliversDecodedMessagesAndStampsOutputs) {
  MemoryBus bus;
  Doubler d;
  bus.add(d);
  bus.inject("ODOMETRY", odom(42, 0.5), 1'000'000);
  auto out = bus.decoded<evade::cmd_vel_t>("CMD_VEL");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].utime, 42);
  EXPECT_DOUBLE_EQ(out[0].v, 1.0);
  EXPECT_DOUBLE_EQ(out[0].omega, -1.0);
}

TEST(MemoryBus, TimersRunOnBusTime) {
  MemoryBus bus;
  Doubler d;
  bus.add(d);
  bus.advance_to(1'000'000);
  bus.advance_to(1'250'000);
  // armed at 1.0 s: fires at 1.0, 1.1, 1.2
  EXPECT_EQ(d.tick_times, (std::vector<int64_t>{1'000'000, 1'100'000, 1'200'000}));
  // a short gap catches up tick by tick, each at its own deadline
  bus.advance_to(1'450'000);
  EXPECT_EQ(d.tick_times.size(), 5u);
  EXPECT_EQ(d.tick_times.back(), 1'400'000);
  // a stall of more than 10 periods fires once, at the current time
  bus.advance_to(5'000'000);
  EXPECT_EQ(d.tick_times.size(), 6u);
  EXPECT_EQ(d.tick_times.back(), 5'000'000);
}

// Two timers, one far behind after a gap: every callback sees a bus time no
// earlier than the one before it.
class TwoTimers : public Core {
 public:
  TwoTimers() : Core("two_timers", 50'000) {
    every(20'000, [this] { times.push_back(now()); });
    every(1'000'000, [this] { times.push_back(now()); });
  }
  std::vector<int64_t> times;
};

TEST(MemoryBus, BusTimeNeverRunsBackwardsAfterAGap) {
  MemoryBus bus;
  TwoTimers t;
  bus.add(t);
  bus.advance_to(1'000'000);
  bus.advance_to(1'100'000);
  bus.advance_to(1'250'000);  // 20 ms timer: 7 periods behind (catches up); 50 ms health: 3 behind
  bus.advance_to(9'000'000);  // long gap: 20 ms and 50 ms timers stalled, 1 s timer 7 behind
  ASSERT_GT(t.times.size(), 10u);
  for (size_t i = 1; i < t.times.size(); ++i) EXPECT_LE(t.times[i - 1], t.times[i]) << "at " << i;
  EXPECT_EQ(t.times.back(), 9'000'000);
}

TEST(MemoryBus, HealthReportsInputsCountersAndMalformed) {
  MemoryBus bus;
  Doubler d;
  bus.add(d);
  bus.inject("ODOMETRY", odom(1, 0.1), 1'000'000);
  std::vector<uint8_t> junk{1, 2, 3};
  bus.inject("ODOMETRY", junk, 1'100'000);
  bus.inject("ODOMETRY", odom(2, 0.1), 1'500'000);
  bus.advance_to(2'000'000);
  auto health = bus.decoded<evade::health_t>("HEALTH");
  ASSERT_EQ(health.size(), 2u);  // at 1.0 s (armed) and 2.0 s
  const auto& h = health.back();
  EXPECT_EQ(h.name, "bus_echo");
  EXPECT_EQ(h.seq, 1);
  ASSERT_EQ(h.num_inputs, 1);
  EXPECT_EQ(h.inputs[0].channel, "ODOMETRY");
  EXPECT_EQ(h.inputs[0].received, 3);
  EXPECT_EQ(h.inputs[0].malformed, 1);
  EXPECT_EQ(h.inputs[0].age_us, 500'000);
  // CMD_VEL at 1.0 s (after the first heartbeat) and 1.5 s, over 1 s
  EXPECT_NEAR(h.output_rate_hz, 2.0, 1e-9);
  // the malformed message produced nothing
  EXPECT_EQ(bus.decoded<evade::cmd_vel_t>("CMD_VEL").size(), 2u);
}

TEST(MemoryBus, ExternalInputsAppearInHealth) {
  MemoryBus bus;
  Doubler d;
  bus.add(d);
  int packets = 0;
  bus.input(d, 1'000'000, [&] { ++packets; });  // unnamed: not reported
  d.input(
      1'200'000, [&] { ++packets; }, "udp:2368");
  d.input(
      1'300'000, [&] { ++packets; }, "udp:2368");
  bus.advance_to(2'000'000);
  auto h = bus.decoded<evade::health_t>("HEALTH").back();
  EXPECT_EQ(packets, 3);
  ASSERT_EQ(h.num_inputs, 2);
  EXPECT_EQ(h.inputs[1].channel, "udp:2368");
  EXPECT_EQ(h.inputs[1].received, 2);
  EXPECT_EQ(h.inputs[1].age_us, 700'000);
  EXPECT_EQ(d.channels(), std::vector<std::string>{"ODOMETRY"});  // never subscribed on LCM
}

TEST(LogReplay, SameOutputsTwiceAndSameAsMemoryBus) {
  std::vector<LogEvent> input;
  for (int i = 0; i < 50; ++i) input.push_back(LogEvent{1'000'000 + i * 37'000, "ODOMETRY", encode(odom(i, 0.01 * i))});
  input.push_back(LogEvent{2'900'000, "OTHER", {9, 9}});

  Doubler a, b;
  auto out_a = replay({&a}, input);
  auto out_b = replay({&b}, input);
  ASSERT_EQ(out_a.size(), out_b.size());
  for (size_t i = 0; i < out_a.size(); ++i) {
    EXPECT_EQ(out_a[i].timestamp, out_b[i].timestamp);
    EXPECT_EQ(out_a[i].channel, out_b[i].channel);
    EXPECT_EQ(out_a[i].data, out_b[i].data) << "event " << i;
  }

  MemoryBus bus;
  Doubler c;
  c.set_measure_latency(false);
  bus.add(c);
  for (const auto& e : input) bus.inject(e.channel, e.data, e.timestamp);
  const auto& out_c = bus.published();
  ASSERT_EQ(out_c.size(), out_a.size());
  for (size_t i = 0; i < out_c.size(); ++i) EXPECT_EQ(out_c[i].data, out_a[i].data);
}

TEST(LogReplay, FileToFileRoundTrip) {
  std::string in = ::testing::TempDir() + "/bus_in.lcmlog";
  std::string out = ::testing::TempDir() + "/bus_out.lcmlog";
  std::vector<LogEvent> input;
  for (int i = 0; i < 10; ++i) input.push_back(LogEvent{i * 100'000, "ODOMETRY", encode(odom(i, 1.0))});
  write_log(in, input);
  Doubler d;
  ReplayOptions opt;
  opt.keep_health = false;
  int64_t n = replay_file({&d}, in, out, opt);
  EXPECT_EQ(n, 10);
  auto back = read_log(out);
  ASSERT_EQ(back.size(), 10u);
  evade::cmd_vel_t c;
  ASSERT_TRUE(decode(back[3].data.data(), back[3].data.size(), &c));
  EXPECT_EQ(c.utime, 3);
  EXPECT_EQ(back[3].timestamp, 300'000);
  EXPECT_EQ(back[3].channel, "CMD_VEL");
}

TEST(Decode, RejectsTruncatedAndForeignBytes) {
  auto bytes = encode(odom(7, 1.0));
  evade::odometry_t m;
  EXPECT_TRUE(decode(bytes.data(), bytes.size(), &m));
  EXPECT_FALSE(decode(bytes.data(), bytes.size() - 1, &m));
  evade::cmd_vel_t c;
  EXPECT_FALSE(decode(bytes.data(), bytes.size(), &c));  // wrong fingerprint
}

}  // namespace
}  // namespace evade::bus
