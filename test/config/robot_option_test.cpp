// --robot NAME reaches every process: each program, started with it, prints
// the named profile's footprint at start ("footprint L x W m, profile NAME,
// source FILE:LINE") before it does anything else; and a --robot that the
// scenario contradicts stops it with status 2 and one line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

const std::string kBin = EVADE_BIN_DIR;
const std::string kSrc = EVADE_SOURCE_DIR;

struct Result {
  int status = -1;
  std::string output;
};

Result run(const std::string& cmd) {
  Result r;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), buf.size(), p)) r.output += buf.data();
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// --replay without --replay-out: each process loads its configuration,
// prints the footprint, then refuses (status 2) before touching a bus.
TEST(RobotOption, EveryProcessPrintsTheProfilesFootprint) {
  const std::string profile = kSrc + "/config/robots/scout2.yaml";
  for (const std::string p :
       {"lidar_driver", "base_driver", "elevation_map", "tracker", "predictor", "planner", "route"}) {
    const Result r = run(kBin + "/" + p + " --config " + kSrc + "/config/robot.yaml --robot scout2 --replay /dev/null");
    EXPECT_EQ(r.status, 2) << p << ": " << r.output;
    EXPECT_NE(r.output.find(p + ": footprint 0.93 x 0.7 m, profile scout2, source " + profile + ":"), std::string::npos)
        << p << ": " << r.output;
  }
  // sim: a bad --lidar-dest stops it after the configuration is loaded
  const Result sim = run(kBin + "/sim --config " + kSrc + "/config/robot.yaml --robot jackal --scenario " + kSrc +
                         "/config/scenarios/paper_sim.yaml --lidar-dest nowhere");
  EXPECT_EQ(sim.status, 2) << sim.output;
  EXPECT_NE(
      sim.output.find("sim: footprint 0.46 x 0.42 m, profile jackal, source " + kSrc + "/config/robots/jackal.yaml:"),
      std::string::npos)
      << sim.output;
}

TEST(RobotOption, ScenarioRobotAndCommandLineMustAgree) {
  const Result r = run(kBin + "/planner --config " + kSrc + "/config/robot.yaml --robot jackal --scenario " + kSrc +
                       "/config/scenarios/paper_realworld.yaml --replay /dev/null");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("key 'robot.profile': the scenario's robot is 'scout2' but --robot names 'jackal'"),
            std::string::npos)
      << r.output;
  const Result unknown =
      run(kBin + "/tracker --config " + kSrc + "/config/robot.yaml --robot nosuch --replay /dev/null");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.output.find("tracker: --robot nosuch: no robot profile 'nosuch'"), std::string::npos)
      << unknown.output;
}

}  // namespace
