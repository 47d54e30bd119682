// The health board's table and verdict from decoded heartbeats and a time.
#include "health_board.h"

#include <gtest/gtest.h>

#include <regex>

#include "config/config.h"

namespace {

using evade::health::HealthBoard;
using evade::health::HealthBoardParams;

evade::health_t beat(const std::string& name, double rate, double mean_us, double max_us) {
  evade::health_t m{};
  m.utime = 0;
  m.name = name;
  m.seq = 1;
  m.output_rate_hz = rate;
  m.latency_us_mean = mean_us;
  m.latency_us_max = max_us;
  return m;
}

void add_input(evade::health_t* m, const std::string& ch, int64_t age_us) {
  evade::health_channel_t c{};
  c.channel = ch;
  c.received = 5;
  c.age_us = age_us;
  m->inputs.push_back(c);
  m->num_inputs = int32_t(m->inputs.size());
}

void add_counter(evade::health_t* m, const std::string& name, int64_t v) {
  evade::health_counter_t c{};
  c.name = name;
  c.value = v;
  m->counters.push_back(c);
  m->num_counters = int32_t(m->counters.size());
}

size_t visible_width(const std::string& s) {
  return std::regex_replace(s, std::regex("\033\\[[0-9;]*[A-Za-z]"), "").size();
}

constexpr int64_t kSec = 1'000'000;

TEST(HealthBoard, OneRowPerProcessWithAgeRateLatencyAndOldestInput) {
  HealthBoard board;
  auto m = beat("tracker", 10.0, 412.0, 1530.0);
  add_input(&m, "ELEVATION_MAP", 80'000);
  add_input(&m, "ODOMETRY", 2'340'000);
  board.add(m, 100 * kSec);
  board.add(beat("route", 1.0, 20.0, 30.0), 100 * kSec + 500'000);
  const auto lines = render_table(board, {}, 101 * kSec, HealthBoardParams{}, false);
  ASSERT_EQ(lines.size(), 3u);
  // rows sorted by name: route, tracker
  EXPECT_NE(lines[1].find("route"), std::string::npos);
  EXPECT_NE(lines[2].find("tracker"), std::string::npos);
  EXPECT_NE(lines[2].find(" 1.0 "), std::string::npos) << lines[2];  // heartbeat age 1.0 s
  EXPECT_NE(lines[2].find("10.0"), std::string::npos);               // output rate
  EXPECT_NE(lines[2].find("0.41"), std::string::npos);               // mean latency, ms
  EXPECT_NE(lines[2].find("1.53"), std::string::npos);               // max latency, ms
  EXPECT_NE(lines[2].find("ODOMETRY"), std::string::npos);           // the older of its two inputs
  EXPECT_NE(lines[2].find("2.34"), std::string::npos);
  EXPECT_EQ(lines[2].find("ELEVATION_MAP"), std::string::npos);
  EXPECT_NE(lines[1].find(" 0.5 "), std::string::npos) << lines[1];
}

TEST(HealthBoard, AnInputNeverHeardIsTheOldest) {
  HealthBoard board;
  auto m = beat("planner", 10.0, 1.0, 2.0);
  add_input(&m, "ODOMETRY", 5'000'000);
  add_input(&m, "ROUTE", -1);
  board.add(m, 0);
  const auto lines = render_table(board, {}, 0, HealthBoardParams{}, false);
  EXPECT_NE(lines[1].find("ROUTE"), std::string::npos) << lines[1];
  EXPECT_NE(lines[1].find("never"), std::string::npos);
}

TEST(HealthBoard, OnlyNonZeroCountersAreListedAndWrappedWithin80Columns) {
  HealthBoard board;
  auto m = beat("a_process_with_a_very_long_name", 123456789.0, 1e9, 1e12);
  add_counter(&m, "zero_counter", 0);
  for (int i = 0; i < 12; ++i) add_counter(&m, "malformed_reason_number_" + std::to_string(i), 1000 + i);
  add_input(&m, "A_CHANNEL_WITH_A_VERY_LONG_NAME", 123'456'789'000);
  board.add(m, 0);
  const auto lines = render_table(board, {"missing_one"}, 10000 * kSec, HealthBoardParams{}, true);
  std::string all;
  for (const auto& l : lines) {
    EXPECT_LE(visible_width(l), 80u) << l;
    all += l + "\n";
  }
  EXPECT_EQ(all.find("zero_counter"), std::string::npos);
  for (int i = 0; i < 12; ++i)
    EXPECT_NE(all.find("malformed_reason_number_" + std::to_string(i) + "=" + std::to_string(1000 + i)),
              std::string::npos)
        << i;
  EXPECT_GT(lines.size(), 4u);  // the counters took more than one line
}

TEST(HealthBoard, StaleRowsAreRedAndJudgedStale) {
  HealthBoardParams p;
  p.stale_after_s = 2.0;
  HealthBoard board;
  board.add(beat("fresh", 1, 1, 1), 10 * kSec);
  board.add(beat("old", 1, 1, 1), 7 * kSec);
  const int64_t now = 10 * kSec + 100'000;
  const auto lines = render_table(board, {}, now, p, true);
  ASSERT_EQ(lines.size(), 3u);
  // rows by name: "fresh", then "old"
  EXPECT_NE(lines[2].find("old"), std::string::npos);
  EXPECT_NE(lines[2].find("\033[31m"), std::string::npos);
  EXPECT_EQ(lines[1].find("\033[31m"), std::string::npos);
  const auto plain = render_table(board, {}, now, p, false);
  EXPECT_NE(plain[2].find("STALE"), std::string::npos);
  EXPECT_EQ(plain[1].find("STALE"), std::string::npos);

  const auto v = judge(board, {}, now, p);
  EXPECT_EQ(v.stale, std::vector<std::string>{"old"});
  EXPECT_FALSE(v.ok());
  EXPECT_TRUE(judge(board, {}, 9 * kSec, p).ok());  // 2.0 s old at 9 s: not yet stale
}

TEST(HealthBoard, ExpectedProcessesNeverHeardAreMissing) {
  HealthBoard board;
  board.add(beat("route", 1, 1, 1), 0);
  const auto v = judge(board, {"route", "planner", "tracker"}, 0, HealthBoardParams{});
  EXPECT_EQ(v.missing, (std::vector<std::string>{"planner", "tracker"}));
  EXPECT_TRUE(v.stale.empty());
  const auto lines = render_table(board, {"route", "planner"}, 0, HealthBoardParams{}, false);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[2].find("planner"), std::string::npos);
  EXPECT_NE(lines[2].find("never heard"), std::string::npos);
  EXPECT_TRUE(judge(board, {"route"}, 0, HealthBoardParams{}).ok());
}

TEST(HealthBoard, KeepsTheNewestHeartbeatPerProcess) {
  HealthBoard board;
  board.add(beat("route", 2.0, 1, 1), 5 * kSec);
  board.add(beat("route", 1.0, 1, 1), 4 * kSec);  // older, arrives late: ignored
  ASSERT_EQ(board.processes().size(), 1u);
  EXPECT_EQ(board.processes().at("route").msg.output_rate_hz, 2.0);
  EXPECT_EQ(board.processes().at("route").received_utime, 5 * kSec);
}

TEST(HealthBoard, ConfigIsReadStrictly) {
  const auto ok = evade::config::load_string(
      "stale_after_s: 1.5\nonce_listen_s: 2.0\nrefresh_period_s: 0.5\nwait_timeout_s: 4.0\n", "t.yaml");
  const auto p = HealthBoardParams::from_config(ok);
  EXPECT_EQ(p.stale_after_s, 1.5);
  EXPECT_EQ(p.once_listen_s, 2.0);
  EXPECT_EQ(p.wait_timeout_s, 4.0);
  const auto extra = evade::config::load_string(
      "stale_after_s: 1.5\nonce_listen_s: 2.0\nrefresh_period_s: 0.5\nwait_timeout_s: 4.0\nstale_s: 1\n", "t.yaml");
  EXPECT_THROW(HealthBoardParams::from_config(extra), evade::config::ConfigError);
  const auto bad = evade::config::load_string(
      "stale_after_s: -1\nonce_listen_s: 2.0\nrefresh_period_s: 0.5\nwait_timeout_s: 4.0\n", "t.yaml");
  EXPECT_THROW(HealthBoardParams::from_config(bad), evade::config::ConfigError);
  // robot.yaml's section loads
  const auto root = evade::config::load_robot_config(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  EXPECT_NO_THROW(HealthBoardParams::from_config(root.section("health_board")));
}

TEST(HealthBoard, AnInputCountsAsReceivedOnlyOnceItsProcessReportsAMessageOnIt) {
  using evade::health::InputWanted;
  HealthBoard board;
  const std::vector<InputWanted> wanted = {{"planner", "ROUTE"}, {"tracker", "ELEVATION_MAP"}};
  EXPECT_EQ(inputs_not_received(board, wanted), (std::vector<std::string>{"planner:ROUTE", "tracker:ELEVATION_MAP"}));
  auto planner = beat("planner", 10.0, 1.0, 1.0);
  add_input(&planner, "ROUTE", -1);
  planner.inputs.back().received = 0;  // subscribed, nothing yet
  add_input(&planner, "ODOMETRY", 1000);
  board.add(planner, 1 * kSec);
  auto tracker = beat("tracker", 10.0, 1.0, 1.0);
  add_input(&tracker, "ELEVATION_MAP", 1000);
  board.add(tracker, 1 * kSec);
  EXPECT_EQ(inputs_not_received(board, wanted), (std::vector<std::string>{"planner:ROUTE"}));
  planner.inputs[0].received = 1;
  board.add(planner, 2 * kSec);
  EXPECT_TRUE(inputs_not_received(board, wanted).empty());
}

TEST(HealthBoard, AWantedInputIsProcessColonChannel) {
  evade::health::InputWanted w;
  std::string why;
  ASSERT_TRUE(parse_input_wanted("planner:ROUTE", &w, &why));
  EXPECT_EQ(w.process, "planner");
  EXPECT_EQ(w.channel, "ROUTE");
  for (const char* bad : {"planner", ":ROUTE", "planner:", "a:b:c"}) {
    EXPECT_FALSE(parse_input_wanted(bad, &w, &why)) << bad;
    EXPECT_NE(why.find(bad), std::string::npos) << why;
  }
}

}  // namespace
