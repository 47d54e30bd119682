// LcmSchema, part 1 of 3: the parser of the .lcm definitions and the
// registry of types by fingerprint. The pre-decode check is in
// lcm_schema_check.cpp, the decoder and JSON writer in lcm_schema_value.cpp.
#include "bus/lcm_schema.h"

#include <cctype>
#include <stdexcept>

namespace evade::bus {

// Provided by the build (generated from lcmtypes/ by cmake/LcmTypes.cmake).
std::vector<std::string> evade_lcm_texts();
std::vector<std::pair<std::string, int64_t>> evade_lcm_hashes();

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

}  // namespace

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

}  // namespace evade::bus
