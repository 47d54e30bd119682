// Which LCM message an IPv4 UDP packet of the bus carries, from its
// headers: LCM's wire format puts a short message ("LC02": sequence
// number, channel, data) in one datagram and a long one in fragments
// ("LC03": sequence number, message size, offset, fragment number and
// count; the channel in fragment 0 only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace evade::netem {

struct LcmPacket {
  uint16_t src_port = 0;  // the sender's socket: with seqno, names the message
  uint32_t seqno = 0;
  bool fragmented = false;
  uint16_t fragment = 0;  // 0 for a short message
  uint16_t fragments = 1;
  std::string channel;  // empty on fragments after the first
};

// Parses a whole IPv4 packet (as a netfilter queue hands it over). None for
// anything that is not a UDP datagram holding an LCM header.
std::optional<LcmPacket> parse_lcm_packet(const uint8_t* data, size_t n);

}  // namespace evade::netem
