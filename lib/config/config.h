// Typed, strict access to the YAML configuration.
//
// Every value is read through a Node, which knows the file and the dotted
// key path it came from, so that a missing key, a wrong type or an unknown
// key produces one line naming file, line and key. A section is "closed"
// after its owner has read it: any key it holds that nobody asked for is
// an error (a typo must not silently fall back to a default).
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace evade::config {

struct Provenance;  // robot_profile.h: which file each merged value came from

// The one error type for bad configuration: "file:line: key 'a.b': reason".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Node {
 public:
  Node(YAML::Node node, std::string file, std::string path);

  // Sub-section; error if missing or not a map.
  Node section(const std::string& key) const;
  bool has(const std::string& key) const;

  template <class T>
  T get(const std::string& key) const;  // bool, int, int64_t, double, std::string

  // Numbers with a range check, the most common case in robot parameters.
  double get_double(const std::string& key, double min, double max) const;
  int get_int(const std::string& key, int min, int max) const;
  double get_positive(const std::string& key) const;  // > 0
  std::vector<double> get_doubles(const std::string& key, size_t count) const;
  std::vector<std::string> get_strings(const std::string& key) const;         // a non-empty list of non-empty strings
  std::vector<std::vector<double>> get_points(const std::string& key) const;  // [[x, y], ...]
  std::string get_choice(const std::string& key, const std::vector<std::string>& choices) const;

  // Error if this map holds keys that were never read through get/section.
  void close() const;

  // Throws ConfigError naming this node (or its key) and the reason.
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const YAML::Node& yaml() const { return node_; }
  std::vector<std::string> keys() const;

  // "file:line" of the value under `key` (of this node itself for ""):
  // the file it came from when the configuration was merged from several
  // (robot_profile.h), else this node's file.
  std::string source(const std::string& key) const;
  // Set by the merge (robot_profile.cpp) on the root; sections inherit it.
  void set_provenance(std::shared_ptr<const Provenance> p) { prov_ = std::move(p); }
  const Provenance* provenance() const { return prov_.get(); }

 private:
  YAML::Node child(const std::string& key) const;  // marks used, errors if missing
  std::string key_path(const std::string& key) const;
  int line_of(const YAML::Node& n) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::shared_ptr<std::set<std::string>> used_;
  std::shared_ptr<const Provenance> prov_;  // null: every value is from file_
};

// Loads a YAML file; parse errors become ConfigError with file and line.
Node load_file(const std::string& path);
// Loads YAML text (tests, fuzzers); `name` stands in for the file name.
Node load_string(const std::string& text, const std::string& name);

// The top-level sections of a robot configuration (config/robot.yaml): the
// robot's limits, the LiDAR, and one per program. Each program reads only
// the sections it needs, so a misspelt section would go unnoticed by all of
// them; load_robot_config rejects any other top-level key.
const std::vector<std::string>& robot_sections();
// load_file, then a ConfigError (file, line, key) for a top-level key that
// is not one of robot_sections() (or the flag `test_config`), and the
// cross-section safety rules of config/safety.h.
Node load_robot_config(const std::string& path);
// The checks of load_robot_config on a configuration already loaded (or
// merged: robot_profile.h).
void check_robot_config(const Node& root);

// Where a process finds a configuration file NAME (robot.yaml,
// scenario_families.yaml) when no --config names one. One rule, the first
// that exists wins (config_path.cpp):
//   1. ./config/NAME            (started inside a working tree)
//   2. SOURCE/config/NAME       (the executable runs from this build's tree:
//                                the source tree it was built from)
//   3. SYSCONF/evade/NAME       (installed: the install's sysconfdir, found
//                                relative to the executable, so /etc/evade
//                                for /usr/libexec/evade/bin/X and
//                                ROOT/etc/evade for a copy under ROOT)
// Nothing exists: the last candidate (the error then names it).
std::vector<std::string> config_file_candidates(const std::string& name);
std::string find_config_file(const std::string& name);
// The default robot configuration: $EVADE_CONFIG, else
// find_config_file("robot.yaml").
std::string default_config_path();

}  // namespace evade::config
