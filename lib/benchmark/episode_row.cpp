#include "benchmark/episode_row.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace evade::benchmark {
namespace {

using Json = nlohmann::ordered_json;

// Keys of metrics.json that every row carries (SPEC "Metrics").
const char* const kRequiredBool[] = {"success", "reached_goal", "collided", "at_fault", "timed_out"};
const char* const kRequiredInt[] = {"collisions_at_fault", "collisions_not_at_fault"};
const char* const kRequiredNumberOrNull[] = {"min_dist_m", "time_to_goal_s", "planner_cycle_ms_p99"};
// Copied when present.
const char* const kOptional[] = {
    "contacts",        "reaction_time_s",      "speed_var", "path_length_m", "planner_solve_ms_p99",
    "solver_failures", "final_goal_distance_m"};

Json id_json(const EpisodeId& id) {
  Json j;
  j["family"] = id.family;
  j["seed"] = id.seed;
  j["mode"] = id.mode;
  return j;
}

void add_run_fields(Json& j, const EpisodeId& id) {
  j["host"] = id.host;
  j["scenario_sha256"] = id.scenario_sha256;
  j["exit_code"] = id.exit_code;
  j["wall_s"] = id.wall_s;
  j["dir"] = id.dir;
}

const Json& need(const Json& j, const char* key, const char* what) {
  auto it = j.find(key);
  if (it == j.end()) throw std::runtime_error(std::string("missing key '") + key + "'" + what);
  return *it;
}

std::optional<double> number_or_null(const Json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  if (!it->is_number()) throw std::runtime_error(std::string("key '") + key + "' is not a number");
  return it->get<double>();
}

bool boolean(const Json& j, const char* key) {
  const Json& v = need(j, key, "");
  if (!v.is_boolean()) throw std::runtime_error(std::string("key '") + key + "' is not true/false");
  return v.get<bool>();
}

int integer(const Json& j, const char* key) {
  const Json& v = need(j, key, "");
  if (!v.is_number_integer()) throw std::runtime_error(std::string("key '") + key + "' is not an integer");
  return v.get<int>();
}

// Keys of perception-metrics' JSON that a row carries (they pool).
const char* const kPerceptionKeys[] = {
    "objects",     "matches",         "misses",         "false_positives", "splits",
    "merges",      "id_switches",     "fragmentations", "motp_m",          "track_s",
    "predictions", "ade_1s_m",        "fde_2_5s_m",     "walker_ade_1s_m", "walker_predictions",
    "step_dt_s",   "coverage_inside", "coverage_n"};

// Optional keys (newer than some rows): copied when present.
const char* const kPerceptionOptionalKeys[] = {"static_track_frames", "static_moving_frames", "static_speed_mean_mps"};

Json perception_subset(const std::string& text) {
  Json p;
  try {
    p = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw std::runtime_error(std::string("perception JSON is not JSON: ") + e.what());
  }
  Json out = Json::object();
  for (const char* k : kPerceptionKeys) out[k] = need(p, k, " in the perception JSON");
  for (const char* k : kPerceptionOptionalKeys)
    if (p.contains(k)) out[k] = p[k];
  return out;
}

std::vector<int64_t> counts(const Json& j, const char* key) {
  const Json& v = need(j, key, " in perception");
  if (!v.is_array()) throw std::runtime_error(std::string("perception '") + key + "' is not a list");
  std::vector<int64_t> out;
  for (const Json& x : v) {
    if (!x.is_number_integer()) throw std::runtime_error(std::string("perception '") + key + "' has a non-integer");
    out.push_back(x.get<int64_t>());
  }
  return out;
}

std::string text(const Json& j, const char* key) {
  const Json& v = need(j, key, "");
  if (!v.is_string()) throw std::runtime_error(std::string("key '") + key + "' is not a string");
  return v.get<std::string>();
}

PerceptionCounts parse_perception(const Json& p) {
  if (!p.is_object()) throw std::runtime_error("key 'perception' is not an object");
  auto whole = [&](const char* k) {
    const Json& v = need(p, k, " in perception");
    if (!v.is_number_integer()) throw std::runtime_error(std::string("perception '") + k + "' is not an integer");
    return v.get<int64_t>();
  };
  PerceptionCounts c;
  c.objects = whole("objects");
  c.matches = whole("matches");
  c.misses = whole("misses");
  c.false_positives = whole("false_positives");
  c.splits = whole("splits");
  c.merges = whole("merges");
  c.id_switches = whole("id_switches");
  c.fragmentations = whole("fragmentations");
  c.centre_error_sum_m = number_or_null(p, "motp_m").value_or(0.0) * static_cast<double>(c.matches);
  c.track_s = number_or_null(p, "track_s").value_or(0.0);
  c.predictions = whole("predictions");
  c.ade_1s_m = number_or_null(p, "ade_1s_m");
  c.fde_2_5s_m = number_or_null(p, "fde_2_5s_m");
  c.walker_ade_1s_m = number_or_null(p, "walker_ade_1s_m");
  c.walker_predictions = whole("walker_predictions");
  c.step_dt_s = number_or_null(p, "step_dt_s").value_or(0.0);
  if (p.contains("static_track_frames")) {
    c.static_track_frames = whole("static_track_frames");
    c.static_moving_frames = whole("static_moving_frames");
    c.static_speed_sum_mps =
        number_or_null(p, "static_speed_mean_mps").value_or(0.0) * static_cast<double>(c.static_track_frames);
  }
  c.coverage_inside = counts(p, "coverage_inside");
  c.coverage_n = counts(p, "coverage_n");
  if (c.coverage_inside.size() != c.coverage_n.size())
    throw std::runtime_error("perception coverage lists differ in length");
  return c;
}

}  // namespace

std::string make_row(const EpisodeId& id, const std::string& metrics_json_text,
                     const std::string& perception_json_text) {
  Json m;
  try {
    m = Json::parse(metrics_json_text);
  } catch (const Json::parse_error& e) {
    throw std::runtime_error(std::string("metrics.json is not JSON: ") + e.what());
  }
  if (!m.is_object()) throw std::runtime_error("metrics.json is not a JSON object");
  Json row = id_json(id);
  for (const char* k : kRequiredBool) {
    const Json& v = need(m, k, " in metrics.json");
    if (!v.is_boolean()) throw std::runtime_error(std::string("metrics.json: '") + k + "' is not true/false");
    row[k] = v;
  }
  for (const char* k : kRequiredInt) {
    const Json& v = need(m, k, " in metrics.json");
    if (!v.is_number_integer()) throw std::runtime_error(std::string("metrics.json: '") + k + "' is not an integer");
    row[k] = v;
  }
  for (const char* k : kRequiredNumberOrNull) {
    const Json& v = need(m, k, " in metrics.json");
    if (!v.is_number() && !v.is_null())
      throw std::runtime_error(std::string("metrics.json: '") + k + "' is not a number or null");
    row[k] = v;
  }
  for (const char* k : kOptional)
    if (m.contains(k)) row[k] = m[k];
  if (!perception_json_text.empty()) row["perception"] = perception_subset(perception_json_text);
  add_run_fields(row, id);
  return row.dump();
}

std::string make_error_row(const EpisodeId& id, const std::string& error) {
  Json row = id_json(id);
  row["error"] = error;
  add_run_fields(row, id);
  return row.dump();
}

Episode parse_row(const std::string& line) {
  Json j;
  try {
    j = Json::parse(line);
  } catch (const Json::parse_error& e) {
    throw std::runtime_error(std::string("not JSON: ") + e.what());
  }
  if (!j.is_object()) throw std::runtime_error("a row is a JSON object");
  Episode e;
  e.id.family = text(j, "family");
  const Json& seed = need(j, "seed", "");
  if (!seed.is_number_integer()) throw std::runtime_error("key 'seed' is not an integer");
  e.id.seed = seed.get<int64_t>();
  e.id.mode = text(j, "mode");
  if (j.contains("host")) e.id.host = text(j, "host");
  if (j.contains("scenario_sha256")) e.id.scenario_sha256 = text(j, "scenario_sha256");
  if (j.contains("exit_code")) e.id.exit_code = integer(j, "exit_code");
  if (j.contains("dir")) e.id.dir = text(j, "dir");
  e.id.wall_s = number_or_null(j, "wall_s").value_or(0.0);
  if (j.contains("error")) {
    e.error = text(j, "error");
    if (e.error.empty()) throw std::runtime_error("key 'error' is empty");
    return e;
  }
  e.success = boolean(j, "success");
  e.reached_goal = boolean(j, "reached_goal");
  e.collided = boolean(j, "collided");
  e.at_fault = boolean(j, "at_fault");
  e.timed_out = boolean(j, "timed_out");
  e.collisions_at_fault = integer(j, "collisions_at_fault");
  e.collisions_not_at_fault = integer(j, "collisions_not_at_fault");
  for (const char* k : kRequiredNumberOrNull) need(j, k, "");
  e.min_dist_m = number_or_null(j, "min_dist_m");
  e.time_to_goal_s = number_or_null(j, "time_to_goal_s");
  e.planner_cycle_ms_p99 = number_or_null(j, "planner_cycle_ms_p99");
  e.reaction_time_s = number_or_null(j, "reaction_time_s");
  e.speed_var = number_or_null(j, "speed_var");
  if (j.contains("perception")) e.perception = parse_perception(j["perception"]);
  return e;
}

std::vector<Episode> read_results(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path);
  std::vector<Episode> rows;
  std::string line;
  for (int n = 1; std::getline(f, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      rows.push_back(parse_row(line));
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ":" + std::to_string(n) + ": " + e.what());
    }
  }
  return rows;
}

}  // namespace evade::benchmark
