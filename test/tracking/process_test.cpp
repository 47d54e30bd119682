// The real binaries over a log: elevation_map --replay, then tracker
// --replay on its output, as an offline run would do it; the same log twice
// gives byte-identical outputs; a bad configuration exits with status 2.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>

#include "../bus/test_signer.h"
#include "bus/core.h"
#include "bus/log.h"
#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/pointcloud_t.hpp"
#include "mapping/synthetic_scan.h"

namespace evade {
namespace {

std::string tmp(const std::string& name) {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir ? dir : "/tmp") + "/evade_perception_" + std::to_string(::getpid()) + "_" + name;
}

int run(const std::string& cmd) {
  const int st = std::system((cmd + " 2>/dev/null").c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

void write_input_log(const std::string& path) {
  bus::LogWriter log(path);
  const int64_t t0 = 1'700'000'000'000'000;
  int64_t next_odom = t0 - 100'000;
  bus::HmacAuth base_driver = bus::testing::test_signer("base_driver");  // unsigned ODOMETRY is refused
  for (int f = 0; f < 20; ++f) {
    const int64_t utime = t0 + f * 100'000;
    for (; next_odom <= utime + 100'000; next_odom += 20'000) {
      odometry_t o{};
      o.utime = next_odom;
      log.write(next_odom, "ODOMETRY", bus::testing::signed_bytes(base_driver, "ODOMETRY", o, next_odom));
    }
    mapping::SynthWorld w;
    w.cylinders.push_back({2.0, 1.0, 0.3, 1.0});
    w.cylinders.push_back({-1.0, -2.0 + 0.15 * f, 0.25, 1.7});
    mapping::SynthScanOptions opt;
    opt.seed = uint32_t(f + 1);
    opt.range_noise_std_m = 0.01;
    const auto c = mapping::synth_vlp16(w, opt);
    pointcloud_t m;
    m.utime = utime;
    m.sensor_model = "vlp16";
    m.mount = {};
    m.mount.z = 0.5;
    m.packets = 0;
    m.n = int32_t(c.x.size());
    m.x = c.x;
    m.y = c.y;
    m.z = c.z;
    m.intensity.assign(c.x.size(), 0.0f);
    m.ring.assign(c.x.size(), 0);
    m.time_offset = c.time_offset;
    log.write(utime + 100'000, "LIDAR_POINTS", bus::encode(m));
  }
}

std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

TEST(Processes, ReplayThroughElevationMapAndTracker) {
  const std::string in = tmp("in.lcmlog"), maps = tmp("maps.lcmlog"), maps2 = tmp("maps2.lcmlog"),
                    obs = tmp("obs.lcmlog");
  write_input_log(in);
  const std::string cfg = std::string(" --config ") + EVADE_SOURCE_DIR + "/config/robot.yaml";
  ASSERT_EQ(run(std::string(ELEVATION_MAP_BIN) + cfg + " --replay " + in + " --replay-out " + maps), 0);
  ASSERT_EQ(run(std::string(ELEVATION_MAP_BIN) + cfg + " --replay " + in + " --replay-out " + maps2), 0);
  EXPECT_EQ(slurp(maps), slurp(maps2));  // deterministic
  ASSERT_EQ(run(std::string(TRACKER_BIN) + cfg + " --replay " + maps + " --replay-out " + obs), 0);
  int n_maps = 0;
  for (const auto& e : bus::read_log(maps)) n_maps += e.channel == "ELEVATION_MAP";
  EXPECT_EQ(n_maps, 20);
  std::map<int64_t, int> frames_of_id;
  int lists = 0;
  for (const auto& e : bus::read_log(obs)) {
    if (e.channel != "OBSTACLES") continue;
    obstacle_list_t l;
    ASSERT_TRUE(bus::decode(e.data.data(), e.data.size(), &l));
    ++lists;
    EXPECT_EQ(l.num_obstacles, 2);
    for (const auto& o : l.obstacles) ++frames_of_id[o.id];
  }
  EXPECT_EQ(lists, 20);
  ASSERT_EQ(frames_of_id.size(), 2u);  // two obstacles, two ids, all the way
  for (const auto& [id, n] : frames_of_id) EXPECT_EQ(n, 20) << id;
  for (const auto& p : {in, maps, maps2, obs}) std::remove(p.c_str());
}

TEST(Processes, BadConfigurationExitsWithStatus2) {
  const std::string cfg = tmp("bad.yaml");
  // The repository's configuration with one edit, run through `bin`.
  auto status_with = [&](const std::string& bin, const std::string& from, const std::string& to) {
    std::string text = slurp(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml");
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at == std::string::npos) return -1;
    text.replace(at, from.size(), to);
    std::ofstream(cfg) << text;
    return run(bin + " --config " + cfg + " --replay /nonexistent --replay-out /dev/null");
  };
  EXPECT_EQ(status_with(ELEVATION_MAP_BIN, "  sobel_max:", "  sobel_maxx:"), 2);
  EXPECT_EQ(status_with(TRACKER_BIN, "  large_cluster: split", "  large_cluster: melt"), 2);
  EXPECT_EQ(status_with(TRACKER_BIN, "\nroute:", "\nroutes:"), 2);  // a misspelt section neither reads
  std::remove(cfg.c_str());
}

}  // namespace
}  // namespace evade
