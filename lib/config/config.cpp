#include "config/config.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "config/robot_profile.h"
#include "config/safety.h"

namespace evade::config {
namespace {

std::string type_name(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "null";
    case YAML::NodeType::Scalar:
      return "a scalar";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "undefined";
  }
}

// A map key as text; keys that are lists or maps (YAML allows them) are
// not configuration names.
bool key_text(const YAML::Node& key, std::string* out) {
  if (!key.IsScalar()) return false;
  *out = key.Scalar();
  return true;
}

}  // namespace

Node::Node(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)),
      file_(std::move(file)),
      path_(std::move(path)),
      used_(std::make_shared<std::set<std::string>>()) {}

std::string Node::key_path(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

int Node::line_of(const YAML::Node& n) const { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

std::string Node::source(const std::string& key) const {
  std::string file = file_;
  int line = line_of(node_);
  if (!key.empty() && node_.IsMap()) {
    // Point at the key itself where it exists; a value merged in from
    // another file (robot_profile.h) at that value, in that file.
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      std::string k;
      if (key_text(it->first, &k) && k == key) {
        line = line_of(it->first);
        if (const std::string* from = prov_ ? prov_->file_of(it->second) : nullptr) {
          file = *from;
          line = line_of(it->second);
        }
        break;
      }
    }
  }
  return file + ":" + std::to_string(line);
}

void Node::fail(const std::string& key, const std::string& reason) const {
  std::ostringstream os;
  os << source(key) << ": key '" << (key.empty() ? path_ : key_path(key)) << "': " << reason;
  throw ConfigError(os.str());
}

bool Node::has(const std::string& key) const { return node_.IsMap() && node_[key].IsDefined(); }

YAML::Node Node::child(const std::string& key) const {
  if (!node_.IsMap()) fail("", "expected a map, found " + type_name(node_));
  YAML::Node c = node_[key];
  if (!c.IsDefined()) fail(key, "missing");
  used_->insert(key);
  return c;
}

Node Node::section(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsMap()) fail(key, "expected a map, found " + type_name(c));
  Node out(c, file_, key_path(key));
  out.prov_ = prov_;
  return out;
}

template <>
std::string Node::get<std::string>(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsScalar()) fail(key, "expected a string, found " + type_name(c));
  return c.Scalar();
}

template <>
double Node::get<double>(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsScalar()) fail(key, "expected a number, found " + type_name(c));
  try {
    double v = c.as<double>();
    if (!std::isfinite(v)) fail(key, "expected a finite number, found '" + c.Scalar() + "'");
    return v;
  } catch (const YAML::Exception&) {
    fail(key, "expected a number, found '" + c.Scalar() + "'");
  }
}

template <>
int64_t Node::get<int64_t>(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsScalar()) fail(key, "expected an integer, found " + type_name(c));
  try {
    return c.as<int64_t>();
  } catch (const YAML::Exception&) {
    fail(key, "expected an integer, found '" + c.Scalar() + "'");
  }
}

template <>
int Node::get<int>(const std::string& key) const {
  int64_t v = get<int64_t>(key);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) fail(key, "integer out of range");
  return static_cast<int>(v);
}

template <>
bool Node::get<bool>(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsScalar()) fail(key, "expected true or false, found " + type_name(c));
  const std::string& s = c.Scalar();
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  fail(key, "expected true or false, found '" + s + "'");
}

double Node::get_double(const std::string& key, double min, double max) const {
  double v = get<double>(key);
  if (v < min || v > max) {
    std::ostringstream os;
    os << "value " << v << " outside [" << min << ", " << max << "]";
    fail(key, os.str());
  }
  return v;
}

int Node::get_int(const std::string& key, int min, int max) const {
  int v = get<int>(key);
  if (v < min || v > max) {
    std::ostringstream os;
    os << "value " << v << " outside [" << min << ", " << max << "]";
    fail(key, os.str());
  }
  return v;
}

double Node::get_positive(const std::string& key) const {
  double v = get<double>(key);
  if (!(v > 0.0)) fail(key, "must be greater than 0");
  return v;
}

std::vector<std::string> Node::get_strings(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsSequence() || c.size() == 0) fail(key, "expected a non-empty list of names, found " + type_name(c));
  std::vector<std::string> out;
  for (const auto& e : c) {
    if (!e.IsScalar() || e.Scalar().empty()) fail(key, "expected a list of non-empty names");
    out.push_back(e.Scalar());
  }
  return out;
}

std::vector<double> Node::get_doubles(const std::string& key, size_t count) const {
  YAML::Node c = child(key);
  if (!c.IsSequence()) fail(key, "expected a list of numbers, found " + type_name(c));
  if (count != 0 && c.size() != count)
    fail(key, "expected " + std::to_string(count) + " numbers, found " + std::to_string(c.size()));
  std::vector<double> out;
  for (const auto& e : c) {
    try {
      double v = e.as<double>();
      if (!std::isfinite(v)) throw YAML::Exception(e.Mark(), "not finite");
      out.push_back(v);
    } catch (const YAML::Exception&) {
      fail(key, "expected a list of finite numbers");
    }
  }
  return out;
}

std::vector<std::vector<double>> Node::get_points(const std::string& key) const {
  YAML::Node c = child(key);
  if (!c.IsSequence()) fail(key, "expected a list of [x, y] points, found " + type_name(c));
  std::vector<std::vector<double>> out;
  for (const auto& p : c) {
    if (!p.IsSequence() || p.size() != 2) fail(key, "expected a list of [x, y] points");
    std::vector<double> xy;
    for (const auto& e : p) {
      try {
        double v = e.as<double>();
        if (!std::isfinite(v)) throw YAML::Exception(e.Mark(), "not finite");
        xy.push_back(v);
      } catch (const YAML::Exception&) {
        fail(key, "expected a list of [x, y] points of finite numbers");
      }
    }
    out.push_back(xy);
  }
  return out;
}

std::string Node::get_choice(const std::string& key, const std::vector<std::string>& choices) const {
  std::string v = get<std::string>(key);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  fail(key, "'" + v + "' is not one of: " + list);
}

std::vector<std::string> Node::keys() const {
  std::vector<std::string> out;
  if (!node_.IsMap()) return out;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    std::string k;
    if (!key_text(it->first, &k)) {
      std::ostringstream os;
      os << file_ << ":" << line_of(it->first) << ": key '" << path_ << "': a key must be a plain name";
      throw ConfigError(os.str());
    }
    out.push_back(k);
  }
  return out;
}

void Node::close() const {
  for (const auto& k : keys())
    if (!used_->count(k)) fail(k, "unknown key");
}

namespace {
Node parse(const std::string& text, const std::string& name) {
  try {
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) {
      std::ostringstream os;
      os << name << ":1: key '': expected a map at the top level";
      throw ConfigError(os.str());
    }
    return Node(root, name, "");
  } catch (const YAML::ParserException& e) {
    std::ostringstream os;
    os << name << ":" << e.mark.line + 1 << ": key '': YAML syntax error: " << e.msg;
    throw ConfigError(os.str());
  }
}
}  // namespace

Node load_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ":0: key '': cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse(ss.str(), path);
}

Node load_string(const std::string& text, const std::string& name) { return parse(text, name); }

const std::vector<std::string>& robot_sections() {
  static const std::vector<std::string> sections = {
      "robot",    "lidar",        "sim",     "lidar_driver", "base_driver", "elevation_map",
      "tracker",  "predictor",    "planner", "route",        "metrics",     "perception_metrics",
      "lockstep", "health_board", "viz",     "bus",          "teleop"};
  return sections;
}

void check_robot_config(const Node& root) {
  const auto& known = robot_sections();
  for (const auto& k : root.keys())
    if (k != kTestConfigKey && std::find(known.begin(), known.end(), k) == known.end()) root.fail(k, "unknown section");
  check_safety(root);
}

Node load_robot_config(const std::string& path) {
  Node root = load_file(path);
  check_robot_config(root);
  return root;
}

}  // namespace evade::config
