#include "netem/impairment.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "netem/lcm_packet.h"

namespace evade::netem {

Impairment::Impairment(const ImpairmentParams& p) : p_(p), rng_(p.seed) {
  if (!(p.loss >= 0 && p.loss <= 1)) throw std::invalid_argument("loss must be within [0, 1]");
  if (!(p.delay_s >= 0) || !(p.jitter_s >= 0)) throw std::invalid_argument("delay and jitter must be >= 0");
}

Verdict Impairment::on_packet(const uint8_t* data, size_t n, double now_s) {
  const auto pkt = parse_lcm_packet(data, n);
  std::string channel = "(not LCM)";
  bool first = true, last = true;
  Open* open = nullptr;
  if (pkt) {
    channel = pkt->channel;
    if (pkt->fragmented) {
      const auto key = std::make_pair(pkt->src_port, pkt->seqno);
      if (pkt->fragment == 0) {
        if (open_.size() > 4096) open_.clear();  // fragments that never completed; bounded
        open_[key] = Open{pkt->channel, false};
      }
      auto it = open_.find(key);
      channel = it == open_.end() ? "(fragment of an unseen message)" : it->second.channel;
      if (it != open_.end()) open = &it->second;
      first = pkt->fragment == 0;
      last = pkt->fragment + 1 == pkt->fragments;
    }
  }
  ChannelStats& s = stats_[channel];
  ++s.packets;
  if (first) ++s.messages;
  Verdict v{false, now_s};
  const bool impaired = pkt && !p_.exempt.count(channel);
  if (impaired) {
    v.drop = std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < p_.loss;
    const double d = std::uniform_real_distribution<double>(p_.delay_s - p_.jitter_s, p_.delay_s + p_.jitter_s)(rng_);
    v.release_s = now_s + std::max(0.0, d);
    if (!p_.reorder && !v.drop) v.release_s = std::max(v.release_s, last_release_s_);
    if (!v.drop) last_release_s_ = v.release_s;
  }
  if (v.drop) {
    ++s.packets_dropped;
    if (open ? !open->lost : true) ++s.messages_lost;
    if (open) open->lost = true;
  } else {
    s.delay_s_sum += v.release_s - now_s;
  }
  if (pkt && pkt->fragmented && last) open_.erase(std::make_pair(pkt->src_port, pkt->seqno));
  return v;
}

std::string Impairment::stats_json() const {
  nlohmann::json ch = nlohmann::json::object();
  for (const auto& [name, s] : stats_) {
    const int64_t passed = s.packets - s.packets_dropped;
    ch[name] = {{"packets", s.packets},
                {"packets_dropped", s.packets_dropped},
                {"messages", s.messages},
                {"messages_lost", s.messages_lost},
                {"mean_delay_ms", passed > 0 ? 1e3 * s.delay_s_sum / passed : 0.0},
                {"exempt", p_.exempt.count(name) > 0}};
  }
  return nlohmann::json{
      {"loss", p_.loss}, {"delay_s", p_.delay_s}, {"jitter_s", p_.jitter_s}, {"reorder", p_.reorder}, {"channels", ch}}
      .dump(2);
}

}  // namespace evade::netem
