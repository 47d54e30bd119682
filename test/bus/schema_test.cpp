// The generic decoder agrees with lcm-gen's own encoders on every shape of
// field our types use (nested structs, variable and 2D arrays, strings,
// booleans) and rejects malformed bytes.
#include <gtest/gtest.h>

#include <cmath>

#include "bus/core.h"
#include "bus/lcm_schema.h"
#include "evade/grid_map_t.hpp"
#include "evade/health_t.hpp"
#include "evade/pointcloud_t.hpp"

namespace evade::bus {
namespace {

TEST(LcmSchema, KnowsEveryType) {
  auto types = LcmSchema::evade().types();
  for (const char* t : {"pointcloud_t", "odometry_t", "grid_map_t", "obstacle_list_t", "prediction_list_t", "path_t",
                        "plan_t", "cmd_vel_t", "base_status_t", "sim_truth_t", "health_t"})
    EXPECT_NE(std::find(types.begin(), types.end(), t), types.end()) << t;
}

TEST(LcmSchema, DecodesNestedAndArrays) {
  evade::pointcloud_t pc{};
  pc.utime = 123;
  pc.sensor_model = "vlp16";
  pc.mount.z = 0.5;
  pc.n = 2;
  pc.x = {1.5f, -2.25f};
  pc.y = {0.f, 1.f};
  pc.z = {0.f, 0.f};
  pc.intensity = {10.f, 20.f};
  pc.ring = {0, 15};
  pc.time_offset = {0, 55};
  auto bytes = encode(pc);
  std::string type;
  auto v = LcmSchema::evade().decode(bytes.data(), bytes.size(), &type);
  ASSERT_TRUE(v);
  EXPECT_EQ(type, "pointcloud_t");
  EXPECT_EQ(to_json(*v->field("x")), "[1.5,-2.25]");
  EXPECT_EQ(to_json(*v->field("ring")), "[0,15]");
  EXPECT_EQ(v->field("mount")->field("z")->number(), 0.5);
  EXPECT_EQ(v->field("sensor_model")->s, "vlp16");

  evade::grid_map_t g{};
  g.width = 3;
  g.height = 2;
  g.elevation.assign(2, std::vector<float>(3, 0.25f));
  g.elevation[1][2] = NAN;
  g.obstacle.assign(2, std::vector<int8_t>(3, 0));
  g.obstacle[0][1] = 1;
  bytes = encode(g);
  v = LcmSchema::evade().decode(bytes.data(), bytes.size(), &type);
  ASSERT_TRUE(v);
  EXPECT_EQ(to_json(*v->field("elevation")), "[[0.25,0.25,0.25],[0.25,0.25,null]]");
  EXPECT_EQ(to_json(*v->field("obstacle")), "[[0,1,0],[0,0,0]]");

  evade::health_t h{};
  h.name = "x\"y";
  h.num_inputs = 1;
  h.inputs.resize(1);
  h.inputs[0].channel = "ODOMETRY";
  h.inputs[0].age_us = -1;
  bytes = encode(h);
  v = LcmSchema::evade().decode(bytes.data(), bytes.size(), &type);
  ASSERT_TRUE(v);
  EXPECT_NE(to_json(*v).find("\"name\":\"x\\\"y\""), std::string::npos);
  EXPECT_EQ(v->field("inputs")->items.at(0).field("age_us")->i, -1);
}

TEST(LcmSchema, RejectsMalformed) {
  evade::pointcloud_t pc{};
  pc.n = 1;
  pc.x = pc.y = pc.z = pc.intensity = {1.f};
  pc.ring = {1};
  pc.time_offset = {1};
  auto bytes = encode(pc);
  for (size_t cut = 0; cut < bytes.size(); ++cut) EXPECT_FALSE(LcmSchema::evade().decode(bytes.data(), cut)) << cut;
  bytes.push_back(0);
  EXPECT_FALSE(LcmSchema::evade().decode(bytes.data(), bytes.size()));
  std::vector<uint8_t> junk(64, 0xAB);
  EXPECT_FALSE(LcmSchema::evade().decode(junk.data(), junk.size()));
}

}  // namespace
}  // namespace evade::bus

#include "bus/log_diff.h"
#include "evade/plan_t.hpp"

namespace evade::bus {
namespace {

std::vector<LogEvent> plans(double v3, int64_t solve_us, int n = 3) {
  std::vector<LogEvent> out;
  for (int i = 0; i < n; ++i) {
    evade::plan_t p{};
    p.utime = i;
    p.mode = "dcbf";
    p.horizon = 4;
    p.num_states = 5;
    p.x = p.y = p.yaw = std::vector<double>(5, 0.0);
    p.v = {0.1, 0.2, 0.3, i == 1 ? v3 : 0.4};
    p.omega = std::vector<double>(4, 0.0);
    p.solve_time_us = solve_us;
    out.push_back({i, "PLAN", encode(p)});
  }
  return out;
}

TEST(LogDiff, ToleranceIgnoredFieldsAndPaths) {
  DiffOptions opt;
  opt.per_channel["PLAN"] = Tolerance{1e-3, 0.0};
  opt.ignore_fields = {"PLAN.solve_time_us"};
  EXPECT_TRUE(diff_logs(plans(0.4, 100), plans(0.4, 900), opt).same());     // wall time ignored
  EXPECT_TRUE(diff_logs(plans(0.4005, 100), plans(0.4, 100), opt).same());  // within 1e-3
  auto rep = diff_logs(plans(0.41, 100), plans(0.4, 100), opt);
  ASSERT_FALSE(rep.same());
  EXPECT_EQ(rep.differing_messages, 1u);
  ASSERT_EQ(rep.lines.size(), 1u);
  EXPECT_EQ(rep.lines[0], "PLAN#1.v[3]: 0.41 vs 0.4");
  auto count = diff_logs(plans(0.4, 100, 2), plans(0.4, 100, 3), opt);
  EXPECT_FALSE(count.same());
  EXPECT_EQ(count.lines[0], "PLAN: 2 messages vs 3 in the reference");
}

}  // namespace
}  // namespace evade::bus
