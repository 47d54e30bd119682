// docs/SPEC.md names exactly the channels, lcm types and processes the
// repository has (spec_check.h says how each side is read); the other tests
// show that each kind of disagreement is caught.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "spec_check.h"

namespace evade::spec {
namespace {

const std::string kRoot = EVADE_SOURCE_DIR;

std::string spec_text() {
  std::ifstream in(kRoot + "/docs/SPEC.md");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += "  " + l + "\n";
  return out;
}

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems)
    if (p.find(text) != std::string::npos) return true;
  return false;
}

// The SPEC without the table row that starts with `cell`.
std::string without_row(const std::string& md, const std::string& cell) {
  const size_t at = md.find("\n| " + cell + " |");
  if (at == std::string::npos) return md;
  return md.substr(0, at) + md.substr(md.find('\n', at + 1));
}

TEST(Spec, MatchesTheRepository) {
  const std::string text = spec_text();
  ASSERT_FALSE(text.empty()) << kRoot << "/docs/SPEC.md";
  const Spec spec = parse_spec(text);
  const Code code = scan_repository(kRoot);
  // Both sides were read at all (a parser that finds nothing agrees with anything).
  EXPECT_GE(spec.channel_type.size(), 11u);
  EXPECT_GE(spec.binaries.size(), 8u);
  EXPECT_GE(spec.tools.size(), 3u);
  EXPECT_GE(code.types.size(), 19u);
  EXPECT_GE(code.uses.size(), 20u);
  const auto problems = compare(spec, code);
  EXPECT_TRUE(problems.empty()) << "docs/SPEC.md and the code disagree:\n"
                                << joined(problems)
                                << "A new channel, type or process goes into docs/SPEC.md, with a line in its "
                                   "Changes section naming the issue.";
}

TEST(Spec, AnUndocumentedChannelIsReported) {
  const std::string text = without_row(spec_text(), "`LIDAR_SCAN`");
  ASSERT_NE(text, spec_text()) << "the channel table has no LIDAR_SCAN row to remove";
  const auto problems = compare(parse_spec(text), scan_repository(kRoot));
  EXPECT_TRUE(mentions(problems, "channel LIDAR_SCAN (used at lib/")) << joined(problems);
  // its types are then named nowhere in the SPEC either
  EXPECT_TRUE(mentions(problems, "type evade.lidar_scan_t (lcmtypes/) is not in the SPEC")) << joined(problems);
}

TEST(Spec, ADocumentedChannelNoCodeUsesIsReported) {
  std::string text = spec_text();
  const size_t at = text.find("| `ODOMETRY` |");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, "| `DOCKING` | `evade.odometry_t` | utime |\n");
  const auto problems = compare(parse_spec(text), scan_repository(kRoot));
  EXPECT_TRUE(mentions(problems, "channel DOCKING is in the SPEC but no source")) << joined(problems);
}

TEST(Spec, TypesAndProcessesAreComparedBothWays) {
  const Spec spec = parse_spec(spec_text());
  Code code = scan_repository(kRoot);
  code.types.insert("evade.docking_t");
  code.types.erase("evade.cmd_vel_t");
  code.binaries.insert("docker");
  code.binaries.erase("tracker");
  const auto problems = compare(spec, code);
  EXPECT_TRUE(mentions(problems, "type evade.docking_t (lcmtypes/) is not in the SPEC")) << joined(problems);
  EXPECT_TRUE(mentions(problems, "type evade.cmd_vel_t is in the SPEC but not in lcmtypes/")) << joined(problems);
  EXPECT_TRUE(mentions(problems, "process docker (procs/*/CMakeLists.txt) is not in the SPEC")) << joined(problems);
  EXPECT_TRUE(mentions(problems, "process tracker is in the SPEC but not in procs/")) << joined(problems);
}

TEST(Spec, ProcessTableAndToolsAreChecked) {
  std::string text = spec_text();
  const size_t at = text.find("`OBSTACLE_PREDICTIONS` |");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, "`DOCKING`, ");
  Code code = scan_repository(kRoot);
  code.tools.erase("lcmlog-export");
  const auto problems = compare(parse_spec(text), code);
  EXPECT_TRUE(mentions(problems, "the process table names DOCKING")) << joined(problems);
  EXPECT_TRUE(mentions(problems, "tool lcmlog-export is in the SPEC")) << joined(problems);
}

TEST(Spec, SourceScanResolvesConstantsAndCatchesWhatItCannotName) {
  const Spec spec = parse_spec(spec_text());
  Code code = scan_repository(kRoot);
  ASSERT_TRUE(compare(spec, code).empty());
  // A constant defined in one file and used in another; comments do not count.
  scan_source("a.h", "inline constexpr const char* kDockChannel = \"DOCK\";\n", false, &code);
  scan_source("b.cpp",
              "// publish(\"GHOST\", m);\n/* subscribe<evade::x_t>(\"GHOST2\", f); */\n"
              "void f() {\n  publish(kDockChannel,\n          msg);\n  publish(topic_, msg);\n"
              "  subscribe<evade::path_t>(\"ODOMETRY\", h);\n  if (e.channel == \"REPLAYED\") {}\n}\n",
              false, &code);
  scan_source("lib/other/node.cpp",
              "void Node::publish(const std::string& channel, int64_t now) {}\n"
              "void g() { publish(std::string(\"X\"), m); }\n",
              false, &code);
  scan_source("lib/bus/x.cpp", "void Bus::publish(const std::string& channel, int n) { lcm_->publish(channel, n); }",
              true, &code);
  const auto problems = compare(spec, code);
  EXPECT_TRUE(mentions(problems, "channel DOCK (used at a.h:1)")) << joined(problems);
  EXPECT_FALSE(mentions(problems, "b.cpp:4: `kDockChannel`")) << joined(problems);
  EXPECT_TRUE(mentions(problems, "b.cpp:6: `topic_` is neither")) << joined(problems);
  EXPECT_TRUE(mentions(problems, "ODOMETRY: the SPEC says evade.odometry_t, the code subscribes with evade.path_t"))
      << joined(problems);
  EXPECT_TRUE(mentions(problems, "channel REPLAYED (used at b.cpp:8)")) << joined(problems);
  EXPECT_FALSE(mentions(problems, "GHOST")) << joined(problems);
  EXPECT_FALSE(mentions(problems, "lib/bus/x.cpp")) << joined(problems);
  EXPECT_FALSE(mentions(problems, "node.cpp:1")) << joined(problems);  // a signature
  EXPECT_TRUE(mentions(problems, "node.cpp:2: `std::string` is neither")) << joined(problems);
  EXPECT_EQ(problems.size(), 5u) << joined(problems);
}

}  // namespace
}  // namespace evade::spec
