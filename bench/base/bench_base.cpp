// base_driver hot paths: the stream parser's throughput (a 115200-baud
// UART carries at most 11.5 kB/s, so anything in the MB/s is plenty), the
// cost of one motion-status frame through the core (parse, exact-arc
// odometry, ODOMETRY encode), and one 50 Hz command tick.
#include <benchmark/benchmark.h>

#include <vector>

#include "base/base_driver_core.h"

namespace {

using namespace evade::base;

// Discards what the core publishes (the LCM send is not the driver's cost).
class NullSink : public evade::bus::Sink {
 public:
  void publish(const std::string&, int64_t, std::vector<uint8_t> data) override {
    benchmark::DoNotOptimize(data.data());
  }
};

std::vector<uint8_t> status_stream(size_t frames) {
  std::vector<uint8_t> s;
  for (size_t i = 0; i < frames; ++i) {
    FrameBytes f = (i % 2) ? encode(MotionStatus{500, 250}, static_cast<uint8_t>(i))
                           : encode(SystemStatus{0, kControlModeSerial, 246, 0}, static_cast<uint8_t>(i));
    s.insert(s.end(), f.begin(), f.end());
    if (i % 7 == 0) s.push_back(0x00);  // a little noise
  }
  return s;
}

void BM_ParserThroughput(benchmark::State& state) {
  const auto stream = status_stream(5000);
  const size_t chunk = static_cast<size_t>(state.range(0));
  size_t frames = 0;
  for (auto _ : state) {
    StreamParser p;
    for (size_t pos = 0; pos < stream.size(); pos += chunk)
      p.feed(stream.data() + pos, std::min(chunk, stream.size() - pos), [&](const Frame&) { ++frames; });
  }
  benchmark::DoNotOptimize(frames);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * stream.size()));
}
BENCHMARK(BM_ParserThroughput)->Arg(1)->Arg(13)->Arg(64)->Arg(4096);

void BM_MotionStatusToOdometry(benchmark::State& state) {
  BaseDriverCore core{BaseDriverParams{}};
  NullSink sink;
  core.attach(&sink);
  core.set_measure_latency(false);
  core.input(0, [&] { core.on_link_opened(); });
  int64_t t = 0;
  uint8_t count = 0;
  for (auto _ : state) {
    FrameBytes f = encode(MotionStatus{500, 250}, count++);
    t += 20'000;
    core.input(t, [&] { core.on_serial_bytes(f.data(), f.size()); });
  }
  benchmark::DoNotOptimize(core.pose());
}
BENCHMARK(BM_MotionStatusToOdometry);

void BM_CommandTick(benchmark::State& state) {
  BaseDriverCore core{BaseDriverParams{}};
  NullSink sink;
  core.attach(&sink);
  core.set_measure_latency(false);
  core.input(0, [&] { core.on_link_opened(); });
  int64_t t = 0;
  for (auto _ : state) {
    t += 20'000;
    core.advance_to(t);  // the command tick (+ the 10 Hz BASE_STATUS and 1 Hz HEALTH when due)
    auto tx = core.take_tx();
    benchmark::DoNotOptimize(tx.data());
  }
}
BENCHMARK(BM_CommandTick);

}  // namespace

BENCHMARK_MAIN();
