// Generic decoding of evade's LCM messages from their .lcm definitions.
//
// The .lcm files are parsed at run time (their text is compiled in), and a
// message is matched to its type by the 8-byte fingerprint that lcm-gen's
// C++ code computes (getHash()). This lets tools (lcmlog-export, the
// log-replay diff) handle every type, including fields added later,
// without a hand-written serializer per type.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace evade::bus {

struct Value {
  enum class Kind { Int, Float, Bool, String, Array, Struct };
  Kind kind = Kind::Int;
  int64_t i = 0;
  double f = 0.0;
  bool b = false;
  std::string s;
  std::vector<Value> items;                           // Array
  std::vector<std::pair<std::string, Value>> fields;  // Struct, in declaration order

  const Value* field(const std::string& name) const;
  double number() const;  // Int, Float or Bool as double
};

class LcmSchema {
 public:
  // The schema of every evade type, built from the compiled-in .lcm texts.
  static const LcmSchema& evade();
  // Parses .lcm source texts; throws std::runtime_error on a syntax error.
  explicit LcmSchema(const std::vector<std::string>& lcm_texts);
  void register_hash(const std::string& type, int64_t hash);

  // Decodes a whole message (fingerprint first). Returns nullopt when the
  // fingerprint is unknown or the bytes are malformed; `type` gets the name.
  std::optional<Value> decode(const uint8_t* data, size_t size, std::string* type = nullptr) const;
  std::vector<std::string> types() const;
  // Checks that the bytes are a well-formed message of a known type: every
  // length fits in what is left, and the sizes add up exactly. Allocates
  // nothing and skips arrays of primitives in O(1), so it can run before
  // lcm-gen's decoder, which sizes its arrays from the length fields
  // before it checks the buffer (a 20-byte message could ask for GBs).
  bool check(const uint8_t* data, size_t size) const;

 private:
  struct Dim {
    bool is_const;
    int64_t size;       // const size
    std::string field;  // variable size: the name of an earlier integer field
  };
  struct Field {
    std::string type;  // primitive name or struct name (without package)
    std::string name;
    std::vector<Dim> dims;
  };
  struct Struct {
    std::string name;
    std::vector<Field> fields;
  };
  bool decode_struct(const Struct& s, const uint8_t* data, size_t size, size_t* pos, Value* out) const;
  bool decode_field(const std::string& type, const uint8_t* data, size_t size, size_t* pos, Value* out) const;
  bool decode_dims(const Field& f, size_t d, const std::vector<int64_t>& lens, const uint8_t* data, size_t size,
                   size_t* pos, Value* out) const;
  bool skip_struct(const Struct& s, const uint8_t* data, size_t size, size_t* pos, int depth) const;
  bool skip_value(const std::string& type, const uint8_t* data, size_t size, size_t* pos, int depth) const;

  std::map<std::string, Struct> structs_;
  std::map<int64_t, std::string> by_hash_;
};

// JSON text of a decoded value (NaN/Inf as null; floats with 17 digits).
std::string to_json(const Value& v);

}  // namespace evade::bus
