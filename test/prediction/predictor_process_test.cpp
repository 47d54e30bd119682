// The predictor binary end to end: --replay a log of OBSTACLES, get
// OBSTACLE_PREDICTIONS stamped with each frame's utime, byte-identical on a
// second run; a bad config exits 2 with file, line and key.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "bus/core.h"
#include "bus/log.h"
#include "evade/obstacle_list_t.hpp"
#include "evade/prediction_list_t.hpp"

namespace {

using namespace evade;

std::string tmp(const std::string& name) {
  return (::testing::TempDir().empty() ? std::string("/tmp/") : ::testing::TempDir()) + "pred_" + name;
}

// Runs the binary; its stderr goes to tmp(err) (one file per test: ctest may run them in parallel).
int run(const std::string& args, const std::string& err) {
  const std::string cmd = std::string(PREDICTOR_BIN) + " " + args + " >/dev/null 2>" + tmp(err);
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(PredictorProcess, ReplayIsStampedAndDeterministic) {
  std::vector<bus::LogEvent> events;
  for (int f = 0; f < 30; ++f) {
    obstacle_list_t l;
    l.utime = 2'000'000 + f * 100'000;
    for (int id = 1; id <= 3; ++id) {
      obstacle_t o{};
      o.id = id;
      o.x = id + 0.1 * f;
      o.y = -id + 0.05 * f;
      o.a = 0.4;
      o.b = 0.3;
      o.theta = 0.2;
      l.obstacles.push_back(o);
    }
    l.num_obstacles = 3;
    events.push_back({l.utime + 5'000, "OBSTACLES", bus::encode(l)});
  }
  bus::write_log(tmp("in.lcmlog"), events);
  std::remove(tmp("out1.lcmlog").c_str());  // --replay-out never replaces a file without --force
  std::remove(tmp("out2.lcmlog").c_str());
  ASSERT_EQ(run("--replay " + tmp("in.lcmlog") + " --replay-out " + tmp("out1.lcmlog"), "replay1.err"), 0);
  ASSERT_EQ(run("--replay " + tmp("in.lcmlog") + " --replay-out " + tmp("out2.lcmlog"), "replay2.err"), 0);
  const auto out1 = bus::read_log(tmp("out1.lcmlog"));
  const auto out2 = bus::read_log(tmp("out2.lcmlog"));
  std::vector<prediction_list_t> preds;
  for (const auto& e : out1) {
    if (e.channel != "OBSTACLE_PREDICTIONS") continue;
    prediction_list_t p;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &p));
    preds.push_back(p);
  }
  ASSERT_EQ(preds.size(), 30u);
  for (size_t i = 0; i < preds.size(); ++i) {
    EXPECT_EQ(preds[i].utime, 2'000'000 + static_cast<int64_t>(i) * 100'000);
    EXPECT_EQ(preds[i].num_tracks, 3);
    EXPECT_EQ(preds[i].horizon, 26);
  }
  // the last frame: every track moving at (1.0, 0.5) m/s
  for (const auto& t : preds.back().tracks) {
    EXPECT_NEAR(t.vx, 1.0, 0.05);
    EXPECT_NEAR(t.vy, 0.5, 0.05);
  }
  ASSERT_EQ(out1.size(), out2.size());
  for (size_t i = 0; i < out1.size(); ++i) {
    if (out1[i].channel == "HEALTH") continue;  // carries latency figures
    EXPECT_EQ(out1[i].channel, out2[i].channel);
    EXPECT_EQ(out1[i].timestamp, out2[i].timestamp);
    EXPECT_EQ(out1[i].data, out2[i].data);
  }
}

TEST(PredictorProcess, BadConfigExitsTwoNamingTheKey) {
  std::ifstream in(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string key = "    kappa: 5.5";
  const auto pos = text.find(key);
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, key.size(), "    kappa: -1.0");
  {
    std::ofstream out(tmp("bad.yaml"));
    out << text;
  }
  EXPECT_EQ(run("--config " + tmp("bad.yaml") + " --replay /nonexistent --replay-out /dev/null", "badconfig.err"), 2);
  // The error is the last line (the footprint line of issue 19 may come first).
  std::ifstream err(tmp("badconfig.err"));
  std::string line, last;
  while (std::getline(err, line))
    if (!line.empty()) last = line;
  EXPECT_NE(last.find("predictor.adaptive_noise.kappa"), std::string::npos) << last;
}

}  // namespace
