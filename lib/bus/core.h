// The one interface every evade process core implements.
//
// A Core knows nothing of sockets or clocks. It declares which channels it
// reads (subscribe) and which periodic work it does (every), gets decoded
// messages together with the bus time `now()` (the receive time live, the
// event timestamp in a log), and hands messages to publish back to whichever
// adapter runs it: LiveBus (LCM udpm), LogReplay (an lcm-logger file, in
// process, deterministic) or MemoryBus (tests). Same core, same outputs.
//
// Every core gets a HEALTH heartbeat for free: its name, a sequence number,
// the age and count of each input channel, its output rate, handler latency
// and any counters it keeps with count().
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace evade::bus {

class ClockSync;  // clock_sync.h

inline constexpr int64_t kNever = std::numeric_limits<int64_t>::max();
inline constexpr const char* kHealthChannel = "HEALTH";

// Signs what a core publishes and checks what it receives, for the
// channels that carry authentication (lib/bus/auth.h). Set on a core by
// whoever runs it (process_main, base_driver's main, the lockstep loop,
// process-replay); the core's own code never sees keys, codes or
// sequence numbers. Verdicts other than kOk are counted in HEALTH under
// verdict_name() and the message is dropped before it is decoded.
enum class AuthVerdict { kOk, kUnsigned, kBadMac, kOldSeq, kOutsideWindow };
const char* verdict_name(AuthVerdict v);
class Authenticator {
 public:
  virtual ~Authenticator() = default;
  // Signs `data` (an encoded message) in place for `channel`, published at
  // bus time `now`; channels without authentication are left as they are.
  // False when the message cannot be signed (it carries no auth fields).
  virtual bool sign(const std::string& channel, int64_t now, std::vector<uint8_t>* data) = 0;
  // kOk for a channel without authentication.
  virtual AuthVerdict verify(const std::string& channel, const uint8_t* data, size_t size, int64_t now) = 0;
};

// Where a core's output goes. `now` is the bus time at which it was published.
class Sink {
 public:
  virtual ~Sink() = default;
  virtual void publish(const std::string& channel, int64_t now, std::vector<uint8_t> data) = 0;
};

class Core {
 public:
  explicit Core(std::string name, int64_t health_period_us = 1'000'000);
  virtual ~Core() = default;
  Core(const Core&) = delete;
  Core& operator=(const Core&) = delete;

  const std::string& name() const { return name_; }

  // ---- used by adapters ----
  std::vector<std::string> channels() const;
  void attach(Sink* sink) { sink_ = sink; }
  // Decodes one message and calls its handler at bus time `now`. Malformed
  // messages are counted per channel and reported in HEALTH; returns false.
  bool deliver(const std::string& channel, const uint8_t* data, size_t size, int64_t now);
  // Fires every timer due at or before `now`, each at its own deadline (the
  // callback's now()), in deadline order. A timer more than kMaxCatchUp
  // periods behind (a stalled process) skips to `now` instead of bursting.
  void advance_to(int64_t now);
  // Fires the single earliest timer due at or before `now`; false if none.
  bool fire_next(int64_t now);
  static constexpr int64_t kMaxCatchUp = 10;
  int64_t next_deadline() const;
  // Timers start at the first bus time the core sees: they fire then.
  void arm_timers(int64_t now);
  // Runs external input (a UDP packet, serial bytes) at bus time `now`,
  // counted in the latency figures like a message handler. A non-empty
  // `source` (e.g. "udp:2368", "serial") is reported in HEALTH among the
  // inputs, with its count and age, like a channel.
  void input(int64_t now, const std::function<void()>& fn, const std::string& source = "");
  // Latency uses a steady clock; off for deterministic log replay.
  void set_measure_latency(bool on) { measure_latency_ = on; }
  // Bus time of the callback being run.
  int64_t now() const { return now_; }

  // Counters by name (also what HEALTH reports).
  int64_t counter(const std::string& name) const;
  // A counter the adapter or main sets from outside the core (e.g.
  // bus_exposed_interfaces at start), reported in HEALTH like count().
  void note(const std::string& name, int64_t n = 1) { count(name, n); }
  // Signs outputs and checks inputs from now on (not owned; nullptr: off).
  void set_authenticator(Authenticator* auth) { auth_ = auth; }
  // Answers clock-offset requests on CLOCK_SYNC and, when `sync` requests,
  // sends its own and reports the estimate among the HEALTH counters
  // (clock_sync.h). Before the core is added to a bus; not owned. The
  // channel is handled here, not listed among the inputs in HEALTH.
  void set_clock_sync(ClockSync* sync);

 protected:
  template <class Msg>
  void subscribe(const std::string& channel, std::function<void(const Msg&)> handler);
  void every(int64_t period_us, std::function<void()> fn);
  template <class Msg>
  void publish(const std::string& channel, const Msg& msg);
  void publish_raw(const std::string& channel, std::vector<uint8_t> data);
  void count(const std::string& name, int64_t n = 1);

 private:
  struct Input {
    std::function<bool(const uint8_t*, size_t)> decode_and_handle;  // false = malformed
    int64_t received = 0;
    int64_t malformed = 0;
    int64_t last_now = -1;
  };
  struct Timer {
    int64_t period_us;
    int64_t next;  // -1 = not armed yet (armed at the first bus time seen)
    std::function<void()> fn;
  };
  void publish_health();
  void on_clock_sync(const uint8_t* data, size_t size);
  void refresh_clock_counters();
  void run_measured(const std::function<void()>& fn);

  std::string name_;
  Sink* sink_ = nullptr;
  Authenticator* auth_ = nullptr;
  ClockSync* clock_sync_ = nullptr;
  std::map<std::string, Input> inputs_;
  std::map<std::string, Input> external_;  // non-LCM inputs: reported, never subscribed
  std::vector<Timer> timers_;
  std::map<std::string, int64_t> counters_;
  int64_t now_ = 0;
  int64_t advanced_to_ = 0;  // the latest bus time an adapter advanced the timers to
  bool measure_latency_ = true;
  // health accounting since the last heartbeat
  int64_t health_seq_ = 0;
  int64_t outputs_since_ = 0;
  int64_t last_health_now_ = -1;
  double latency_sum_us_ = 0.0;
  double latency_max_us_ = 0.0;
  int64_t latency_n_ = 0;
};

// ---- encoding helpers for lcm-gen types ----
template <class Msg>
std::vector<uint8_t> encode(const Msg& msg) {
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

// True when the bytes are a structurally valid evade message (see
// LcmSchema::check); defined in lcm_schema.cpp.
bool well_formed(const uint8_t* data, size_t size);

// Decodes; false when the bytes are not a valid Msg (wrong fingerprint,
// truncated, or lengths that do not fit the bytes). The structure is
// checked first, so a malformed length never makes lcm-gen's decoder
// allocate more than the message holds.
template <class Msg>
bool decode(const uint8_t* data, size_t size, Msg* out) {
  if (size < 8 || !well_formed(data, size)) return false;
  try {
    return out->decode(data, 0, static_cast<int>(size)) == static_cast<int>(size);
  } catch (const std::exception&) {
    return false;
  }
}

template <class Msg>
void Core::subscribe(const std::string& channel, std::function<void(const Msg&)> handler) {
  inputs_[channel].decode_and_handle = [handler](const uint8_t* data, size_t size) {
    Msg msg;
    if (!decode(data, size, &msg)) return false;
    handler(msg);
    return true;
  };
}

template <class Msg>
void Core::publish(const std::string& channel, const Msg& msg) {
  publish_raw(channel, encode(msg));
}

}  // namespace evade::bus
