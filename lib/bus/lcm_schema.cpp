#include "bus/lcm_schema.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

namespace evade::bus {

// Provided by the build (generated from lcmtypes/ by cmake/LcmTypes.cmake).
std::vector<std::string> evade_lcm_texts();
std::vector<std::pair<std::string, int64_t>> evade_lcm_hashes();

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

// Tokens of the .lcm grammar: identifiers, numbers and punctuation.
std::vector<std::string> tokenize(const std::string& text) {
  std::vector<std::string> out;
  size_t i = 0, n = text.size();
  while (i < n) {
    char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '/') {
      while (i < n && text[i] != '\n') ++i;
    } else if (c == '/' && i + 1 < n && text[i + 1] == '*') {
      size_t e = text.find("*/", i + 2);
      i = (e == std::string::npos) ? n : e + 2;
    } else if (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-') {
      size_t j = i;
      while (j < n &&
             (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_' || text[j] == '.' || text[j] == '-'))
        ++j;
      out.push_back(text.substr(i, j - i));
      i = j;
    } else {
      out.push_back(std::string(1, c));
      ++i;
    }
  }
  return out;
}

std::string strip_package(const std::string& t) {
  size_t dot = t.rfind('.');
  return dot == std::string::npos ? t : t.substr(dot + 1);
}

// Elements of a field with these dimension lengths, or -1 when malformed: a
// negative length, or more elements than bytes (every element takes at
// least one byte). An empty outer dimension ends the count: inner lengths
// are then never read (lcm-gen's decoder does the same).
int64_t element_count(const std::vector<int64_t>& lens, size_t size) {
  uint64_t count = 1;
  for (int64_t len : lens) {
    if (count == 0) break;
    if (len < 0) return -1;
    count *= static_cast<uint64_t>(len);
    if (count > size) return -1;
  }
  return static_cast<int64_t>(count);
}

bool read_be(const uint8_t* data, size_t size, size_t* pos, size_t n, uint64_t* out) {
  if (*pos + n > size) return false;
  uint64_t v = 0;
  for (size_t k = 0; k < n; ++k) v = (v << 8) | data[*pos + k];
  *pos += n;
  *out = v;
  return true;
}

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

bool well_formed(const uint8_t* data, size_t size) { return LcmSchema::evade().check(data, size); }

std::string to_json(const Value& v) {
  std::ostringstream os;
  json(os, v);
  return os.str();
}

LcmSchema::LcmSchema(const std::vector<std::string>& lcm_texts) {
  for (const auto& text : lcm_texts) {
    auto tok = tokenize(text);
    size_t i = 0;
    auto expect = [&](const std::string& t) {
      if (i >= tok.size() || tok[i] != t)
        throw std::runtime_error("lcm schema: expected '" + t + "' near token " + std::to_string(i));
      ++i;
    };
    while (i < tok.size()) {
      if (tok[i] == "package") {
        i += 2;
        expect(";");
      } else if (tok[i] == "struct") {
        ++i;
        Struct s;
        s.name = tok.at(i++);
        expect("{");
        while (i < tok.size() && tok[i] != "}") {
          if (tok[i] == "const") {  // const TYPE NAME = VALUE [, NAME = VALUE];
            while (i < tok.size() && tok[i] != ";") ++i;
            expect(";");
            continue;
          }
          Field f;
          f.type = strip_package(tok.at(i++));
          f.name = tok.at(i++);
          while (tok.at(i) == "[") {
            ++i;
            Dim d{};
            const std::string& sz = tok.at(i++);
            if (std::isdigit(static_cast<unsigned char>(sz[0]))) {
              d.is_const = true;
              d.size = std::stoll(sz);
            } else {
              d.is_const = false;
              d.field = sz;
            }
            f.dims.push_back(d);
            expect("]");
          }
          expect(";");
          s.fields.push_back(f);
        }
        expect("}");
        structs_[s.name] = s;
      } else {
        throw std::runtime_error("lcm schema: unexpected token '" + tok[i] + "'");
      }
    }
  }
}

void LcmSchema::register_hash(const std::string& type, int64_t hash) { by_hash_[hash] = strip_package(type); }

std::vector<std::string> LcmSchema::types() const {
  std::vector<std::string> out;
  for (const auto& [n, s] : structs_) out.push_back(n);
  return out;
}

const LcmSchema& LcmSchema::evade() {
  static const LcmSchema schema = [] {
    LcmSchema s(evade_lcm_texts());
    for (const auto& [name, hash] : evade_lcm_hashes()) s.register_hash(name, hash);
    return s;
  }();
  return schema;
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
