// The pieces of simulated time: the event queue's order, a process's
// busy / waiting / conflation model, the UART's byte timing.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bus/core.h"
#include "closedloop/event_queue.h"
#include "closedloop/process_node.h"
#include "closedloop/serial_line.h"
#include "evade/cmd_vel_t.hpp"

namespace evade::closedloop {
namespace {

TEST(EventQueue, RunsInTimeOrderAndTiesInSchedulingOrder) {
  EventQueue q;
  std::vector<std::string> order;
  q.at(30, [&] { order.push_back("c30"); });
  q.at(10, [&] { order.push_back("a10"); });
  q.at(10, [&] { order.push_back("b10"); });
  q.at(20, [&] {
    order.push_back("x20");
    q.at(5, [&] { order.push_back("past->now"); });  // the past runs now, after what is already due now
  });
  while (q.run_next()) {
  }
  EXPECT_EQ(order, (std::vector<std::string>{"a10", "b10", "x20", "past->now", "c30"}));
  EXPECT_EQ(q.now(), 30);
}

// A core that answers every CMD_VEL on channel OUT and counts its timer.
class Echo : public bus::Core {
 public:
  explicit Echo(int64_t timer_us) : Core("echo", 1'000'000'000) {
    subscribe<evade::cmd_vel_t>("IN", [this](const evade::cmd_vel_t& m) {
      seen.push_back({now(), m.v});
      evade::cmd_vel_t out = m;
      publish("OUT", out);
    });
    if (timer_us > 0) every(timer_us, [this] { ticks.push_back(now()); });
  }
  std::vector<std::pair<int64_t, double>> seen;  // (bus time handled, v)
  std::vector<int64_t> ticks;
};

// Runs the queue up to bus time t (a core's HEALTH timer never lets it empty).
void run_until(EventQueue& q, int64_t t) {
  while (q.next_time() <= t && q.run_next()) {
  }
}

// Charges d for a callback that answered on OUT, nothing for others (the
// HEALTH heartbeat).
ProcessNode::ComputeModel charge_answers(int64_t d) {
  return [d](const std::vector<bus::LogEvent>& out) {
    for (const auto& o : out)
      if (o.channel == "OUT") return d;
    return int64_t{0};
  };
}

Bytes cmd(double v) {
  evade::cmd_vel_t m{};
  m.v = v;
  return std::make_shared<const std::vector<uint8_t>>(bus::encode(m));
}

struct Routed {
  std::string channel;
  int64_t t;
};

TEST(ProcessNode, OutputsLeaveAfterTheComputeTimeAndInputsWaitMeanwhile) {
  EventQueue q;
  Echo echo(0);
  std::vector<Routed> routed;
  ProcessNode node(echo, q, charge_answers(100));
  node.set_router([&](const std::string& ch, int64_t t, const Bytes&) {
    if (ch == "OUT") routed.push_back({ch, t});
  });
  node.start(0);
  q.at(1000, [&] { node.deliver("IN", cmd(1)); });
  q.at(1050, [&] { node.deliver("IN", cmd(2)); });  // arrives while the first is computed
  run_until(q, 10'000);
  ASSERT_EQ(echo.seen.size(), 2u);
  EXPECT_EQ(echo.seen[0].first, 1000);
  EXPECT_EQ(echo.seen[1].first, 1100);  // handled when the process is free
  ASSERT_EQ(routed.size(), 2u);
  EXPECT_EQ(routed[0].t, 1100);
  EXPECT_EQ(routed[1].t, 1200);
  EXPECT_EQ(node.compute_us(), 200);
}

TEST(ProcessNode, AConflatedChannelKeepsOnlyTheNewestWaitingMessage) {
  EventQueue q;
  Echo echo(0);
  ProcessNode node(echo, q, charge_answers(500), {"IN"});
  node.set_router([](const std::string&, int64_t, const Bytes&) {});
  node.start(0);
  q.at(0, [&] { node.deliver("IN", cmd(1)); });
  q.at(100, [&] { node.deliver("IN", cmd(2)); });
  q.at(200, [&] { node.deliver("IN", cmd(3)); });
  run_until(q, 10'000);
  ASSERT_EQ(echo.seen.size(), 2u);
  EXPECT_DOUBLE_EQ(echo.seen[0].second, 1.0);
  EXPECT_DOUBLE_EQ(echo.seen[1].second, 3.0);  // 2 was superseded while waiting
  EXPECT_EQ(echo.seen[1].first, 500);
}

TEST(ProcessNode, TimersFireOnTimeWhenIdleAndLateWhenBusy) {
  EventQueue q;
  Echo echo(1000);  // a tick every millisecond from t = 0
  ProcessNode node(echo, q, charge_answers(2500));
  node.set_router([](const std::string&, int64_t, const Bytes&) {});
  node.start(0);
  q.at(1500, [&] { node.deliver("IN", cmd(1)); });  // busy from 1500 to 4000
  run_until(q, 6000);
  // 0 and 1000 on time; 2000 and 3000 come due while busy: the core runs
  // them at 4000 (callback time = deadline), then 4000, 5000, 6000.
  ASSERT_GE(echo.ticks.size(), 6u);
  EXPECT_EQ(echo.ticks[0], 0);
  EXPECT_EQ(echo.ticks[1], 1000);
  EXPECT_EQ(echo.ticks[2], 2000);
  EXPECT_EQ(echo.ticks[3], 3000);
  EXPECT_EQ(echo.ticks[4], 4000);
  EXPECT_EQ(echo.ticks[5], 5000);
}

TEST(SerialLine, BytesArriveAtTheBaudRateBehindEarlierWrites) {
  EventQueue q;
  std::vector<std::pair<int64_t, size_t>> got;
  SerialLine line(q, 115200, [&](const std::vector<uint8_t>& b) { got.push_back({q.now(), b.size()}); });
  EXPECT_NEAR(line.byte_time_us(), 86.8, 0.1);  // 10 bits a byte
  q.at(0, [&] {
    line.write(0, std::vector<uint8_t>(13, 0));
    line.write(0, std::vector<uint8_t>(10, 0));  // queued behind the first
  });
  while (q.run_next()) {
  }
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].first, 1129);  // ceil(13 x 86.806)
  EXPECT_EQ(got[1].first, 1997);  // ceil(23 x 86.806)
  EXPECT_EQ(got[0].second, 13u);
}

}  // namespace
}  // namespace evade::closedloop
