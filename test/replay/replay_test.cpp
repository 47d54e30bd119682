// Log-playback regression: every process of every case in logs/ replayed
// through its core must reproduce its reference outputs (within the
// tolerances documented in process_replay.cpp). When a change of behaviour
// is intended, regenerate the references with
//   build/bin/process-replay --update-refs
// and commit them with the change.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bus/lcm_schema.h"
#include "bus/log.h"
#include "process_replay.h"

namespace fs = std::filesystem;

namespace evade::replay {
namespace {

const std::string kLogs = std::string(EVADE_SOURCE_DIR) + "/logs";

std::vector<std::string> cases() {
  std::vector<std::string> out;
  if (fs::exists(kLogs))
    for (const auto& d : fs::directory_iterator(kLogs))
      if (fs::exists(d.path() / "input.lcmlog")) out.push_back(d.path().filename());
  std::sort(out.begin(), out.end());
  return out;
}

config::Node repo_config() { return config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"); }

TEST(ProcessReplay, GoldenCasesExist) {
  auto c = cases();
  EXPECT_GE(c.size(), 2u) << "logs/ should hold at least two cases";
  uintmax_t bytes = 0;
  for (const auto& e : fs::recursive_directory_iterator(kLogs))
    if (e.is_regular_file()) bytes += e.file_size();
  // the budget of a clone: two cases, each an elevation_map reference of 60
  // maps of 240 x 240 cells (8.6 MB) and a 4.5 MB input (logs/README.md)
  EXPECT_LT(bytes, 32u * 1024 * 1024) << "logs/ must stay under 32 MB";
}

// A change of lcmtypes changes fingerprints: golden logs recorded before it
// no longer decode and must be recorded again (process-replay --cut).
TEST(ProcessReplay, EveryGoldenMessageDecodesWithTheCurrentTypes) {
  for (const auto& c : cases()) {
    size_t bad = 0, n = 0;
    std::string first_bad;
    for (const auto& e : bus::read_log(fs::path(kLogs) / c / "input.lcmlog")) {
      ++n;
      if (!bus::LcmSchema::evade().decode(e.data.data(), e.data.size())) {
        if (!bad++) first_bad = e.channel;
      }
    }
    EXPECT_EQ(bad, 0u) << c << ": " << bad << " of " << n << " messages do not decode (first on " << first_bad
                       << "); record the case again";
  }
}

class EveryProcess : public ::testing::TestWithParam<std::tuple<std::string, std::string>> {};

TEST_P(EveryProcess, MatchesReference) {
  const auto& [case_name, process] = GetParam();
  const ProcessCase* pc = nullptr;
  for (const auto& c : process_cases())
    if (c.process == process) pc = &c;
  ASSERT_NE(pc, nullptr);
  fs::path dir = fs::path(kLogs) / case_name;
  fs::path ref = dir / "refs" / (process + ".lcmlog");
  ASSERT_TRUE(fs::exists(ref)) << ref << " missing: build/bin/process-replay --update-refs";
  auto out = run_process(*pc, bus::read_log(dir / "input.lcmlog"), repo_config());
  auto rep = bus::diff_logs(out, bus::read_log(ref), pc->diff);
  EXPECT_GT(rep.compared_messages, 0u) << "no outputs to compare";
  std::string lines;
  for (const auto& l : rep.lines) lines += "  " + l + "\n";
  EXPECT_TRUE(rep.same()) << process << " on " << case_name << ": " << rep.differing_messages << " of "
                          << rep.compared_messages << " messages differ (" << pc->why << ")\n"
                          << lines << "If the change is intended: build/bin/process-replay --update-refs";
}

std::vector<std::tuple<std::string, std::string>> all_pairs() {
  std::vector<std::tuple<std::string, std::string>> out;
  for (const auto& c : cases())
    for (const auto& p : process_cases()) out.emplace_back(c, p.process);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Logs, EveryProcess, ::testing::ValuesIn(all_pairs()),
                         [](const auto& info) { return std::get<0>(info.param) + "_" + std::get<1>(info.param); });
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(EveryProcess);

// The regression must catch a change of behaviour: a different parameter
// changes what the mapping and tracking produce.
TEST(ProcessReplay, ABehaviourChangeFails) {
  auto c = cases();
  ASSERT_FALSE(c.empty());
  fs::path dir = fs::path(kLogs) / c.front();
  auto input = bus::read_log(dir / "input.lcmlog");
  // Same configuration text with the elevation map's step limit lowered.
  std::ifstream f(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string text = ss.str();
  auto pos = text.find("step_max_m:");
  ASSERT_NE(pos, std::string::npos) << "elevation_map.step_max_m not in robot.yaml";
  auto eol = text.find('\n', pos);
  text.replace(pos, eol - pos, "step_max_m: 0.02");
  auto changed = config::load_string(text, "changed.yaml");
  for (const auto& pc : process_cases()) {
    if (pc.process != "elevation_map") continue;
    auto out = run_process(pc, input, changed);
    auto rep = bus::diff_logs(out, bus::read_log(dir / "refs" / "elevation_map.lcmlog"), pc.diff);
    EXPECT_FALSE(rep.same()) << "a lower step limit should change the obstacle layer";
  }
}

}  // namespace
}  // namespace evade::replay
