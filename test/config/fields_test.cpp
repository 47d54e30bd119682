// The field-list visitors (config/fields.h) on a small struct: load keeps
// the loader's strictness, to_yaml and load agree, check applies the same
// ranges and rules to a struct built in code, dump_yaml names file:line.
#include "config/fields.h"

#include <gtest/gtest.h>

namespace evade::config {
namespace {

enum class Colour { kRed, kBlue };

struct Inner {
  int count = 3;
  std::vector<double> xy{1.0, 2.0};
  template <class V>
  void fields(V& v) {
    v.field("count", count, between(1, 10));
    v.field("xy", xy, 2);
  }
};

struct Toy {
  double gap_s = 0.5;
  double min_m = 1.0;
  double max_m = 2.0;
  bool on = true;
  std::string name = "toy";
  Colour colour = Colour::kBlue;
  double angle_rad = M_PI / 4.0;
  Inner inner;
  template <class V>
  void fields(V& v) {
    v.field("gap_s", gap_s, positive());
    v.field("min_m", min_m, between(0.0, 10.0));
    v.field("max_m", max_m, between(0.0, 10.0));
    v.rule(max_m > min_m, "max_m", "must exceed min_m");
    v.field("on", on);
    v.field("name", name);
    v.choice("colour", colour, Choices<Colour>{{"red", Colour::kRed}, {"blue", Colour::kBlue}});
    v.convert("angle_deg", angle_rad, degrees_as_radians(between(0.0, 90.0)));
    v.section("inner", inner);
    v.rule(inner.count < 9 || on, "inner.count", "9 or more needs on");
  }
};

const char* kToy =
    "toy:\n"
    "  gap_s: 0.25\n"
    "  min_m: 1.0e-5\n"
    "  max_m: 3\n"
    "  on: false\n"
    "  name: hi\n"
    "  colour: red\n"
    "  angle_deg: 30\n"
    "  inner:\n"
    "    count: 4\n"
    "    xy: [5, 6.5]\n";

std::string with(const std::string& from, const std::string& to) {
  std::string s = kToy;
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

std::string load_error(const std::string& text) {
  try {
    (void)load<Toy>(load_string(text, "toy.yaml").section("toy"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Fields, LoadReadsEveryField) {
  const Toy t = load<Toy>(load_string(kToy, "toy.yaml").section("toy"));
  EXPECT_EQ(t.gap_s, 0.25);
  EXPECT_EQ(t.min_m, 1e-5);
  EXPECT_EQ(t.max_m, 3.0);
  EXPECT_FALSE(t.on);
  EXPECT_EQ(t.name, "hi");
  EXPECT_EQ(t.colour, Colour::kRed);
  EXPECT_DOUBLE_EQ(t.angle_rad, M_PI / 6.0);
  EXPECT_EQ(t.inner.count, 4);
  EXPECT_EQ(t.inner.xy, (std::vector<double>{5.0, 6.5}));
}

TEST(Fields, LoadErrorsNameFileLineAndKey) {
  EXPECT_EQ(load_error(with("  gap_s: 0.25\n", "  gap_s: 0\n")), "toy.yaml:2: key 'toy.gap_s': must be greater than 0");
  EXPECT_EQ(load_error(with("  max_m: 3\n", "  max_m: 0.000001\n")), "toy.yaml:4: key 'toy.max_m': must exceed min_m");
  EXPECT_EQ(load_error(with("  colour: red\n", "  colour: green\n")),
            "toy.yaml:7: key 'toy.colour': 'green' is not one of: red, blue");
  EXPECT_EQ(load_error(with("  angle_deg: 30\n", "  angle_deg: 91\n")),
            "toy.yaml:8: key 'toy.angle_deg': value 91 outside [0, 90]");
  EXPECT_EQ(load_error(with("    count: 4\n", "    count: 9\n")),
            "toy.yaml:10: key 'toy.inner.count': 9 or more needs on");
  EXPECT_EQ(load_error(with("  name: hi\n", "  name: hi\n  nmae: x\n")), "toy.yaml:7: key 'toy.nmae': unknown key");
  EXPECT_EQ(load_error(with("    xy: [5, 6.5]\n", "    xy: [5, 6.5]\n    z: 1\n")),
            "toy.yaml:12: key 'toy.inner.z': unknown key");
  EXPECT_EQ(load_error(with("  on: false\n", "")), "toy.yaml:2: key 'toy.on': missing");
}

TEST(Fields, WrittenValuesLoadBackTheSame) {
  const Toy t = load<Toy>(load_string(kToy, "toy.yaml").section("toy"));
  const YAML::Node y = to_yaml(t);
  const Toy again = load<Toy>(Node(YAML::Load(yaml_text(y)), "dump", "toy"));
  EXPECT_TRUE(yaml_differences(to_yaml(again), y).empty());
  EXPECT_TRUE(yaml_differences(y, load_string(kToy, "toy.yaml").section("toy").yaml()).empty());
}

TEST(Fields, DifferencesNameTheKey) {
  Toy a, b;
  b.inner.count = 5;
  b.name = "other";
  const auto d = yaml_differences(to_yaml(a), to_yaml(b));
  ASSERT_EQ(d.size(), 2u);
  EXPECT_EQ(d[0], "name: toy != other");
  EXPECT_EQ(d[1], "inner.count: 3 != 5");
  EXPECT_TRUE(yaml_differences(YAML::Load("a: 1.0e-5"), YAML::Load("a: 1e-05")).empty());
  EXPECT_EQ(yaml_differences(YAML::Load("a: 1"), YAML::Load("b: 1")).size(), 2u);
}

TEST(Fields, CheckAppliesTheRangesToAStructBuiltInCode) {
  Toy t;
  EXPECT_NO_THROW(check(t, "toy"));
  t.gap_s = -1.0;
  try {
    check(t, "toy");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "toy (built in code):1: key 'toy.gap_s': must be greater than 0");
  }
  t.gap_s = 1.0;
  t.max_m = 0.5;
  EXPECT_THROW(check(t, "toy"), ConfigError);
  t.max_m = 2.0;
  t.inner.count = 11;
  EXPECT_THROW(check(t, "toy"), ConfigError);
}

TEST(Fields, DumpNamesTheSourceLineOfEveryValue) {
  const Node root = load_string(kToy, "toy.yaml");
  const std::string text = dump_yaml("toy", to_yaml(load<Toy>(root.section("toy"))), root.section("toy"));
  EXPECT_NE(text.find("  gap_s: 0.25  # toy.yaml:2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("  angle_deg: 30  # toy.yaml:8\n"), std::string::npos) << text;
  EXPECT_NE(text.find("    xy: [5, 6.5]  # toy.yaml:11\n"), std::string::npos) << text;
  EXPECT_TRUE(yaml_differences(YAML::Load(text)["toy"], root.section("toy").yaml()).empty()) << text;
}

}  // namespace
}  // namespace evade::config
