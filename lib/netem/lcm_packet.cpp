#include "netem/lcm_packet.h"

namespace evade::netem {
namespace {

uint32_t be32(const uint8_t* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }
uint16_t be16(const uint8_t* p) { return uint16_t(p[0] << 8 | p[1]); }

constexpr uint32_t kShortMagic = 0x4c433032;     // "LC02"
constexpr uint32_t kFragmentMagic = 0x4c433033;  // "LC03"

// The NUL-terminated channel at p (at most end - p bytes); none if unterminated.
std::optional<std::string> channel_at(const uint8_t* p, const uint8_t* end) {
  for (const uint8_t* q = p; q < end; ++q)
    if (*q == 0) return std::string(reinterpret_cast<const char*>(p), q - p);
  return std::nullopt;
}

}  // namespace

std::optional<LcmPacket> parse_lcm_packet(const uint8_t* data, size_t n) {
  if (n < 20 || (data[0] >> 4) != 4 || data[9] != 17) return std::nullopt;  // IPv4, UDP
  const size_t ihl = size_t(data[0] & 0x0f) * 4;
  if (ihl < 20 || n < ihl + 8 + 8) return std::nullopt;
  const uint8_t* udp = data + ihl;
  const uint8_t* p = udp + 8;
  const uint8_t* end = data + n;
  LcmPacket out;
  out.src_port = be16(udp);
  const uint32_t magic = be32(p);
  out.seqno = be32(p + 4);
  if (magic == kShortMagic) {
    auto ch = channel_at(p + 8, end);
    if (!ch) return std::nullopt;
    out.channel = *ch;
    return out;
  }
  if (magic != kFragmentMagic || end - p < 20) return std::nullopt;
  out.fragmented = true;
  out.fragment = be16(p + 16);
  out.fragments = be16(p + 18);
  if (out.fragments == 0 || out.fragment >= out.fragments) return std::nullopt;
  if (out.fragment == 0) {
    auto ch = channel_at(p + 20, end);
    if (!ch) return std::nullopt;
    out.channel = *ch;
  }
  return out;
}

}  // namespace evade::netem
