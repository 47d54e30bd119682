// scenario-gen --family F --seed K [--out FILE] [--config ROBOT.yaml] [--robot NAME]
//              [--families FAMILIES.yaml]
// scenario-gen --check SCENARIO.yaml [--config ...] [--families ...]
// scenario-gen --list
// Writes one scenario of family F drawn with seed K (lib/sim/scenario_gen.h)
// to FILE, or to stdout. The same family, seed and configuration give the
// same bytes. --check prints the validity rules a scenario file breaks
// (lib/sim/scenario_check.h), one a line; exit 1 if any. The robot is that
// of --config merged with --robot's profile (config/robot_profile.h): its
// footprint, LiDAR model and height go into the scene, which names the
// profile (robot.profile).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "bus/process_main.h"
#include "config/config.h"
#include "config/robot_profile.h"
#include "sim/scenario_gen.h"

namespace {

// Writes next to `path` first, then renames, so a failed write leaves any
// earlier file whole.
void write_file(const std::string& path, const std::string& text) {
  std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    if (!f) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

// A scenario to check, its robot resolved from the configuration.
evade::sim::Scenario checked(const std::string& path, const evade::config::Node& root) {
  evade::sim::Scenario sc = evade::sim::load_scenario(path);
  evade::sim::resolve_robot(&sc, root);
  return sc;
}

}  // namespace

int main(int argc, char** argv) {
  namespace gen = evade::sim::gen;
  CLI::App app{"Write a randomized scenario of one family (lib/sim/README.md)"};
  std::string family, out, families_path, check;
  evade::bus::CommonOptions opts;
  uint64_t seed = 1;
  bool list = false;
  app.add_option("--family", family,
                 "crossing, headon, overtaking, crowd, doorway, occlusion, fast_small, "
                 "static_clutter or mixed");
  app.add_option("--seed", seed, "random seed, 0 to 2^63 - 1 (also the scenario's sensor noise seed)");
  app.add_option("--out", out, "scenario file to write (default: stdout)");
  evade::bus::add_robot_options(app, opts, false);  // --config, --robot
  app.add_option("--families", families_path, "family ranges (default: config/scenario_families.yaml)");
  app.add_flag("--list", list, "print the family names and exit");
  app.add_option("--check", check, "print the validity rules this scenario file breaks (exit 1 if any)");
  CLI11_PARSE(app, argc, argv);
  if (list) {
    for (const auto& f : gen::family_names()) std::printf("%s\n", f.c_str());
    return 0;
  }
  if (family.empty() && check.empty()) {
    std::fprintf(stderr, "scenario-gen: --family is required (--list names them)\n");
    return 2;
  }
  try {
    const std::string config_path = opts.config_path.empty() ? evade::config::default_config_path() : opts.config_path;
    if (families_path.empty()) families_path = gen::default_families_path();
    const evade::config::Node root =
        evade::config::load_robot_config(config_path, {opts.robot, check.empty() ? "" : check});
    const gen::RobotFacts robot = gen::RobotFacts::from_config(root);
    gen::FamilyParams params = gen::FamilyParams::from_config(evade::config::load_file(families_path), robot);
    if (!check.empty()) {
      std::vector<std::string> problems =
          evade::sim::check_scenario(checked(check, root), gen::check_params(params, robot));
      for (const auto& p : problems) std::printf("%s: %s\n", check.c_str(), p.c_str());
      return problems.empty() ? 0 : 1;
    }
    gen::Generated g = gen::generate(family, seed, params, robot);
    if (out.empty())
      std::cout << g.yaml << std::flush;
    else
      write_file(out, g.yaml);
  } catch (const evade::config::ConfigError& e) {
    std::fprintf(stderr, "scenario-gen: %s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "scenario-gen: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scenario-gen: %s\n", e.what());
    return 1;
  }
  return 0;
}
