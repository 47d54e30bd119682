// Issue 20: the attack the authentication is for. A dead perception chain
// kept "fresh" by someone publishing empty OBSTACLE_PREDICTIONS: without
// authentication the planner drives on blind; with it, the planner refuses
// the unsigned and forged lists, its predictions go stale and it brakes.
#include <gtest/gtest.h>

#include <memory>

#include "bus/auth.h"
#include "bus/memory_bus.h"
#include "config/config.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/plan_t.hpp"
#include "evade/prediction_list_t.hpp"
#include "planning/params.h"
#include "planning/planner_core.h"

namespace evade::planning {
namespace {

constexpr int64_t kT0 = 1'700'000'000'000'000;
constexpr int64_t kPeriod = 100'000;  // perception and odometry at 10 Hz

const std::vector<uint8_t>& key() {
  static const std::vector<uint8_t> k(32, 0x3c);
  return k;
}

template <class Msg>
std::vector<uint8_t> signed_as(bus::HmacAuth& who, const std::string& channel, const Msg& m, int64_t now) {
  std::vector<uint8_t> d = bus::encode(m);
  EXPECT_TRUE(who.sign(channel, now, &d));
  return d;
}

evade::prediction_list_t predictions(int64_t utime, int tracks) {
  evade::prediction_list_t m{};
  m.utime = utime;
  m.dt = 0.1;
  m.horizon = 26;
  for (int i = 0; i < tracks; ++i) {  // a post far off the route
    evade::track_prediction_t t{};
    t.id = i + 1;
    t.horizon = m.horizon;
    for (auto* v : {&t.x, &t.y}) v->assign(m.horizon, 6.0);
    for (auto* v : {&t.a, &t.b}) v->assign(m.horizon, 0.3);
    for (auto* v : {&t.theta, &t.sigma}) v->assign(m.horizon, 0.0);
    m.tracks.push_back(t);
  }
  m.num_tracks = tracks;
  return m;
}

// The planner, its signed inputs, and an attacker; `authenticated`: the
// planner checks signatures (as every live process does).
struct Rig {
  explicit Rig(bool authenticated)
      : core(PlannerParams::from_config(config::load_file(std::string(EVADE_SOURCE_DIR) + "/config/robot.yaml"))) {
    core.set_measure_latency(false);
    if (authenticated) core.set_authenticator(&planner);
    bus.add(core);
    evade::path_t r{};
    r.utime = kT0;
    r.n = 2;
    r.x = {0.0, 20.0};
    r.y = {0.0, 0.0};
    bus.inject("ROUTE", signed_as(route, "ROUTE", r, kT0), kT0);
  }
  // One 10 Hz step: the genuine predictor (while alive) or the attacker's
  // empty lists (unsigned, and signed with another key), then odometry.
  void step(int k, bool predictor_alive) {
    const int64_t t = kT0 + k * kPeriod;
    if (predictor_alive) {
      bus.inject("OBSTACLE_PREDICTIONS", signed_as(predictor, "OBSTACLE_PREDICTIONS", predictions(t, 1), t), t);
    } else {
      bus.inject("OBSTACLE_PREDICTIONS", bus::encode(predictions(t, 0)), t);
      bus.inject("OBSTACLE_PREDICTIONS", signed_as(attacker, "OBSTACLE_PREDICTIONS", predictions(t, 0), t), t);
    }
    evade::odometry_t o{};
    o.utime = t + 10'000;
    o.x = 0.0;
    o.v = 0.3;
    o.epoch = 7;
    bus.inject("ODOMETRY", signed_as(base_driver, "ODOMETRY", o, t + 10'000), t + 10'000);
  }
  // The last CMD_VEL published at or after `from`.
  evade::cmd_vel_t last_cmd_since(int64_t from) const {
    evade::cmd_vel_t last{};
    last.v = -1.0;
    for (const auto& e : bus.published()) {
      evade::cmd_vel_t c;
      if (e.channel == "CMD_VEL" && e.timestamp >= from && bus::decode(e.data.data(), e.data.size(), &c)) last = c;
    }
    return last;
  }
  bus::HmacAuth planner{key(), "planner", 2.0};
  bus::HmacAuth route{key(), "route", 2.0};
  bus::HmacAuth predictor{key(), "predictor", 2.0};
  bus::HmacAuth base_driver{key(), "base_driver", 2.0};
  bus::HmacAuth attacker{std::vector<uint8_t>(32, 0x3d), "predictor", 2.0};
  bus::MemoryBus bus;
  PlannerCore core;
};

TEST(PlannerAuth, EmptyPredictionsFromAnAttackerDoNotKeepADeadChainFresh) {
  for (bool authenticated : {false, true}) {
    SCOPED_TRACE(authenticated ? "authenticated" : "not authenticated");
    Rig r(authenticated);
    for (int k = 1; k <= 10; ++k) r.step(k, true);
    const auto driving = r.last_cmd_since(kT0);
    EXPECT_GT(driving.v, 0.05);                       // planned and drove while the predictor lived
    for (int k = 11; k <= 30; ++k) r.step(k, false);  // predictor dead for 2 s
    const auto last = r.last_cmd_since(kT0 + 25 * kPeriod);
    ASSERT_GE(last.v, 0.0) << "no CMD_VEL in the last 0.5 s";
    if (authenticated) {
      EXPECT_EQ(last.v, 0.0);
      EXPECT_EQ(r.core.counter("auth_unsigned"), 20);
      EXPECT_EQ(r.core.counter("auth_bad_mac"), 20);
      const auto plans = r.bus.decoded<evade::plan_t>("PLAN");
      ASSERT_FALSE(plans.empty());
      EXPECT_EQ(plans.back().status, int8_t{evade::plan_t::STATUS_STALE_INPUT});
    } else {
      EXPECT_GT(last.v, 0.05);  // the attack works on an unauthenticated planner
    }
  }
}

}  // namespace
}  // namespace evade::planning
