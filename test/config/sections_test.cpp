// Per section of config/robot.yaml (tools/src/config-dump/sections.h): the
// section loaded through its owner's field list and written back equals
// the YAML key by key (so every YAML key is a field and every field a
// key), the dump with source lines reads back the same, and the struct's
// C++ defaults equal the file (they cannot drift from it).
#include "sections.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "config/fields.h"

namespace evade::config_dump {
namespace {

const std::string kRobotYaml = std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml";

std::string lines(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& l : v) s += "  " + l + "\n";
  return s;
}

class SectionTest : public ::testing::TestWithParam<std::string> {
 protected:
  const Section& section() const {
    for (const auto& s : sections())
      if (s.name == GetParam()) return s;
    throw std::runtime_error("no section " + GetParam());
  }
};

TEST_P(SectionTest, LoadedAndWrittenBackEqualsTheYaml) {
  const config::Node root = config::load_robot_config(kRobotYaml);
  const YAML::Node written = section().load(root);
  const auto d = config::yaml_differences(written, root.section(GetParam()).yaml());
  EXPECT_TRUE(d.empty()) << "written (first) vs robot.yaml (second):\n" << lines(d);
}

TEST_P(SectionTest, TheDumpWithSourceLinesReadsBackAsTheYaml) {
  const config::Node root = config::load_robot_config(kRobotYaml);
  const config::Node s = root.section(GetParam());
  const std::string text = config::dump_yaml(GetParam(), section().load(root), s);
  const auto d = config::yaml_differences(YAML::Load(text)[GetParam()], s.yaml());
  EXPECT_TRUE(d.empty()) << text << lines(d);
  // Every value line names robot.yaml and the line of its key there.
  const YAML::Node first = s.yaml().begin()->second;
  const std::string key = s.yaml().begin()->first.Scalar();
  if (!first.IsMap()) {
    EXPECT_NE(text.find("  " + key + ": "), std::string::npos);
  }
  EXPECT_EQ(text.find("# default"), std::string::npos) << text;
  EXPECT_NE(text.find("robot.yaml:" + std::to_string(first.Mark().line + 1)), std::string::npos) << text;
}

TEST_P(SectionTest, TheCppDefaultsAreTheYamlValues) {
  const config::Node root = config::load_robot_config(kRobotYaml);
  const auto d = config::yaml_differences(section().defaults(), section().load(root));
  EXPECT_TRUE(d.empty()) << "C++ default (first) vs robot.yaml (second):\n" << lines(d);
}

std::vector<std::string> names() {
  std::vector<std::string> out;
  for (const auto& s : sections()) out.push_back(s.name);
  return out;
}

INSTANTIATE_TEST_SUITE_P(RobotYaml, SectionTest, ::testing::ValuesIn(names()),
                         [](const auto& info) { return info.param; });

TEST(Sections, EveryRobotSectionHasAFieldList) {
  std::vector<std::string> have = names(), want = config::robot_sections();
  std::sort(have.begin(), have.end());
  std::sort(want.begin(), want.end());
  EXPECT_EQ(have, want);
}

TEST(Sections, AWrongValueStopsTheDumpWithFileLineKey) {
  const config::Node root = config::load_string("robot:\n  footprint_length_m: -1\n", "bad.yaml");
  try {
    (void)dump(root);
    FAIL() << "no error";
  } catch (const config::ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "bad.yaml:2: key 'robot.footprint_length_m': must be greater than 0");
  }
}

// Lines of the keys whose value is not a map. Flow maps (the rows of
// lockstep.costs) are a table under one comment, on their section.
void leaf_lines(const YAML::Node& map, std::vector<int>* out) {
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (!it->second.IsMap())
      out->push_back(it->first.Mark().line);
    else if (it->second.Style() != YAML::EmitterStyle::Flow)
      leaf_lines(it->second, out);
  }
}

// Each line past the file's header (its leading '#' lines) that holds only
// a comment, as "path:line: text" lines: a key's comment is one line, on
// the key's own line.
std::string comment_lines_past_header(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> text;
  for (std::string l; std::getline(in, l);) text.push_back(l);
  if (text.empty()) return path + ": cannot read";
  size_t header = 0;
  while (header < text.size() && text[header].rfind("#", 0) == 0) ++header;
  std::string out;
  for (size_t i = header; i < text.size(); ++i) {
    const size_t hash = text[i].find('#');
    if (hash != std::string::npos && text[i].find_first_not_of(' ') == hash)
      out += path + ":" + std::to_string(i + 1) + ": " + text[i] + "\n";
  }
  return out;
}

TEST(RobotYamlComments, EveryKeyHasOneCommentOnItsLine) {
  std::ifstream in(kRobotYaml);
  std::vector<std::string> text;
  for (std::string l; std::getline(in, l);) text.push_back(l);
  std::vector<int> leaves;
  leaf_lines(YAML::LoadFile(kRobotYaml), &leaves);
  ASSERT_GT(leaves.size(), 250u);
  for (int line : leaves)
    EXPECT_NE(text[size_t(line)].find(" # "), std::string::npos)
        << "robot.yaml:" << line + 1 << ": no comment: " << text[size_t(line)];
  EXPECT_EQ(comment_lines_past_header(kRobotYaml), "");
}

TEST(RobotYamlComments, TheFamiliesFileHasNoCommentOnALineOfItsOwn) {
  EXPECT_EQ(comment_lines_past_header(std::string(EVADE_SOURCE_DIR) + "/config/scenario_families.yaml"), "");
  // the check sees a continued comment
  const std::string path = ::testing::TempDir() + "/continued.yaml";
  std::ofstream(path) << "# header\n\na: 1  # one\n     # and more\nb: 2  # two\n";
  EXPECT_EQ(comment_lines_past_header(path), path + ":4:      # and more\n");
  std::remove(path.c_str());
}

}  // namespace
}  // namespace evade::config_dump
