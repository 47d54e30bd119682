#include "bus/core.h"

#include <algorithm>
#include <chrono>

#include "bus/clock_sync.h"
#include "evade/health_t.hpp"

namespace evade::bus {

Core::Core(std::string name, int64_t health_period_us) : name_(std::move(name)) {
  every(health_period_us, [this] { publish_health(); });
}

std::vector<std::string> Core::channels() const {
  std::vector<std::string> out;
  for (const auto& [ch, in] : inputs_) out.push_back(ch);
  if (clock_sync_ && !inputs_.count(kClockSyncChannel)) out.push_back(kClockSyncChannel);
  return out;
}

void Core::set_clock_sync(ClockSync* sync) {
  clock_sync_ = sync;
  // t1 is when the request leaves: a timer that fires late (a busy
  // process) runs at its deadline, now_, but is sent at advanced_to_.
  if (sync && sync->requests())
    every(sync->period_us(),
          [this] { publish(kClockSyncChannel, clock_sync_->request(std::max(now_, advanced_to_))); });
}

void Core::on_clock_sync(const uint8_t* data, size_t size) {
  evade::clock_sync_t msg;
  if (!decode(data, size, &msg)) {
    count("clock_sync_malformed");
    return;
  }
  if (auto answer = clock_sync_->on_message(msg, now_)) publish(kClockSyncChannel, *answer);
  refresh_clock_counters();
}

void Core::refresh_clock_counters() {
  if (!clock_sync_ || !clock_sync_->requests()) return;
  counters_.erase("clock_offset_us");  // absent while no process answers
  counters_.erase("clock_rtt_us");
  for (const auto& [name, value] : clock_sync_->counters(now_)) counters_[name] = value;
}

void Core::run_measured(const std::function<void()>& fn) {
  if (!measure_latency_) {
    fn();
    return;
  }
  auto t0 = std::chrono::steady_clock::now();
  fn();
  double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  latency_sum_us_ += us;
  latency_max_us_ = std::max(latency_max_us_, us);
  ++latency_n_;
}

const char* verdict_name(AuthVerdict v) {
  switch (v) {
    case AuthVerdict::kOk:
      return "auth_ok";
    case AuthVerdict::kUnsigned:
      return "auth_unsigned";
    case AuthVerdict::kBadMac:
      return "auth_bad_mac";
    case AuthVerdict::kOldSeq:
      return "auth_old_seq";
    case AuthVerdict::kOutsideWindow:
      return "auth_outside_window";
  }
  return "auth_unknown";
}

bool Core::deliver(const std::string& channel, const uint8_t* data, size_t size, int64_t now) {
  if (clock_sync_ && channel == kClockSyncChannel && !inputs_.count(channel)) {
    now_ = now;
    on_clock_sync(data, size);
    return true;
  }
  auto it = inputs_.find(channel);
  if (it == inputs_.end()) return false;
  now_ = now;
  Input& in = it->second;
  in.received++;
  if (auth_) {
    const AuthVerdict v = auth_->verify(channel, data, size, now);
    if (v != AuthVerdict::kOk) {
      count(verdict_name(v));
      return false;
    }
  }
  in.last_now = now;  // the input's age: that of the last message it may act on
  bool ok = true;
  run_measured([&] { ok = in.decode_and_handle(data, size); });
  if (!ok) in.malformed++;
  return ok;
}

void Core::input(int64_t now, const std::function<void()>& fn, const std::string& source) {
  now_ = now;
  if (!source.empty()) {
    Input& in = external_[source];
    in.received++;
    in.last_now = now;
  }
  run_measured(fn);
}

void Core::every(int64_t period_us, std::function<void()> fn) {
  timers_.push_back(Timer{std::max<int64_t>(period_us, 1), -1, std::move(fn)});
}

int64_t Core::next_deadline() const {
  int64_t d = kNever;
  for (const auto& t : timers_) d = std::min(d, t.next < 0 ? kNever : t.next);
  return d;
}

void Core::arm_timers(int64_t now) {
  for (auto& t : timers_) {
    if (t.next < 0) t.next = now;
    // Stalled (a gap in a log, a suspended process): the missed ticks are
    // skipped, and it fires at `now` after the timers that are merely due,
    // so the bus time seen by callbacks never runs backwards.
    if (now - t.next > kMaxCatchUp * t.period_us) t.next = now;
  }
}

bool Core::fire_next(int64_t now) {
  advanced_to_ = std::max(advanced_to_, now);
  arm_timers(now);
  Timer* due = nullptr;
  for (auto& t : timers_)
    if (t.next <= now && (!due || t.next < due->next)) due = &t;
  if (!due) return false;
  now_ = due->next;
  due->next += due->period_us;
  run_measured(due->fn);
  return true;
}

void Core::advance_to(int64_t now) {
  while (fire_next(now)) {
  }
}

void Core::publish_raw(const std::string& channel, std::vector<uint8_t> data) {
  if (auth_ && !auth_->sign(channel, now_, &data)) {
    count("auth_sign_failed");
    return;
  }
  ++outputs_since_;
  if (sink_) sink_->publish(channel, now_, std::move(data));
}

void Core::count(const std::string& name, int64_t n) { counters_[name] += n; }

int64_t Core::counter(const std::string& name) const {
  auto it = counters_.find(name);
  return it == counters_.end() ? 0 : it->second;
}

void Core::publish_health() {
  refresh_clock_counters();
  evade::health_t h;
  h.utime = now_;
  h.name = name_;
  h.seq = health_seq_++;
  double elapsed_s = last_health_now_ < 0 ? 0.0 : (now_ - last_health_now_) * 1e-6;
  h.output_rate_hz = elapsed_s > 0.0 ? outputs_since_ / elapsed_s : 0.0;
  h.latency_us_mean = latency_n_ > 0 ? latency_sum_us_ / latency_n_ : 0.0;
  h.latency_us_max = latency_max_us_;
  for (const auto* inputs : {&inputs_, &external_})
    for (const auto& [ch, in] : *inputs) {
      evade::health_channel_t c;
      c.channel = ch;
      c.received = in.received;
      c.malformed = in.malformed;
      c.age_us = in.last_now < 0 ? -1 : now_ - in.last_now;
      h.inputs.push_back(c);
    }
  h.num_inputs = static_cast<int32_t>(h.inputs.size());
  for (const auto& [name, value] : counters_) {
    evade::health_counter_t c;
    c.name = name;
    c.value = value;
    h.counters.push_back(c);
  }
  h.num_counters = static_cast<int32_t>(h.counters.size());
  last_health_now_ = now_;
  outputs_since_ = 0;
  latency_sum_us_ = 0.0;
  latency_max_us_ = 0.0;
  latency_n_ = 0;
  if (sink_) sink_->publish(kHealthChannel, now_, encode(h));
}

}  // namespace evade::bus
