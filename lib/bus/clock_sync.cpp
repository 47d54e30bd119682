#include "bus/clock_sync.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace evade::bus {

ClockSyncParams ClockSyncParams::from_config(const config::Node& root) {
  return config::load<ClockSyncParams>(root.section("bus").section("clock_sync"));
}

OffsetSample ntp_sample(int64_t t1, int64_t t2, int64_t t3, int64_t t4) {
  OffsetSample s;
  // Halves of each difference first: no overflow for any bus times.
  s.offset_us = (t2 - t1) / 2 + (t3 - t4) / 2;
  s.rtt_us = (t4 - t1) - (t3 - t2);
  s.at_us = t4;
  return s;
}

ClockSync::ClockSync(std::string name, const ClockSyncParams& params, bool requests)
    : name_(std::move(name)),
      requests_(requests),
      period_us_(std::llround(params.period_s * 1e6)),
      window_(static_cast<size_t>(params.window_samples)),
      max_offset_us_(std::llround(params.max_offset_s * 1e6)) {}

evade::clock_sync_t ClockSync::request(int64_t now) {
  evade::clock_sync_t m;
  m.utime = now;
  m.response = false;
  m.requester = name_;
  m.seq = ++seq_;
  m.t1_us = now;
  m.t2_us = 0;
  m.t3_us = 0;
  pending_[m.seq] = now;
  while (pending_.size() > window_) pending_.erase(pending_.begin());
  return m;
}

std::optional<evade::clock_sync_t> ClockSync::on_message(const evade::clock_sync_t& msg, int64_t now) {
  if (!msg.response) {
    if (msg.requester == name_) return std::nullopt;  // our own, looped back
    evade::clock_sync_t a = msg;
    a.utime = now;
    a.response = true;
    a.responder = name_;
    a.t2_us = now;
    a.t3_us = now;  // answered in the same handler
    return a;
  }
  if (msg.requester != name_ || !requests_) return std::nullopt;  // another's answer
  auto it = pending_.find(msg.seq);
  const bool sane = msg.t3_us >= msg.t2_us && now >= msg.t1_us && !msg.responder.empty();
  if (it == pending_.end() || it->second != msg.t1_us || !sane) {
    ++rejected_;
    return std::nullopt;
  }
  const OffsetSample s = ntp_sample(msg.t1_us, msg.t2_us, msg.t3_us, now);
  if (s.rtt_us < 0) {  // the answerer took longer than the whole exchange
    ++rejected_;
    return std::nullopt;
  }
  auto& kept = samples_[msg.responder];
  kept.push_back(s);
  while (kept.size() > window_) kept.pop_front();
  judge(now);
  return std::nullopt;
}

namespace {
// The smallest the true offset can be: the estimate is off by at most half
// the round trip.
int64_t least_offset(const ClockSync::Estimate& e) { return std::llabs(e.offset_us) - e.rtt_us / 2; }
}  // namespace

std::optional<ClockSync::Estimate> ClockSync::estimate(const std::deque<OffsetSample>& s) const {
  const OffsetSample* best = nullptr;
  for (const auto& x : s)
    if (!best || x.rtt_us < best->rtt_us) best = &x;
  if (!best) return std::nullopt;
  return Estimate{"", best->offset_us, best->rtt_us};
}

std::optional<ClockSync::Estimate> ClockSync::worst(int64_t now) const {
  std::optional<Estimate> w;
  const int64_t heard_within = static_cast<int64_t>(window_) * period_us_;
  for (const auto& [peer, s] : samples_) {
    if (s.empty() || now - s.back().at_us > heard_within) continue;
    auto e = estimate(s);
    if (!e) continue;
    e->peer = peer;
    if (!w || least_offset(*e) > least_offset(*w)) w = e;
  }
  return w;
}

void ClockSync::judge(int64_t now) {
  const auto w = worst(now);
  const bool beyond = w && least_offset(*w) > max_offset_us_;
  if (beyond) ++exceeded_;
  if (beyond == beyond_ || !on_warning) {
    beyond_ = beyond;
    return;
  }
  beyond_ = beyond;
  char line[256];
  if (beyond)
    std::snprintf(line, sizeof line,
                  "warning: clock offset to %s is %+.1f ms (round trip %.1f ms), beyond bus.clock_sync.max_offset_s "
                  "%.1f ms: staleness checks compare times across hosts; synchronise the clocks (chrony or PTP)",
                  w->peer.c_str(), w->offset_us * 1e-3, w->rtt_us * 1e-3, max_offset_us_ * 1e-3);
  else
    std::snprintf(line, sizeof line, "clock offset back within %.1f ms", max_offset_us_ * 1e-3);
  on_warning(line);
}

std::map<std::string, int64_t> ClockSync::counters(int64_t now) const {
  std::map<std::string, int64_t> c;
  int64_t peers = 0;
  const int64_t heard_within = static_cast<int64_t>(window_) * period_us_;
  for (const auto& [peer, s] : samples_) peers += !s.empty() && now - s.back().at_us <= heard_within;
  c["clock_sync_peers"] = peers;
  c["clock_offset_exceeded"] = exceeded_;
  c["clock_sync_rejected"] = rejected_;
  if (const auto w = worst(now)) {
    c["clock_offset_us"] = w->offset_us;
    c["clock_rtt_us"] = w->rtt_us;
  }
  return c;
}

}  // namespace evade::bus
