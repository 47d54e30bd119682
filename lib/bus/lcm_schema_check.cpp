// LcmSchema, part 2 of 3: the pre-decode check (check(), well_formed()):
// walks a message by its schema without allocating, before lcm-gen's
// decoder sizes any array.
#include <map>

#include "bus/core.h"
#include "bus/lcm_schema.h"
#include "bus/lcm_wire.h"

namespace evade::bus {

using lcm_wire::element_count;
using lcm_wire::read_be;

namespace {
// Bytes of a primitive, 0 for strings and structs (variable size).
size_t primitive_size(const std::string& t) {
  if (t == "int8_t" || t == "byte" || t == "boolean") return 1;
  if (t == "int16_t") return 2;
  if (t == "int32_t" || t == "float") return 4;
  if (t == "int64_t" || t == "double") return 8;
  return 0;
}
constexpr int kMaxNesting = 16;
}  // namespace

bool LcmSchema::skip_value(const std::string& type, const uint8_t* data, size_t size, size_t* pos, int depth) const {
  if (size_t n = primitive_size(type)) {
    if (*pos + n > size) return false;
    *pos += n;
    return true;
  }
  if (type == "string") {
    uint64_t u = 0;
    if (!read_be(data, size, pos, 4, &u) || u == 0 || u > size - *pos) return false;
    *pos += u;
    return true;
  }
  auto it = structs_.find(type);
  if (it == structs_.end() || depth > kMaxNesting) return false;
  return skip_struct(it->second, data, size, pos, depth + 1);
}

bool LcmSchema::skip_struct(const Struct& s, const uint8_t* data, size_t size, size_t* pos, int depth) const {
  std::map<std::string, int64_t> ints;  // integer fields seen so far (array lengths)
  for (const Field& f : s.fields) {
    if (f.dims.empty()) {
      size_t start = *pos;
      if (!skip_value(f.type, data, size, pos, depth)) return false;
      size_t n = primitive_size(f.type);
      if (n >= 1 && n <= 8 && f.type != "float" && f.type != "double" && f.type != "boolean") {
        uint64_t u = 0;
        size_t p = start;
        read_be(data, size, &p, n, &u);
        int64_t v = n == 1   ? static_cast<int8_t>(u)
                    : n == 2 ? static_cast<int16_t>(u)
                    : n == 4 ? static_cast<int32_t>(u)
                             : static_cast<int64_t>(u);
        if (f.type == "byte") v = static_cast<int64_t>(u);
        ints[f.name] = v;
      }
      continue;
    }
    std::vector<int64_t> lens;
    for (const Dim& d : f.dims) {
      int64_t len = d.size;
      if (!d.is_const) {
        auto it = ints.find(d.field);
        if (it == ints.end()) return false;
        len = it->second;
      }
      lens.push_back(len);
    }
    const int64_t n_elements = element_count(lens, size);
    if (n_elements < 0) return false;
    const uint64_t count = static_cast<uint64_t>(n_elements);
    if (size_t n = primitive_size(f.type)) {
      if (count * n > size - *pos) return false;
      *pos += count * n;
    } else {
      for (uint64_t i = 0; i < count; ++i)
        if (!skip_value(f.type, data, size, pos, depth)) return false;
    }
  }
  return true;
}

bool LcmSchema::check(const uint8_t* data, size_t size) const {
  size_t pos = 0;
  uint64_t hash = 0;
  if (!read_be(data, size, &pos, 8, &hash)) return false;
  auto it = by_hash_.find(static_cast<int64_t>(hash));
  if (it == by_hash_.end()) return false;
  return skip_struct(structs_.at(it->second), data, size, &pos, 0) && pos == size;
}

bool well_formed(const uint8_t* data, size_t size) { return LcmSchema::evade().check(data, size); }

}  // namespace evade::bus
