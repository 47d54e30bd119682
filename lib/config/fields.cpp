#include "config/fields.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "config/robot_profile.h"

namespace evade::config {

std::string number_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

YAML::Node number_node(double v) { return YAML::Node(number_text(v)); }

namespace {
int clamp_int(double v) {
  if (v <= static_cast<double>(std::numeric_limits<int>::min())) return std::numeric_limits<int>::min();
  if (v >= static_cast<double>(std::numeric_limits<int>::max())) return std::numeric_limits<int>::max();
  return static_cast<int>(v);
}

bool bounded(const Range& r) { return std::isfinite(r.min) || std::isfinite(r.max); }

double read_number(const Node& n, const std::string& key, const Range& r) {
  if (r.positive) return n.get_positive(key);
  if (bounded(r)) return n.get_double(key, r.min, r.max);
  return n.get<double>(key);
}
}  // namespace

Converter<int64_t> seconds_as_us_truncated(Range r) {
  return {[r](const Node& n, const std::string& key) { return static_cast<int64_t>(read_number(n, key, r) * 1e6); },
          [](const int64_t& us) { return number_node(static_cast<double>(us) / 1e6); }};
}

Converter<int64_t> seconds_as_us_rounded(Range r) {
  return {[r](const Node& n, const std::string& key) {
            return static_cast<int64_t>(std::llround(read_number(n, key, r) * 1e6));
          },
          [](const int64_t& us) { return number_node(static_cast<double>(us) / 1e6); }};
}

Converter<int64_t> hz_as_period_us(Range r) {
  return {[r](const Node& n, const std::string& key) {
            return static_cast<int64_t>(std::llround(1e6 / read_number(n, key, r)));
          },
          [](const int64_t& us) { return number_node(1e6 / static_cast<double>(us)); }};
}

Converter<double> degrees_as_radians(Range r) {
  return {[r](const Node& n, const std::string& key) { return read_number(n, key, r) * M_PI / 180.0; },
          // to 1e-9 deg: 30 deg is written as 30 again, not 29.999999999999996
          [](const double& rad) { return number_node(std::round(rad * 180.0 / M_PI * 1e9) / 1e9); }};
}

void Loader::field(const char* key, double& m, Range r) { m = read_number(node_, key, r); }

void Loader::field(const char* key, int& m, Range r) { m = node_.get_int(key, clamp_int(r.min), clamp_int(r.max)); }

void Loader::field(const char* key, int64_t& m, Range r) {
  m = node_.get<int64_t>(key);
  if (static_cast<double>(m) < r.min || static_cast<double>(m) > r.max) {
    std::ostringstream os;
    os << "value " << m << " outside [" << number_text(r.min) << ", " << number_text(r.max) << "]";
    node_.fail(key, os.str());
  }
}

void Loader::field(const char* key, bool& m) { m = node_.get<bool>(key); }

void Loader::field(const char* key, std::string& m) { m = node_.get<std::string>(key); }

void Loader::field(const char* key, std::vector<double>& m, size_t count) { m = node_.get_doubles(key, count); }

void Loader::field(const char* key, std::vector<std::string>& m) { m = node_.get_strings(key); }

void Loader::field(const char* key, std::vector<std::vector<double>>& m) { m = node_.get_points(key); }

void Loader::rule(bool ok, const std::string& key, const std::string& reason) const {
  if (ok) return;
  const size_t dot = key.rfind('.');
  if (dot == std::string::npos) node_.fail(key, reason);
  // Walk to the nested section without marking anything read.
  YAML::Node n = node_.yaml();
  std::string path = node_.path();
  std::stringstream parts(key.substr(0, dot));
  std::string part;
  while (std::getline(parts, part, '.')) {
    const YAML::Node& view = n;                                       // const lookups add nothing to the tree
    if (view.IsMap() && view[part].IsDefined()) n.reset(view[part]);  // rebinds (operator= would write)
    path = path.empty() ? part : path + "." + part;
  }
  Node(n, node_.file(), path).fail(key.substr(dot + 1), reason);
}

void Writer::field(const char* key, const std::vector<double>& m, size_t) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (double v : m) list.push_back(number_node(v));
  out_[key] = list;
}

void Writer::field(const char* key, const std::vector<std::string>& m) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const auto& s : m) list.push_back(YAML::Node(s));
  out_[key] = list;
}

void Writer::field(const char* key, const std::vector<std::vector<double>>& m) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (const auto& p : m) {
    YAML::Node xy(YAML::NodeType::Sequence);
    for (double v : p) xy.push_back(number_node(v));
    list.push_back(xy);
  }
  out_[key] = list;
}

namespace {

// A scalar as YAML text: plain where YAML reads it back as the same
// string, else single-quoted.
std::string scalar_text(const std::string& s) {
  bool plain = !s.empty() && s != "~" && s != "null";
  for (char c : s)
    if (c == '#' || c == ':' || c == '\'' || c == '"' || c == '[' || c == ']' || c == '{' || c == '}' || c == ',' ||
        c == '\n' || c == '&' || c == '*' || c == '!' || c == '|' || c == '>' || c == '%' || c == '@' || c == '`')
      plain = false;
  if (!s.empty() && (s.front() == ' ' || s.back() == ' ' || s.front() == '-' || s.front() == '?')) plain = false;
  if (plain) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("''") : std::string(1, c);
  return q + "'";
}

std::string flow_text(const YAML::Node& n) {
  if (n.IsSequence()) {
    std::string s = "[";
    for (size_t i = 0; i < n.size(); ++i) s += (i ? ", " : "") + flow_text(n[i]);
    return s + "]";
  }
  if (n.IsMap()) {
    std::string s = "{";
    bool first = true;
    for (auto it = n.begin(); it != n.end(); ++it) {
      s += (first ? "" : ", ") + it->first.Scalar() + ": " + flow_text(it->second);
      first = false;
    }
    return s + "}";
  }
  return scalar_text(n.Scalar());
}

// `prov`: where merged values came from (robot_profile.h; null: all from `file`).
void emit(std::ostringstream& os, const YAML::Node& values, const YAML::Node* source, const std::string& file,
          int indent, const Provenance* prov = nullptr) {
  const std::string pad(static_cast<size_t>(indent), ' ');
  for (auto it = values.begin(); it != values.end(); ++it) {
    const std::string key = it->first.Scalar();
    YAML::Node src;
    bool have = false;
    if (source && source->IsMap() && (*source)[key].IsDefined()) {
      src = (*source)[key];
      have = true;
    }
    if (it->second.IsMap()) {
      os << pad << key << ":\n";
      emit(os, it->second, have ? &src : nullptr, file, indent + 2, prov);
      continue;
    }
    os << pad << key << ": " << flow_text(it->second);
    const std::string* from = have && prov ? prov->file_of(src) : nullptr;
    if (source)
      os << "  # "
         << (have ? (from ? *from : file) + ":" + std::to_string(src.Mark().line + 1) : std::string("default"));
    os << "\n";
  }
}

bool same_scalar(const std::string& a, const std::string& b) {
  if (a == b) return true;
  try {
    size_t ua = 0, ub = 0;
    const double da = std::stod(a, &ua), db = std::stod(b, &ub);
    return ua == a.size() && ub == b.size() && da == db;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

std::string yaml_text(const YAML::Node& values) {
  std::ostringstream os;
  emit(os, values, nullptr, "", 0);
  return os.str();
}

std::string dump_yaml(const std::string& name, const YAML::Node& values, const Node& source) {
  std::ostringstream os;
  os << name << ":\n";
  const YAML::Node src = source.yaml();
  emit(os, values, &src, source.file(), 2, source.provenance());
  return os.str();
}

std::vector<std::string> yaml_differences(const YAML::Node& a, const YAML::Node& b, const std::string& path) {
  std::vector<std::string> out;
  const std::string here = path.empty() ? "(top)" : path;
  if (a.IsMap() && b.IsMap()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      const std::string k = it->first.Scalar();
      const std::string p = path.empty() ? k : path + "." + k;
      if (!b[k].IsDefined()) {
        out.push_back(p + ": only in the first");
        continue;
      }
      for (auto& d : yaml_differences(it->second, b[k], p)) out.push_back(d);
    }
    for (auto it = b.begin(); it != b.end(); ++it) {
      const std::string k = it->first.Scalar();
      if (!a[k].IsDefined()) out.push_back((path.empty() ? k : path + "." + k) + ": only in the second");
    }
    return out;
  }
  if (a.IsSequence() && b.IsSequence() && a.size() == b.size()) {
    for (size_t i = 0; i < a.size(); ++i)
      for (auto& d : yaml_differences(a[i], b[i], path + "[" + std::to_string(i) + "]")) out.push_back(d);
    return out;
  }
  if (a.IsScalar() && b.IsScalar() && same_scalar(a.Scalar(), b.Scalar())) return out;
  out.push_back(here + ": " + flow_text(a) + " != " + flow_text(b));
  return out;
}

}  // namespace evade::config
