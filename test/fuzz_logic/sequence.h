// Logic fuzzing (issue 20): a core fed random but well-formed message
// sequences. The fuzzer's bytes choose what happens next (a message on one
// of the core's channels, timers advancing, bus time jumping back or
// forward by up to a minute) and every field of every message: mostly
// plausible values, now and then NaN, infinities, 1e300, empty or huge
// arrays within the limits a sender could produce, and timestamps from
// INT64_MIN to INT64_MAX. Every message the core publishes is decoded
// generically and must hold finite numbers only (the documented NaN of
// grid_map_t.elevation, "no data", excepted); a crash, a sanitizer report
// or a non-finite output aborts. EVADE_FUZZ_STATS=1 prints each published
// message's channel (and a PLAN's status) on stderr: what a corpus reaches.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "bus/core.h"
#include "bus/lcm_schema.h"

namespace evade::fuzz {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : d_(data), n_(size) {}
  bool empty() const { return i_ >= n_; }
  uint8_t u8() { return i_ < n_ ? d_[i_++] : 0; }
  uint16_t u16() { return static_cast<uint16_t>(u8() | (u8() << 8)); }
  uint32_t u32() { return static_cast<uint32_t>(u16()) | (static_cast<uint32_t>(u16()) << 16); }
  int64_t i64() { return static_cast<int64_t>(static_cast<uint64_t>(u32()) | (static_cast<uint64_t>(u32()) << 32)); }
  bool chance(int one_in) { return u8() % one_in == 0; }
  double unit() { return u16() / 65535.0; }
  double range(double lo, double hi) { return lo + (hi - lo) * unit(); }
  int size(int max) { return max <= 0 ? 0 : static_cast<int>(u16() % (static_cast<unsigned>(max) + 1)); }
  // Mostly within [lo, hi]; one in 16 something a broken sender could send.
  double value(double lo, double hi) {
    if (!chance(16)) return range(lo, hi);
    static const double odd[] = {std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(),
                                 1e300,
                                 -1e300,
                                 0.0,
                                 1e-300};
    return odd[u8() % (sizeof odd / sizeof odd[0])];
  }
  // A message timestamp: half the time `now`, mostly on time (0.2 s late to
  // 0.05 s early), else
  // 2 s late to 0.5 s early, now and then far off or extreme.
  int64_t utime(int64_t now) {
    if (chance(2)) return now;                                            // stamped as it arrives
    if (!chance(3)) return now + static_cast<int64_t>(range(-2e5, 5e4));  // on time
    if (!chance(12)) return now + static_cast<int64_t>(range(-2e6, 5e5));
    static const int64_t odd[] = {std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::min(), 0, -1};
    const uint8_t k = u8() % 6;
    if (k < 4) return odd[k];
    return now + (k == 4 ? 10'000'000 : -60'000'000);
  }

 private:
  const uint8_t* d_;
  size_t n_;
  size_t i_ = 0;
};

// Aborts on any non-finite number in a published message.
class FiniteSink : public bus::Sink {
 public:
  void publish(const std::string& channel, int64_t, std::vector<uint8_t> data) override {
    std::string type;
    auto v = bus::LcmSchema::evade().decode(data.data(), data.size(), &type);
    if (!v) {
      std::fprintf(stderr, "fuzz: %s published an undecodable message\n", channel.c_str());
      std::abort();
    }
    check(*v, channel, type, "");
    ++published;
    if (std::getenv("EVADE_FUZZ_STATS")) {
      const bus::Value* st = channel == "PLAN" ? v->field("status") : nullptr;
      std::fprintf(stderr, "fuzz-stats: %s%s%lld\n", channel.c_str(), st ? " status " : "",
                   st ? static_cast<long long>(st->i) : 0LL);
    }
  }
  int64_t published = 0;

 private:
  static void check(const bus::Value& v, const std::string& channel, const std::string& type, const std::string& path) {
    switch (v.kind) {
      case bus::Value::Kind::Float:
        if (!std::isfinite(v.f)) {
          std::fprintf(stderr, "fuzz: %s (%s) published %s = %g\n", channel.c_str(), type.c_str(), path.c_str(), v.f);
          std::abort();
        }
        break;
      case bus::Value::Kind::Array:
        for (const auto& item : v.items) check(item, channel, type, path + "[]");
        break;
      case bus::Value::Kind::Struct:
        for (const auto& [name, field] : v.fields) {
          if (path.empty() && type.find("grid_map_t") != std::string::npos && name == "elevation") continue;
          check(field, channel, type, path.empty() ? name : path + "." + name);
        }
        break;
      default:
        break;
    }
  }
};

struct Channel {
  std::string name;
  std::function<std::vector<uint8_t>(Bytes&, int64_t now)> make;
};
// Something other than a message (serial bytes, a link event); runs inside
// Core::input at bus time `now`.
using Extra = std::function<void(Bytes&, int64_t now)>;

inline constexpr int64_t kStart = 1'700'000'000'000'000;

// Runs up to max_steps steps of the sequence the bytes describe, after the
// `prelude` messages (delivered at kStart, e.g. a valid route).
inline void run_sequence(bus::Core& core, const std::vector<Channel>& channels, Bytes& in, int max_steps,
                         const std::vector<Extra>& extras = {},
                         const std::vector<std::pair<std::string, std::vector<uint8_t>>>& prelude = {}) {
  FiniteSink sink;
  core.attach(&sink);
  core.set_measure_latency(false);
  int64_t now = kStart;
  for (const auto& [channel, msg] : prelude) core.deliver(channel, msg.data(), msg.size(), now);
  const int ops = static_cast<int>(channels.size() + extras.size()) + 1;
  for (int step = 0; step < max_steps && !in.empty(); ++step) {
    const int op = in.u8() % ops;
    if (op < static_cast<int>(channels.size())) {
      const Channel& c = channels[op];
      const std::vector<uint8_t> msg = c.make(in, now);
      core.deliver(c.name, msg.data(), msg.size(), now);
    } else if (op < static_cast<int>(channels.size() + extras.size())) {
      const Extra& e = extras[op - channels.size()];
      core.input(now, [&] { e(in, now); });
    } else if (!in.chance(8)) {
      now += static_cast<int64_t>(in.range(0, in.chance(4) ? 1e6 : 1e5));  // time passes: timers fire
      core.advance_to(now);
    } else {
      now += static_cast<int64_t>(in.range(-6e7, 6e7));  // the clock jumps, back or forward
      core.advance_to(now);
    }
  }
  core.attach(nullptr);
}

}  // namespace evade::fuzz
