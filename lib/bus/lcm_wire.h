// The LCM wire format's primitives shared by the schema's pre-decode check
// (lcm_schema_check.cpp) and its decoder (lcm_schema_value.cpp): big-endian
// reads and the element count of an array. Internal to lib/bus.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace evade::bus::lcm_wire {

// Elements of a field with these dimension lengths, or -1 when malformed: a
// negative length, or more elements than bytes (every element takes at
// least one byte). An empty outer dimension ends the count: inner lengths
// are then never read (lcm-gen's decoder does the same).
inline int64_t element_count(const std::vector<int64_t>& lens, size_t size) {
  uint64_t count = 1;
  for (int64_t len : lens) {
    if (count == 0) break;
    if (len < 0) return -1;
    count *= static_cast<uint64_t>(len);
    if (count > size) return -1;
  }
  return static_cast<int64_t>(count);
}

inline bool read_be(const uint8_t* data, size_t size, size_t* pos, size_t n, uint64_t* out) {
  if (*pos + n > size) return false;
  uint64_t v = 0;
  for (size_t k = 0; k < n; ++k) v = (v << 8) | data[*pos + k];
  *pos += n;
  *out = v;
  return true;
}

}  // namespace evade::bus::lcm_wire
