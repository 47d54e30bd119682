// What authentication costs per message (lib/bus/auth.h): signing and
// checking a CMD_VEL (the smallest) and an OBSTACLE_PREDICTIONS of 64
// tracks x 30 steps (the largest signed message evade sends).
#include <benchmark/benchmark.h>

#include <memory>

#include "bus/auth.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/prediction_list_t.hpp"

namespace {

using evade::bus::HmacAuth;

std::vector<uint8_t> message(bool large) {
  if (!large) return evade::bus::encode(evade::cmd_vel_t{});
  evade::prediction_list_t p{};
  p.horizon = 30;
  for (int i = 0; i < 64; ++i) {
    evade::track_prediction_t t{};
    t.id = i;
    t.horizon = p.horizon;
    for (auto* v : {&t.x, &t.y, &t.a, &t.b, &t.theta, &t.sigma}) v->assign(p.horizon, 0.5);
    p.tracks.push_back(t);
  }
  p.num_tracks = static_cast<int32_t>(p.tracks.size());
  return evade::bus::encode(p);
}

void BM_Sign(benchmark::State& state) {
  HmacAuth signer(std::vector<uint8_t>(32, 7), "planner", 2.0);
  const auto unsigned_msg = message(state.range(0) != 0);
  int64_t now = 0;
  for (auto _ : state) {
    auto data = unsigned_msg;
    signer.sign("OBSTACLE_PREDICTIONS", ++now, &data);
    benchmark::DoNotOptimize(data.data());
  }
  state.SetLabel(std::to_string(unsigned_msg.size()) + " bytes");
}
BENCHMARK(BM_Sign)->Arg(0)->Arg(1);

void BM_Verify(benchmark::State& state) {
  HmacAuth signer(std::vector<uint8_t>(32, 7), "planner", 2.0);
  std::vector<std::vector<uint8_t>> signed_msgs;
  for (int i = 0; i < 1000; ++i) {
    auto d = message(state.range(0) != 0);
    signer.sign("OBSTACLE_PREDICTIONS", i + 1, &d);
    signed_msgs.push_back(std::move(d));
  }
  std::unique_ptr<HmacAuth> receiver;
  size_t i = 0;
  for (auto _ : state) {
    if (i % signed_msgs.size() == 0) {  // a fresh receiver per round: each message is new to it
      state.PauseTiming();
      receiver = std::make_unique<HmacAuth>(std::vector<uint8_t>(32, 7), "predictor", 2.0);
      state.ResumeTiming();
    }
    const auto& d = signed_msgs[i++ % signed_msgs.size()];
    if (receiver->verify("OBSTACLE_PREDICTIONS", d.data(), d.size(), 500) != evade::bus::AuthVerdict::kOk)
      state.SkipWithError("a signed message did not verify");
  }
}
BENCHMARK(BM_Verify)->Arg(0)->Arg(1);

}  // namespace

BENCHMARK_MAIN();
