// process-replay [--update-refs] [--logs DIR] [--case NAME] [--process NAME]
// process-replay --cut RUN.lcmlog --start-s S --duration-s D --case NAME
//
// Replays every process of every case in logs/ through its core and compares
// the outputs with logs/<case>/refs/<process>.lcmlog (see process_replay.h).
// Exit 0 when everything matches. --update-refs rewrites the references
// from the current code and configuration (a deliberate behaviour change).
// --cut makes a new case from a run log (e.g. one left by run_scenario); it
// refuses to replace an existing case's input without --force.
#include <sys/stat.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "bus/log.h"
#include "bus/process_main.h"
#include "config/robot_profile.h"
#include "process_replay.h"

namespace fs = std::filesystem;

namespace {

// --cut: the case `name` under `logs` from a window of the run log `cut`;
// false (after one line on stderr) when the case exists and not `force`.
bool make_case(const std::string& cut, const std::string& logs, const std::string& name, double start_s,
               double duration_s, bool force) {
  if (name.empty()) throw std::runtime_error("--cut needs --case NAME");
  const std::string existing = logs + "/" + name + "/input.lcmlog";
  if (fs::exists(existing) && !force) {
    std::fprintf(stderr, "process-replay: case %s exists (%s); refusing to replace it without --force\n", name.c_str(),
                 existing.c_str());
    return false;
  }
  std::vector<std::string> channels{
      "LIDAR_SCAN",           "ODOMETRY", "ROUTE",   "ELEVATION_MAP", "OBSTACLES", "OCCLUSIONS",
      "OBSTACLE_PREDICTIONS", "PLAN",     "CMD_VEL", "SIM_TRUTH"};
  auto events = evade::replay::cut_case(evade::bus::read_log(cut), start_s, duration_s, channels);
  fs::create_directories(logs + "/" + name + "/refs");
  evade::bus::write_log(existing, events);
  std::printf("process-replay: case %s: %zu events from %s [%.1f s, %.1f s)\n", name.c_str(), events.size(),
              cut.c_str(), start_s, start_s + duration_s);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Log-playback regression: replay each process over logged inputs and diff against references"};
  std::string logs = std::string(EVADE_SOURCE_DIR) + "/logs", only_case, only_process, cut;
  evade::bus::CommonOptions opts;
  bool update = false;
  double start_s = 0, duration_s = 4;
  app.add_flag("--update-refs", update, "rewrite the references from the current code");
  app.add_option("--logs", logs, "folder of cases (default: the repository's logs/)");
  app.add_option("--case", only_case, "only this case (or: the name of the case --cut makes)");
  app.add_option("--process", only_process, "only this process");
  evade::bus::add_robot_options(app, opts, false);  // --config (default: the repository's), --robot
  app.add_option("--cut", cut, "make a case from this run log");
  app.add_option("--start-s", start_s, "with --cut: window start after the log's first event");
  app.add_option("--duration-s", duration_s, "with --cut: window length");
  bool force = false;
  app.add_flag("--force", force, "with --cut: replace an existing case");
  CLI11_PARSE(app, argc, argv);
  const std::string config_path =
      opts.config_path.empty() ? std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml" : opts.config_path;

  try {
    auto root = evade::config::load_robot_config(config_path, {opts.robot, ""});
    if (!cut.empty()) {
      if (!make_case(cut, logs, only_case, start_s, duration_s, force)) return 2;
      update = true;  // a new case starts with references from the current code
    }
    int failures = 0, compared = 0;
    for (const auto& dir : fs::directory_iterator(logs)) {
      if (!dir.is_directory() || !fs::exists(dir.path() / "input.lcmlog")) continue;
      std::string name = dir.path().filename();
      if (!only_case.empty() && name != only_case) continue;
      auto input = evade::bus::read_log(dir.path() / "input.lcmlog");
      for (const auto& pc : evade::replay::process_cases()) {
        if (!only_process.empty() && pc.process != only_process) continue;
        auto out = evade::replay::run_process(pc, input, root);
        fs::path ref = dir.path() / "refs" / (pc.process + ".lcmlog");
        if (update) {
          fs::create_directories(ref.parent_path());
          evade::bus::write_log(ref, out);
          std::printf("process-replay: %s/%s: reference written (%zu messages)\n", name.c_str(), pc.process.c_str(),
                      out.size());
          continue;
        }
        ++compared;
        if (!fs::exists(ref)) {
          std::printf("process-replay: %s/%s: FAIL: no reference (run with --update-refs)\n", name.c_str(),
                      pc.process.c_str());
          ++failures;
          continue;
        }
        auto rep = evade::bus::diff_logs(out, evade::bus::read_log(ref), pc.diff);
        if (rep.same()) {
          std::printf("process-replay: %s/%s: ok (%zu messages)\n", name.c_str(), pc.process.c_str(),
                      rep.compared_messages);
        } else {
          ++failures;
          std::printf("process-replay: %s/%s: FAIL: %zu of %zu messages differ\n", name.c_str(), pc.process.c_str(),
                      rep.differing_messages, rep.compared_messages);
          for (const auto& l : rep.lines) std::printf("    %s\n", l.c_str());
        }
      }
    }
    if (!update) std::printf("process-replay: %d compared, %d failed\n", compared, failures);
    return failures ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "process-replay: %s\n", e.what());
    return 2;
  }
}
