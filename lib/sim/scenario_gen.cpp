#include "sim/scenario_gen.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "sim/scenario_gen_families.h"
#include "sim/scenario_writer.h"

namespace evade::sim::gen {
namespace {

using detail::Ctx;
using detail::Draft;
using Builder = bool (*)(Ctx&, Draft&);

Builder builder_of(const std::string& family) {
  if (family == "crossing") return detail::crossing;
  if (family == "headon") return detail::headon;
  if (family == "overtaking") return detail::overtaking;
  if (family == "crowd") return detail::crowd;
  if (family == "doorway") return detail::doorway;
  if (family == "occlusion") return detail::occlusion;
  if (family == "fast_small") return detail::fast_small;
  if (family == "static_clutter") return detail::static_clutter;
  return nullptr;
}

// Draws `families` of mixed.weights without replacement, by weight, and
// builds each on the same route.
bool mixed(Ctx& c, Draft& d) {
  std::vector<std::pair<std::string, double>> left;
  for (const auto& w : c.p.mixed.weights)
    if (w.second > 0.0) left.push_back(w);
  int n = c.rng.integer(c.p.mixed.families);
  for (int i = 0; i < n && !left.empty(); ++i) {
    double total = 0.0;
    for (const auto& w : left) total += w.second;
    double r = c.rng.uniform(0.0, total);
    size_t k = 0;
    while (k + 1 < left.size() && r >= left[k].second) r -= left[k++].second;
    if (!builder_of(left[k].first)(c, d)) return false;
    left.erase(left.begin() + static_cast<long>(k));
  }
  return true;
}

void finish(const Ctx& c, const std::string& family, uint64_t seed, Draft& d) {
  double length = detail::path_length(d.sc.route);
  d.sc.name = family + "_" + std::to_string(seed);
  d.sc.seed = seed;
  d.sc.duration_s =
      std::ceil(c.p.common.duration_factor * length / c.robot.reference_speed_mps + c.p.common.duration_slack_s);
}

std::vector<std::string> header(const std::string& family, uint64_t seed, const Draft& d) {
  std::vector<std::string> h{"tools/scenario-gen --family " + family + " --seed " + std::to_string(seed) +
                             " (ranges: config/scenario_families.yaml, lib/sim/README.md)."};
  for (const std::string& s : d.summary) h.push_back(s + ".");
  h.push_back("Times are nominal: the robot at the reference speed from its first motion, when obstacles start.");
  return h;
}

}  // namespace

ScenarioCheckParams check_params(const FamilyParams& p, const RobotFacts& robot) {
  ScenarioCheckParams c;
  c.start_margin_m = p.common.start_margin_m;
  c.start_clear_time_s = p.common.start_clear_time_s;
  c.goal_margin_m = p.common.goal_margin_m;
  c.passage_margin_m = p.common.passage_margin_m;
  c.min_height_m = robot.step_max_m + p.common.min_visible_height_m;
  return c;
}

Generated generate(const std::string& family, uint64_t seed, const FamilyParams& p, const RobotFacts& robot) {
  Builder build = family == "mixed" ? mixed : builder_of(family);
  if (!build) {
    std::string list;
    for (const auto& f : family_names()) list += (list.empty() ? "" : ", ") + f;
    throw std::invalid_argument("unknown family '" + family + "' (one of: " + list + ")");
  }
  if (seed > static_cast<uint64_t>(INT64_MAX))
    throw std::invalid_argument("seed " + std::to_string(seed) + " is above 2^63 - 1 (the scenario file's limit)");
  const ScenarioCheckParams check = check_params(p, robot);
  Rng rng(seed);
  Ctx c{p, robot, check, rng};
  std::vector<std::string> problems;
  for (int attempt = 1; attempt <= p.common.max_attempts; ++attempt) {
    Draft d = detail::straight_draft(c);
    if (!build(c, d)) {
      problems = {"could not place the family's obstacles"};
      continue;
    }
    finish(c, family, seed, d);
    Generated g;
    g.yaml = scenario_yaml(d.sc, header(family, seed, d), d.notes);
    g.scenario = parse_scenario(g.yaml, d.sc.name + ".yaml");
    g.attempts = attempt;
    problems = check_scenario(g.scenario, check);
    if (problems.empty()) return g;
  }
  std::string why;
  for (const auto& s : problems) why += "; " + s;
  throw std::runtime_error("family " + family + ", seed " + std::to_string(seed) + ": no valid scene in " +
                           std::to_string(p.common.max_attempts) + " attempts (last" + why + ")");
}

}  // namespace evade::sim::gen
