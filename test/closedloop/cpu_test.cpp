// The shared cores of a lockstep run (Cpu, processor sharing): jobs that
// outnumber the cores stretch, a background load slows every job by the
// stated factor, and the same jobs give the same times.
#include "closedloop/cpu.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bus/core.h"
#include "closedloop/event_queue.h"
#include "closedloop/process_node.h"
#include "evade/cmd_vel_t.hpp"

namespace evade::closedloop {
namespace {

// Starts a job of `work` at bus time `start`; its completion time goes to done[name].
void job(EventQueue& q, Cpu& cpu, std::map<std::string, int64_t>& done, const std::string& name, int64_t start,
         int64_t work) {
  q.at(start, [&q, &cpu, &done, name, work] { cpu.run(work, [&q, &done, name] { done[name] = q.now(); }); });
}

void run_all(EventQueue& q) {
  while (q.run_next()) {
  }
}

TEST(Cpu, AJobAloneOnACoreTakesItsWork) {
  EventQueue q;
  Cpu cpu(q, 1, 0);
  std::map<std::string, int64_t> done;
  job(q, cpu, done, "a", 100, 1000);
  run_all(q);
  EXPECT_EQ(done.at("a"), 1100);
  EXPECT_DOUBLE_EQ(cpu.work_done_us(), 1000.0);
}

TEST(Cpu, TwoJobsOnOneCoreTakeTwiceAsLong) {
  EventQueue q;
  Cpu cpu(q, 1, 0);
  std::map<std::string, int64_t> done;
  job(q, cpu, done, "a", 0, 1000);
  job(q, cpu, done, "b", 0, 1000);
  run_all(q);
  EXPECT_EQ(done.at("a"), 2000);
  EXPECT_EQ(done.at("b"), 2000);
}

TEST(Cpu, OnTwoCoresTwoJobsRunFreelyAndAThirdSlowsAllThree) {
  EventQueue q;
  Cpu cpu(q, 2, 0);
  std::map<std::string, int64_t> done;
  job(q, cpu, done, "a", 0, 1000);
  job(q, cpu, done, "b", 0, 1000);
  job(q, cpu, done, "c", 500, 250);  // a and b have 500 left; three share two cores: 2/3 each
  run_all(q);
  EXPECT_EQ(done.at("c"), 875);   // 250 / (2/3)
  EXPECT_EQ(done.at("a"), 1125);  // 250 left at 875, then a core each
  EXPECT_EQ(done.at("b"), 1125);
  EXPECT_NEAR(cpu.work_done_us(), 2250.0, 1e-6);
}

TEST(Cpu, ABackgroundLoadSlowsEveryJobByTheStatedFactor) {
  {
    EventQueue q;
    Cpu cpu(q, 1, 1);  // one other thread always runnable: half a core
    std::map<std::string, int64_t> done;
    job(q, cpu, done, "a", 0, 1000);
    run_all(q);
    EXPECT_EQ(done.at("a"), 2000);
  }
  {
    EventQueue q;
    Cpu cpu(q, 2, 2);  // 2 cores, 2 background threads, 1 job: 2/3 of a core
    std::map<std::string, int64_t> done;
    job(q, cpu, done, "a", 0, 900);
    run_all(q);
    EXPECT_EQ(done.at("a"), 1350);
  }
  {
    EventQueue q;
    Cpu cpu(q, 2, 1);  // a core for the background, a core for the job: no slower
    std::map<std::string, int64_t> done;
    job(q, cpu, done, "a", 0, 900);
    run_all(q);
    EXPECT_EQ(done.at("a"), 900);
  }
}

// Many overlapping jobs of odd sizes: the same times twice, every job done
// no earlier than its work allows, and no CPU time lost or made up.
std::map<std::string, int64_t> mixed_run(double* work) {
  EventQueue q;
  Cpu cpu(q, 2, 0.7);
  std::map<std::string, int64_t> done;
  int64_t total = 0;
  for (int i = 0; i < 200; ++i) {
    const int64_t start = (i * 7919) % 20000, w = 1 + (i * 104729) % 3000;
    job(q, cpu, done, "j" + std::to_string(i), start, w);
    total += w;
  }
  run_all(q);
  EXPECT_EQ(done.size(), 200u);
  EXPECT_EQ(cpu.running(), 0);
  EXPECT_NEAR(cpu.work_done_us(), static_cast<double>(total), 1e-3 * 200);
  for (int i = 0; i < 200; ++i) {
    const int64_t start = (i * 7919) % 20000, w = 1 + (i * 104729) % 3000;
    EXPECT_GE(done.at("j" + std::to_string(i)), start + w);
  }
  *work = cpu.work_done_us();
  return done;
}

TEST(Cpu, TheSameJobsGiveTheSameTimes) {
  double wa = 0, wb = 0;
  const auto a = mixed_run(&wa);
  const auto b = mixed_run(&wb);
  EXPECT_EQ(a, b);
  EXPECT_EQ(wa, wb);
}

// Two processes on one core: each callback charged 100 us, both handed a
// message at the same time, answer at 200 instead of 100.
class Echo : public bus::Core {
 public:
  explicit Echo(const std::string& name) : Core(name, 1'000'000'000) {
    subscribe<evade::cmd_vel_t>("IN", [this](const evade::cmd_vel_t& m) { publish("OUT", m); });
  }
};

// cores 0: each process on a core of its own.
std::vector<int64_t> answers(double cores) {
  EventQueue q;
  std::unique_ptr<Cpu> cpu = cores > 0 ? std::make_unique<Cpu>(q, cores, 0.0) : nullptr;
  Echo e1("one"), e2("two");
  auto charge = [](const std::vector<bus::LogEvent>& out) { return out.empty() ? int64_t{0} : int64_t{100}; };
  ProcessNode n1(e1, q, charge), n2(e2, q, charge);
  std::vector<int64_t> left;
  for (ProcessNode* n : {&n1, &n2}) {
    n->set_cpu(cpu.get());
    n->set_router([&left](const std::string& ch, int64_t t, const Bytes&) {
      if (ch == "OUT") left.push_back(t);
    });
    n->start(0);
  }
  evade::cmd_vel_t m{};
  auto data = std::make_shared<const std::vector<uint8_t>>(bus::encode(m));
  q.at(1000, [&] {
    n1.deliver("IN", data);
    n2.deliver("IN", data);
  });
  while (q.next_time() <= 10'000 && q.run_next()) {
  }
  return left;
}

TEST(Cpu, TwoProcessesOnOneCoreAnswerTwiceAsLate) {
  EXPECT_EQ(answers(0), (std::vector<int64_t>{1100, 1100}));  // a core each
  EXPECT_EQ(answers(2), (std::vector<int64_t>{1100, 1100}));  // two cores: no wait
  EXPECT_EQ(answers(1), (std::vector<int64_t>{1200, 1200}));  // one core shared
}

}  // namespace
}  // namespace evade::closedloop

#include "closedloop/cost_profile.h"

namespace evade::closedloop {
namespace {

TEST(CostProfile, TheLineThroughTheSamplesGivesTheBaseAndThePerItemCost) {
  const CostFit f = fit_cost({{0, 0.001}, {1, 0.003}, {2, 0.005}, {0, 0.001}});
  EXPECT_NEAR(f.base_s, 0.001, 1e-12);
  EXPECT_NEAR(f.per_k_s, 0.002, 1e-12);
  EXPECT_EQ(f.n, 4u);
  const CostFit same = fit_cost({{0, 0.002}, {0, 0.004}});  // one size: the mean, nothing per item
  EXPECT_NEAR(same.base_s, 0.003, 1e-12);
  EXPECT_EQ(same.per_k_s, 0.0);
}

}  // namespace
}  // namespace evade::closedloop
