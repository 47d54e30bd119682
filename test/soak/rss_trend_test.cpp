#include "soak/rss_trend.h"

#include <gtest/gtest.h>

namespace evade::soak {
namespace {

TEST(RssTrend, SlopeOfAnExactLine) {
  auto s = ls_slope({0, 1, 2, 3}, {5, 7, 9, 11});
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(*s, 2.0);
  EXPECT_FALSE(ls_slope({1}, {1}));
  EXPECT_FALSE(ls_slope({2, 2}, {1, 3}));
}

TEST(RssTrend, GrowthPerHourIsFittedAfterTheWarmupOfEachProcess) {
  std::vector<RssSample> s;
  // pid 1: a jump in the first minute, then 1024 KiB (1 MiB) per hour.
  s.push_back({0, 1, 1000, 0});
  s.push_back({30, 1, 50000, 0});
  for (int i = 0; i <= 10; ++i) s.push_back({60.0 + 360.0 * i, 1, 60000 + 1024.0 * i / 10, 0});
  // pid 2 starts later, flat.
  s.push_back({100, 2, 2048, 0});
  s.push_back({4000, 2, 2048, 0});
  const auto t = rss_trends(s, 60);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].pid, 1);
  EXPECT_EQ(t[0].samples, 13);
  EXPECT_EQ(t[0].fitted, 11);
  ASSERT_TRUE(t[0].growth_mib_per_h);
  EXPECT_NEAR(*t[0].growth_mib_per_h, 1.0, 1e-9);
  EXPECT_NEAR(t[0].start_mib, 1000 / 1024.0, 1e-9);
  EXPECT_NEAR(t[0].max_mib, 61024 / 1024.0, 1e-9);
  EXPECT_NEAR(t[0].span_s, 3660, 1e-9);
  EXPECT_EQ(t[1].fitted, 1);  // 100 s .. 160 s is warm-up; one sample after
  EXPECT_FALSE(t[1].growth_mib_per_h);
}

TEST(RssTrend, SamplerFileIsReadStrictly) {
  auto s = parse_rss_samples("# t_s pid rss_kib load1\n0.5 42 1000 1.5\n\n1.5 42 1100 1.25\n");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].pid, 42);
  EXPECT_DOUBLE_EQ(s[1].rss_kib, 1100);
  EXPECT_DOUBLE_EQ(s[1].load1, 1.25);
  try {
    parse_rss_samples("0.5 42 1000 1.5\n1.0 42 abc 1\n");
    FAIL() << "a bad line was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_rss_samples("1 2 3 4 5\n"), std::runtime_error);
  EXPECT_THROW(parse_rss_samples("1 2 -3 4\n"), std::runtime_error);
}

}  // namespace
}  // namespace evade::soak
