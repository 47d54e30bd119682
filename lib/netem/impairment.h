// What netem's "loss L delay D J" does to each packet of the bus, decided
// per packet: dropped with probability L, otherwise held for a delay drawn
// uniformly from [D - J, D + J] (at least 0), so packets overtake one
// another as they do under netem's jitter (unless `reorder` is off). Packets of exempt channels pass
// at once (SIM_TRUTH: the simulator's ground truth is not robot traffic,
// and the metrics and the run monitor read it). Counts, per channel,
// packets and messages seen and dropped (a message of several fragments is
// lost when any of them is). No socket, no clock: the caller gives the time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>

namespace evade::netem {

struct ImpairmentParams {
  double loss = 0.05;       // probability a packet is dropped
  double delay_s = 0.020;   // mean delay
  double jitter_s = 0.020;  // half-width of the uniform delay
  uint64_t seed = 1;
  std::set<std::string> exempt = {"SIM_TRUTH"};
  // netem's jitter lets packets overtake one another; false keeps them in
  // their order (each released no earlier than the one before it).
  bool reorder = true;
};

struct Verdict {
  bool drop = false;
  double release_s = 0.0;  // when to let it through (not dropped)
};

struct ChannelStats {
  int64_t packets = 0, packets_dropped = 0;
  int64_t messages = 0, messages_lost = 0;  // messages whose packets were seen; with a packet dropped
  double delay_s_sum = 0.0;                 // over packets let through
};

class Impairment {
 public:
  // Throws std::invalid_argument for a loss outside [0, 1] or a negative
  // delay or jitter.
  explicit Impairment(const ImpairmentParams& p);
  Verdict on_packet(const uint8_t* data, size_t n, double now_s);
  const std::map<std::string, ChannelStats>& stats() const { return stats_; }
  // {"loss":..,"delay_s":..,"jitter_s":..,"channels":{"NAME":{...}}}
  std::string stats_json() const;

 private:
  struct Open {
    std::string channel;
    bool lost = false;
  };
  ImpairmentParams p_;
  std::mt19937_64 rng_;
  double last_release_s_ = 0.0;                         // of the impaired packets (for reorder = false)
  std::map<std::pair<uint16_t, uint32_t>, Open> open_;  // fragmented messages being seen, by sender port and seqno
  std::map<std::string, ChannelStats> stats_;
};

}  // namespace evade::netem
