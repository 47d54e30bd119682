// One field list per parameter struct: each struct names every member once,
// with its YAML key (the member's own name), its range or choices, as
//
//   struct TeleopParams {
//     double rate_hz = 20.0;
//     int estop_repeats = 5;
//     template <class V> void fields(V& v) {
//       v.field("rate_hz", rate_hz, config::positive());
//       v.field("estop_repeats", estop_repeats, config::between(1, 1000));
//     }
//   };
//
// and the visitors below do the rest from that one list:
// - load<T>(section): reads every field from a Node (file:line:key errors,
//   ranges and choices checked, then close(): unknown keys rejected);
// - to_yaml(t): the struct's values as a YAML tree, keyed as the YAML is;
// - check(t, name): the ranges and rules of the list, on a struct built in
//   code (the values are written out and read back through load<T>, so
//   the checks are the loader's, word for word);
// - dump_yaml(values, source): YAML text, each value followed by the file
//   and line it came from (tools/config-dump).
// A nested YAML map is a nested struct with its own field list
// (v.section("filter", filter)). A rule spanning fields is
// v.rule(ok, "key", "reason"), evaluated after the fields listed before it.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "config/config.h"

namespace evade::config {

// A number's allowed values: [min, max], or > 0 (positive()).
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool positive = false;
};
inline Range between(double min, double max) { return Range{min, max, false}; }
inline Range positive() { return Range{0.0, std::numeric_limits<double>::infinity(), true}; }
inline Range any_number() { return Range{}; }

// A choice among names, each standing for a value of the member's type.
template <class T>
using Choices = std::vector<std::pair<std::string, T>>;

// A member whose YAML form differs from its C++ form (degrees in the file,
// radians in the struct; a list as a pose): how to read and write it.
template <class T>
struct Converter {
  std::function<T(const Node& section, const std::string& key)> read;
  std::function<YAML::Node(const T&)> write;
};

// The usual conversions. The member is named with its own unit (the key
// with _s, the member with _us); the range applies to the YAML value.
// Seconds in the YAML, whole microseconds in the struct: truncated
// (int64_t(s * 1e6)) or rounded to the nearest (llround(s * 1e6)).
Converter<int64_t> seconds_as_us_truncated(Range r);
Converter<int64_t> seconds_as_us_rounded(Range r);
// A rate in Hz in the YAML, its period in microseconds in the struct
// (llround(1e6 / hz)).
Converter<int64_t> hz_as_period_us(Range r);
// Degrees in the YAML, radians in the struct (deg * M_PI / 180).
Converter<double> degrees_as_radians(Range r);

// The text of a number as the dump and check write it: the shortest that
// reads back to the same double.
std::string number_text(double v);
YAML::Node number_node(double v);

// Reads a struct from a Node through its field list.
class Loader {
 public:
  explicit Loader(const Node& section) : node_(section) {}

  void field(const char* key, double& m, Range r = {});
  void field(const char* key, int& m, Range r);
  void field(const char* key, int64_t& m, Range r);
  void field(const char* key, bool& m);
  void field(const char* key, std::string& m);
  void field(const char* key, std::vector<double>& m, size_t count);  // count 0: any length
  void field(const char* key, std::vector<std::string>& m);           // non-empty list of names
  void field(const char* key, std::vector<std::vector<double>>& m);   // [[x, y], ...]
  void choice(const char* key, std::string& m, const std::vector<std::string>& names) {
    m = node_.get_choice(key, names);
  }
  template <class T>
  void choice(const char* key, T& m, const Choices<T>& choices) {
    std::vector<std::string> names;
    for (const auto& c : choices) names.push_back(c.first);
    const std::string name = node_.get_choice(key, names);
    for (const auto& c : choices)
      if (c.first == name) m = c.second;
  }
  template <class T>
  void convert(const char* key, T& m, const Converter<T>& c) {
    m = c.read(node_, key);
  }
  template <class S>
  void section(const char* key, S& s) {
    const Node sub = node_.section(key);
    Loader l(sub);
    s.fields(l);
    sub.close();
  }
  // A rule over fields already read; `key` may be dotted (a field of a
  // nested section): the error names that key's file and line.
  void rule(bool ok, const std::string& key, const std::string& reason) const;

 private:
  const Node& node_;
};

// Writes a struct's values as a YAML map through its field list.
class Writer {
 public:
  void field(const char* key, const double& m, Range = {}) { out_[key] = number_node(m); }
  void field(const char* key, const int& m, Range) { out_[key] = number_node(m); }
  void field(const char* key, const int64_t& m, Range) { out_[key] = std::to_string(m); }
  void field(const char* key, const bool& m) { out_[key] = m ? "true" : "false"; }
  void field(const char* key, const std::string& m) { out_[key] = m; }
  void field(const char* key, const std::vector<double>& m, size_t);
  void field(const char* key, const std::vector<std::string>& m);
  void field(const char* key, const std::vector<std::vector<double>>& m);
  void choice(const char* key, const std::string& m, const std::vector<std::string>&) { out_[key] = m; }
  template <class T>
  void choice(const char* key, const T& m, const Choices<T>& choices) {
    for (const auto& c : choices)
      if (c.second == m) {
        out_[key] = c.first;
        return;
      }
    out_[key] = "<not one of the choices>";
  }
  template <class T>
  void convert(const char* key, const T& m, const Converter<T>& c) {
    out_[key] = c.write(m);
  }
  template <class S>
  void section(const char* key, S& s) {
    Writer w;
    s.fields(w);
    out_[key] = w.yaml();
  }
  void rule(bool, const std::string&, const std::string&) const {}

  const YAML::Node& yaml() const { return out_; }

 private:
  YAML::Node out_{YAML::NodeType::Map};
};

// `section` read into t through T's field list, then closed (unknown keys
// are errors). Members not in the list keep their values (a range that
// depends on one, e.g. the LiDAR model's, sees it).
template <class T>
void load_into(const Node& section, T& t) {
  Loader l(section);
  t.fields(l);
  section.close();
}
template <class T>
T load(const Node& section) {
  T t;
  load_into(section, t);
  return t;
}

// T's values, keyed as in the YAML.
template <class T>
YAML::Node to_yaml(const T& t) {
  T copy = t;
  Writer w;
  copy.fields(w);
  return w.yaml();
}

// The values as flow-free YAML text (one key a line), loadable again.
std::string yaml_text(const YAML::Node& values);

// ConfigError "NAME (built in code):LINE: key 'NAME.key': reason" when a
// value of t is outside the ranges, choices or rules of T's field list.
template <class T>
void check(const T& t, const std::string& name) {
  const Node n = load_string(yaml_text(to_yaml(t)), name + " (built in code)");
  (void)load<T>(Node(n.yaml(), n.file(), name));
}

// YAML text of `values` under the key `name`, each scalar or list followed
// by "# FILE:LINE" of the same key in `source` (a section of a loaded
// file), or "# default" where the source has no such key.
std::string dump_yaml(const std::string& name, const YAML::Node& values, const Node& source);

// Differences between two YAML trees, one line each ("a.b: 1 != 2",
// "a.c: only in the first"); numbers compare as doubles, so 1.0e-5 and
// 1e-05 are the same value. Empty when they are equal.
std::vector<std::string> yaml_differences(const YAML::Node& a, const YAML::Node& b, const std::string& path = "");

}  // namespace evade::config
