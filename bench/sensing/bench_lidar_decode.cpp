// LiDAR decode throughput against the sensors' real packet rates.
//   VLP-16, single return: 754 packets/s (12 blocks x 110.592 us = 1327 us each).
//   RS-Helios, single return: 1500 packets/s (12 blocks x 55.56 us).
// `x_real_time` = packets decoded per second / the sensor's packet rate, on
// one core; the goal is >= 100.
#include <benchmark/benchmark.h>

#include <cmath>

#include "sensing/lidar_decoder.h"
#include "sensing/lidar_driver_core.h"
#include "sensing/packet_sources.h"
#include "sensing/rs_helios.h"
#include "sensing/vlp16.h"
#include "synthetic.h"

namespace {

using namespace evade::sensing;

constexpr double kVlp16PacketsPerSecond = 1e6 / (12 * vlp16::kBlockPeriodUs);
constexpr double kHeliosPacketsPerSecond = 1e6 / (12 * rs_helios::kBlockPeriodUs);

void rate_counters(benchmark::State& state, int64_t packets, double sensor_rate) {
  state.counters["packets_per_s"] = benchmark::Counter(static_cast<double>(packets), benchmark::Counter::kIsRate);
  state.counters["x_real_time"] =
      benchmark::Counter(static_cast<double>(packets) / sensor_rate, benchmark::Counter::kIsRate);
}

// One revolution of synthetic packets (every laser returns: the worst case).
std::vector<testing::SyntheticPacket> vlp16_stream(int n) {
  testing::SyntheticVlp16 s;
  std::vector<testing::SyntheticPacket> v;
  for (int k = 0; k < n; ++k) v.push_back(s.packet(k));
  return v;
}

void BM_Vlp16DecodePacket(benchmark::State& state) {
  auto packets = vlp16_stream(76);
  std::vector<LidarReturn> out;
  out.reserve(384);
  vlp16::DecodeOptions opt;
  int64_t n = 0;
  for (auto _ : state) {
    out.clear();
    const auto& p = packets[static_cast<size_t>(n % 76)];
    vlp16::decode_packet(p.bytes.data(), p.bytes.size(), opt, &out, nullptr);
    benchmark::DoNotOptimize(out.data());
    ++n;
  }
  rate_counters(state, n, kVlp16PacketsPerSecond);
}
BENCHMARK(BM_Vlp16DecodePacket);

// Packets -> pointcloud_t revolutions (decode, time stamps, cut).
void BM_Vlp16Revolutions(benchmark::State& state) {
  auto packets = vlp16_stream(754);
  LidarDecoderParams p;
  p.min_range_m = 0.0;
  p.max_range_m = 100.0;
  p.self_filter = false;
  LidarDecoder dec(p, nullptr);
  std::vector<Revolution> out;
  int64_t n = 0;
  for (auto _ : state) {
    const auto& pk = packets[static_cast<size_t>(n % 754)];
    dec.feed(pk.bytes.data(), pk.bytes.size(), pk.sensor_utime + 1500, &out);
    if (!out.empty()) out.clear();
    ++n;
  }
  rate_counters(state, n, kVlp16PacketsPerSecond);
}
BENCHMARK(BM_Vlp16Revolutions);

// The whole core: decode, assemble, LCM-encode LIDAR_POINTS and LIDAR_SCAN.
class NullSink : public evade::bus::Sink {
 public:
  void publish(const std::string&, int64_t, std::vector<uint8_t> data) override { bytes += data.size(); }
  size_t bytes = 0;
};

void BM_Vlp16CoreWithLcmEncoding(benchmark::State& state) {
  auto packets = vlp16_stream(754);
  auto root = evade::config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  LidarDriverCore core(LidarDriverParams::from_config(root), LidarDriverCore::Source::kPackets);
  core.set_measure_latency(false);
  NullSink sink;
  core.attach(&sink);
  int64_t n = 0;
  for (auto _ : state) {
    const auto& pk = packets[static_cast<size_t>(n % 754)];
    core.input(pk.sensor_utime + 1500, [&] { core.on_packet(pk.bytes.data(), pk.bytes.size()); });
    ++n;
  }
  benchmark::DoNotOptimize(sink.bytes);
  rate_counters(state, n, kVlp16PacketsPerSecond);
}
BENCHMARK(BM_Vlp16CoreWithLcmEncoding);

// The real capture (84 packets, many empty sky returns), looped.
void BM_Vlp16RealSample(benchmark::State& state) {
  std::vector<UdpDatagram> data;
  try {
    PcapUdpReader r(std::string(EVADE_SOURCE_DIR) + "/test/data/vlp16_sample.pcap");
    UdpDatagram d;
    while (r.next(&d))
      if (d.payload.size() == vlp16::kPacketSize) data.push_back(d);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  LidarDecoderParams p;
  p.min_range_m = 0.0;
  p.max_range_m = 200.0;
  p.self_filter = false;
  LidarDecoder dec(p, nullptr);
  std::vector<Revolution> out;
  int64_t n = 0, t = 0;
  for (auto _ : state) {
    const auto& d = data[static_cast<size_t>(n) % data.size()];
    t += 1327;
    dec.feed(d.payload.data(), d.payload.size(), t, &out);
    if (!out.empty()) out.clear();
    ++n;
  }
  rate_counters(state, n, kVlp16PacketsPerSecond);
}
BENCHMARK(BM_Vlp16RealSample);

void BM_RsHeliosRevolutions(benchmark::State& state) {
  rs_helios::DifopEncoder de;
  for (int c = 0; c < rs_helios::kChannels; ++c) de.vertical_deg[c] = -55.0 + 70.0 * c / 31.0;
  auto difop = de.encode();
  std::vector<std::array<uint8_t, rs_helios::kPacketSize>> packets;
  const double deg_per_block = 360.0 * 10.0 * rs_helios::kBlockPeriodUs * 1e-6;
  for (int k = 0; k < 1500; ++k) {
    rs_helios::MsopEncoder m;
    for (int b = 0; b < 12; ++b) {
      m.blocks[b].azimuth_deg = std::fmod((k * 12 + b) * deg_per_block, 360.0);
      for (int c = 0; c < 32; ++c) m.blocks[b].distance_m[c] = 12.0;
    }
    m.utc_us = 1'700'000'000'000'000LL + std::llround(k * 12 * rs_helios::kBlockPeriodUs);
    packets.push_back(m.encode());
  }
  LidarDecoderParams p;
  p.min_range_m = 0.0;
  p.max_range_m = 200.0;
  p.self_filter = false;
  p.model = LidarModel::kRsHelios;
  LidarDecoder dec(p, nullptr);
  std::vector<Revolution> out;
  dec.feed(difop.data(), difop.size(), 0, &out);
  int64_t n = 0;
  for (auto _ : state) {
    const auto& pk = packets[static_cast<size_t>(n % 1500)];
    dec.feed(pk.data(), pk.size(), 1'700'000'000'000'000LL + n * 667, &out);
    if (!out.empty()) out.clear();
    ++n;
  }
  rate_counters(state, n, kHeliosPacketsPerSecond);
}
BENCHMARK(BM_RsHeliosRevolutions);

}  // namespace

BENCHMARK_MAIN();
