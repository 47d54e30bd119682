// LcmSchema, part 3 of 3: the decoder of a whole message into a Value and
// the Value's JSON writer.
#include <cmath>
#include <cstring>
#include <sstream>

#include "bus/lcm_schema.h"
#include "bus/lcm_wire.h"

namespace evade::bus {

using lcm_wire::element_count;
using lcm_wire::read_be;

const Value* Value::field(const std::string& name) const {
  for (const auto& [k, v] : fields)
    if (k == name) return &v;
  return nullptr;
}

double Value::number() const {
  switch (kind) {
    case Kind::Int:
      return static_cast<double>(i);
    case Kind::Float:
      return f;
    case Kind::Bool:
      return b ? 1.0 : 0.0;
    default:
      return std::nan("");
  }
}

namespace {

void json_string(std::ostringstream& os, const std::string& s) {
  os << '"';
  for (unsigned char c : s) {
    switch (c) {
      case '"':
        os << "\\\"";
        break;
      case '\\':
        os << "\\\\";
        break;
      case '\n':
        os << "\\n";
        break;
      case '\t':
        os << "\\t";
        break;
      case '\r':
        os << "\\r";
        break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          os << buf;
        } else {
          os << c;
        }
    }
  }
  os << '"';
}

void json(std::ostringstream& os, const Value& v) {
  switch (v.kind) {
    case Value::Kind::Int:
      os << v.i;
      break;
    case Value::Kind::Bool:
      os << (v.b ? "true" : "false");
      break;
    case Value::Kind::Float:
      if (std::isfinite(v.f)) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.17g", v.f);
        os << buf;
      } else {
        os << "null";
      }
      break;
    case Value::Kind::String:
      json_string(os, v.s);
      break;
    case Value::Kind::Array:
      os << '[';
      for (size_t k = 0; k < v.items.size(); ++k) {
        if (k) os << ',';
        json(os, v.items[k]);
      }
      os << ']';
      break;
    case Value::Kind::Struct:
      os << '{';
      for (size_t k = 0; k < v.fields.size(); ++k) {
        if (k) os << ',';
        json_string(os, v.fields[k].first);
        os << ':';
        json(os, v.fields[k].second);
      }
      os << '}';
      break;
  }
}

}  // namespace

std::string to_json(const Value& v) {
  std::ostringstream os;
  json(os, v);
  return os.str();
}

bool LcmSchema::decode_field(const std::string& type, const uint8_t* data, size_t size, size_t* pos, Value* out) const {
  uint64_t u = 0;
  if (type == "int8_t" || type == "byte" || type == "boolean") {
    if (!read_be(data, size, pos, 1, &u)) return false;
    if (type == "boolean") {
      out->kind = Value::Kind::Bool;
      out->b = (u != 0);
    } else {
      out->kind = Value::Kind::Int;
      out->i = (type == "byte") ? static_cast<int64_t>(u) : static_cast<int8_t>(u);
    }
    return true;
  }
  if (type == "int16_t") {
    if (!read_be(data, size, pos, 2, &u)) return false;
    out->kind = Value::Kind::Int;
    out->i = static_cast<int16_t>(u);
    return true;
  }
  if (type == "int32_t") {
    if (!read_be(data, size, pos, 4, &u)) return false;
    out->kind = Value::Kind::Int;
    out->i = static_cast<int32_t>(u);
    return true;
  }
  if (type == "int64_t") {
    if (!read_be(data, size, pos, 8, &u)) return false;
    out->kind = Value::Kind::Int;
    out->i = static_cast<int64_t>(u);
    return true;
  }
  if (type == "float") {
    if (!read_be(data, size, pos, 4, &u)) return false;
    uint32_t w = static_cast<uint32_t>(u);
    float f;
    std::memcpy(&f, &w, 4);
    out->kind = Value::Kind::Float;
    out->f = f;
    return true;
  }
  if (type == "double") {
    if (!read_be(data, size, pos, 8, &u)) return false;
    double d;
    std::memcpy(&d, &u, 8);
    out->kind = Value::Kind::Float;
    out->f = d;
    return true;
  }
  if (type == "string") {
    if (!read_be(data, size, pos, 4, &u)) return false;
    if (u == 0 || *pos + u > size) return false;  // length includes the NUL
    out->kind = Value::Kind::String;
    out->s.assign(reinterpret_cast<const char*>(data + *pos), u - 1);
    *pos += u;
    return true;
  }
  auto it = structs_.find(type);
  if (it == structs_.end()) return false;
  return decode_struct(it->second, data, size, pos, out);
}

bool LcmSchema::decode_dims(const Field& f, size_t d, const std::vector<int64_t>& lens, const uint8_t* data,
                            size_t size, size_t* pos, Value* out) const {
  if (d == f.dims.size()) return decode_field(f.type, data, size, pos, out);
  out->kind = Value::Kind::Array;
  const int64_t n = lens[d];  // bounded by element_count() before any recursion
  out->items.resize(static_cast<size_t>(n));
  for (auto& item : out->items)
    if (!decode_dims(f, d + 1, lens, data, size, pos, &item)) return false;
  return true;
}

bool LcmSchema::decode_struct(const Struct& s, const uint8_t* data, size_t size, size_t* pos, Value* out) const {
  out->kind = Value::Kind::Struct;
  out->fields.clear();
  for (const Field& f : s.fields) {
    Value v;
    if (f.dims.empty()) {
      if (!decode_field(f.type, data, size, pos, &v)) return false;
    } else {
      std::vector<int64_t> lens;
      for (const Dim& d : f.dims) {
        if (d.is_const) {
          lens.push_back(d.size);
        } else {
          const Value* lv = out->field(d.field);
          if (!lv || lv->kind != Value::Kind::Int) return false;
          lens.push_back(lv->i);
        }
      }
      if (element_count(lens, size) < 0) return false;
      if (!decode_dims(f, 0, lens, data, size, pos, &v)) return false;
    }
    out->fields.emplace_back(f.name, std::move(v));
  }
  return true;
}

std::optional<Value> LcmSchema::decode(const uint8_t* data, size_t size, std::string* type) const {
  size_t pos = 0;
  uint64_t hash = 0;
  if (!read_be(data, size, &pos, 8, &hash)) return std::nullopt;
  auto it = by_hash_.find(static_cast<int64_t>(hash));
  if (it == by_hash_.end()) return std::nullopt;
  if (type) *type = it->second;
  Value v;
  if (!decode_struct(structs_.at(it->second), data, size, &pos, &v)) return std::nullopt;
  if (pos != size) return std::nullopt;
  return v;
}

}  // namespace evade::bus
