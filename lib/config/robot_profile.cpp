#include "config/robot_profile.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

namespace evade::config {
namespace fs = std::filesystem;
namespace {

int line_of(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

[[noreturn]] void fail_at(const std::string& file, const YAML::Node& at, const std::string& key,
                          const std::string& reason) {
  std::ostringstream os;
  os << file << ":" << line_of(at) << ": key '" << key << "': " << reason;
  throw ConfigError(os.str());
}

bool valid_name(const std::string& name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// Puts every value of `over` (a map read from `file`) into `base` in place:
// maps key by key, anything else replaced whole. A key `base` does not
// have is an error: a profile is a partial robot.yaml.
void merge_map(YAML::Node base, const YAML::Node& over, const std::string& file, const std::string& path,
               Provenance* prov) {
  for (auto it = over.begin(); it != over.end(); ++it) {
    if (!it->first.IsScalar()) fail_at(file, it->first, path, "a key must be a plain name");
    const std::string key = it->first.Scalar();
    const std::string key_path = path.empty() ? key : path + "." + key;
    const YAML::Node& base_const = base;
    if (!base_const[key].IsDefined()) fail_at(file, it->first, key_path, "unknown key (not in robot.yaml)");
    YAML::Node target = base[key];
    if (target.IsMap() != it->second.IsMap())
      fail_at(file, it->first, key_path,
              target.IsMap() ? "expected a map, as in robot.yaml" : "expected a value, not a map");
    if (it->second.IsMap()) {
      merge_map(target, it->second, file, key_path, prov);
    } else {
      target = it->second;  // shares the node: its mark (line) stays that of `file`
      prov->values.push_back({it->second, file, key_path});
    }
  }
}

std::string profile_path(const std::string& config_path, const std::string& name) {
  return (fs::path(profiles_dir(config_path)) / (name + ".yaml")).string();
}

// The profile named on the command line or by the scenario (file:line of
// its `robot.profile`), checked; "" for none.
std::string choose_profile(const std::string& config_path, const std::string& cli, const YAML::Node* named_or_null,
                           const std::string& scenario) {
  std::string name = cli;
  const YAML::Node named = named_or_null ? *named_or_null : YAML::Node();
  if (named_or_null) {
    if (!named.IsScalar() || named.Scalar().empty())
      fail_at(scenario, named, "robot.profile", "expected the name of a robot profile");
    if (!cli.empty() && cli != named.Scalar())
      fail_at(scenario, named, "robot.profile",
              "the scenario's robot is '" + named.Scalar() + "' but --robot names '" + cli +
                  "' (one robot per run: drop --robot, or give the scenario's)");
    name = named.Scalar();
  }
  if (name.empty()) return name;
  const std::string path = profile_path(config_path, name);
  std::error_code ec;
  if (!valid_name(name) || !fs::is_regular_file(path, ec)) {
    const std::string why =
        "no robot profile '" + name + "' (" + path + "; profiles: " + join(profile_names(config_path)) + ")";
    if (named_or_null) fail_at(scenario, named, "robot.profile", why);
    throw ConfigError("--robot " + name + ": " + why);
  }
  return name;
}

void merge_profile(YAML::Node root, const std::string& path, Provenance* prov) {
  const Node profile = load_file(path);
  const auto& known = robot_sections();
  for (auto it = profile.yaml().begin(); it != profile.yaml().end(); ++it) {
    const std::string key = it->first.IsScalar() ? it->first.Scalar() : "";
    if (std::find(known.begin(), known.end(), key) == known.end())
      fail_at(path, it->first, key, "unknown section (a profile holds robot.yaml sections)");
    if (!it->second.IsMap()) fail_at(path, it->first, key, "expected a map, as in robot.yaml");
  }
  merge_map(root, profile.yaml(), path, "", prov);
}

// The scenario's own robot values, as a partial robot.yaml whose values are
// the scenario's nodes (so their lines stay the scenario's).
YAML::Node child(const YAML::Node& map, const char* key) {
  return map.IsDefined() && map.IsMap() && map[key].IsDefined() ? map[key] : YAML::Node();
}

YAML::Node scenario_layer(const YAML::Node& sc) {
  YAML::Node layer(YAML::NodeType::Map);
  const YAML::Node footprint = child(child(sc, "robot"), "footprint");
  if (child(footprint, "length").IsScalar()) layer["robot"]["footprint_length_m"] = child(footprint, "length");
  if (child(footprint, "width").IsScalar()) layer["robot"]["footprint_width_m"] = child(footprint, "width");
  const YAML::Node lidar = child(sc, "lidar");
  if (child(lidar, "model").IsScalar()) layer["lidar"]["model"] = child(lidar, "model");
  if (child(lidar, "height").IsScalar()) layer["lidar"]["mount"]["z_m"] = child(lidar, "height");
  return layer;
}

}  // namespace

const std::string* Provenance::file_of(const YAML::Node& value) const {
  for (auto it = values.rbegin(); it != values.rend(); ++it)
    if (it->node.is(value)) return &it->file;
  return nullptr;
}

std::string profiles_dir(const std::string& config_path) {
  return (fs::path(config_path).parent_path() / "robots").string();
}

std::vector<std::string> profile_names(const std::string& config_path) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(profiles_dir(config_path), ec))
    if (e.path().extension() == ".yaml") out.push_back(e.path().stem().string());
  std::sort(out.begin(), out.end());
  return out;
}

Node load_robot_config(const std::string& path, const RobotSelection& selection) {
  Node root = load_file(path);
  auto prov = std::make_shared<Provenance>();
  YAML::Node scenario;
  if (!selection.scenario.empty()) scenario = load_file(selection.scenario).yaml();
  const YAML::Node robot = child(scenario, "robot");
  const bool names = robot.IsMap() && robot["profile"].IsDefined();
  const YAML::Node named = names ? child(robot, "profile") : YAML::Node();
  prov->profile = choose_profile(path, selection.profile, names ? &named : nullptr, selection.scenario);
  if (!prov->profile.empty()) merge_profile(root.yaml(), profile_path(path, prov->profile), prov.get());
  if (!selection.scenario.empty()) merge_map(root.yaml(), scenario_layer(scenario), selection.scenario, "", prov.get());
  root.set_provenance(prov);
  check_robot_config(root);
  return root;
}

Footprint effective_footprint(const Node& root) {
  const Node robot = root.section("robot");
  Footprint f;
  f.length_m = robot.get_positive("footprint_length_m");
  f.width_m = robot.get_positive("footprint_width_m");
  f.profile = root.provenance() && !root.provenance()->profile.empty() ? root.provenance()->profile : "none";
  const std::string length = robot.source("footprint_length_m");
  const std::string width = robot.source("footprint_width_m");
  const std::string length_file = length.substr(0, length.rfind(':'));
  if (width.substr(0, width.rfind(':')) == length_file) {
    f.source = length + "," + width.substr(width.rfind(':') + 1);
  } else {
    f.source = length + " (length), " + width + " (width)";
  }
  return f;
}

std::string footprint_line(const Node& root) {
  const Footprint f = effective_footprint(root);
  char buf[96];
  std::snprintf(buf, sizeof(buf), "footprint %.3g x %.3g m", f.length_m, f.width_m);
  return std::string(buf) + ", profile " + f.profile + ", source " + f.source;
}

}  // namespace evade::config
