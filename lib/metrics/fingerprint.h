// The type of an encoded LCM message, without decoding it.
#pragma once

#include <cstdint>
#include <vector>

namespace evade::metrics {

// lcm-gen's fingerprint (getHash()): the first 8 bytes, big-endian; 0 when
// there are fewer.
inline int64_t fingerprint(const std::vector<uint8_t>& data) {
  if (data.size() < 8) return 0;
  uint64_t h = 0;
  for (int i = 0; i < 8; ++i) h = (h << 8) | data[i];
  return static_cast<int64_t>(h);
}

template <class Msg>
bool is_type(const std::vector<uint8_t>& data) {
  return fingerprint(data) == Msg::getHash();
}

}  // namespace evade::metrics
