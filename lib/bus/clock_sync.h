// The clock offset between hosts, estimated NTP-style on bus time (issue 19).
//
// When the stack spans two computers, the staleness checks (the planner's
// odometry and predictions ages, base_driver's CMD_VEL age, the signed
// channels' time window) compare a time taken on one host with a time
// taken on the other. Those checks are only as good as the agreement of
// the two clocks, which chrony or PTP keeps; this module measures it.
//
// A requester (the planner) publishes a request on CLOCK_SYNC every
// `period_s`, stamped t1 with its bus time. Every process that answers
// (each process run by process_main) sends back t2, its bus time when the
// request arrived, and t3, its bus time when it answered; the requester
// notes t4 when the answer arrives. Then, as in NTP (RFC 5905):
//   offset = ((t2 - t1) + (t3 - t4)) / 2   (the answerer's clock minus ours)
//   round trip = (t4 - t1) - (t3 - t2)
// With a symmetric path the offset is exact; otherwise its error is at
// most half the round trip. A sample delayed on one side (a busy
// process handles the message late, a timer fires late) has a longer
// round trip, so per answering process the estimate is the sample with the
// least round trip among the last `window_samples` (NTP's clock filter).
// The true offset then lies within half that round trip of the estimate,
// so an offset counts as beyond the bound only when even its least
// possible size, |offset| - round trip / 2, is (a sample taken while a
// process was busy neither warns nor counts). The reported offset is that
// of the process whose least possible offset is largest among those heard
// within `window_samples` periods: on one host it is near zero, across
// hosts it is the hosts' offset.
//
// Like a core, it never reads a clock: every call is given the bus time.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "config/config.h"
#include "config/fields.h"
#include "evade/clock_sync_t.hpp"

namespace evade::bus {

inline constexpr const char* kClockSyncChannel = "CLOCK_SYNC";

// The `bus.clock_sync` section of the robot configuration.
struct ClockSyncParams {
  double period_s = 1.0;       // a request every period (the requester)
  int window_samples = 8;      // samples kept per answering process
  double max_offset_s = 0.02;  // beyond: the requester warns and counts

  template <class V>
  void fields(V& v) {
    v.field("period_s", period_s, config::between(0.1, 60.0));
    v.field("window_samples", window_samples, config::between(1, 64));
    v.field("max_offset_s", max_offset_s, config::between(0.0001, 10.0));
  }
  // root = the whole configuration; reads `bus.clock_sync`.
  static ClockSyncParams from_config(const config::Node& root);
};

// One exchange, in microseconds of bus time.
struct OffsetSample {
  int64_t offset_us = 0;  // the answerer's clock minus the requester's
  int64_t rtt_us = 0;     // round trip, the answerer's time excluded
  int64_t at_us = 0;      // t4: when the answer arrived (requester's clock)
};
// t1 request sent, t2 request received, t3 answer sent, t4 answer received.
OffsetSample ntp_sample(int64_t t1, int64_t t2, int64_t t3, int64_t t4);

class ClockSync {
 public:
  // `name`: the process's name (requests carry it; its own are not
  // answered). `requests`: this process asks (and estimates); every
  // ClockSync answers the others' requests.
  ClockSync(std::string name, const ClockSyncParams& params, bool requests);

  bool requests() const { return requests_; }
  int64_t period_us() const { return period_us_; }

  // A new request sent at bus time `now`.
  evade::clock_sync_t request(int64_t now);
  // A message on CLOCK_SYNC at bus time `now`: the answer to publish for a
  // request of another process; for an answer to one of this process's
  // requests, a new sample (nullopt). Anything else is ignored: this
  // process's own requests, answers to others, answers to no pending
  // request or with impossible times (counted in `rejected`).
  std::optional<evade::clock_sync_t> on_message(const evade::clock_sync_t& msg, int64_t now);

  struct Estimate {
    std::string peer;
    int64_t offset_us = 0;
    int64_t rtt_us = 0;
  };
  // Among the processes heard within `window_samples` periods of `now`,
  // the estimate whose least possible offset (least_offset) is largest;
  // nullopt when none is.
  std::optional<Estimate> worst(int64_t now) const;
  // HEALTH counters: clock_offset_us and clock_rtt_us (of worst(), absent
  // without one), clock_sync_peers, clock_offset_exceeded (answers after
  // which worst()'s least possible offset was beyond max_offset_s),
  // clock_sync_rejected.
  std::map<std::string, int64_t> counters(int64_t now) const;

  // Called with one line when the offset goes beyond the bound and when
  // it comes back (the process prints it).
  std::function<void(const std::string&)> on_warning;

 private:
  std::optional<Estimate> estimate(const std::deque<OffsetSample>& s) const;
  void judge(int64_t now);

  std::string name_;
  bool requests_;
  int64_t period_us_;
  size_t window_;
  int64_t max_offset_us_;
  int64_t seq_ = 0;
  std::map<int64_t, int64_t> pending_;  // seq -> t1 of the last `window_samples` requests
  std::map<std::string, std::deque<OffsetSample>> samples_;
  int64_t exceeded_ = 0;
  int64_t rejected_ = 0;
  bool beyond_ = false;
};

}  // namespace evade::bus
