// The operator's tools' cores: keys to CMD_VEL, the hold time, the e-stop's
// repeats, the configuration; and, signed, the e-stop tool stopping a
// base_driver core that a teleop core is driving.
#include <gtest/gtest.h>

#include "base/base_driver_core.h"
#include "bus/auth.h"
#include "bus/memory_bus.h"
#include "config/config.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/estop_t.hpp"
#include "teleop/teleop_core.h"

namespace evade::teleop {
namespace {

// Moves bus time in 10 ms steps (one long jump is a stalled process, whose
// timers skip, see Core::kMaxCatchUp).
void run_to(bus::MemoryBus& bus, int64_t from, int64_t to) {
  for (int64_t t = from; t <= to; t += 10'000) bus.advance_to(t);
}

TeleopParams params() {
  TeleopParams p;  // the defaults = robot.yaml
  return p;
}

TEST(Teleop, KeysStepTheCommandWithinItsLimits) {
  TeleopCore core(params());
  bus::MemoryBus bus;
  bus.add(core);
  for (int i = 0; i < 3; ++i) bus.input(core, 1000 + i, [&] { core.on_key('w'); });
  bus.input(core, 1010, [&] { core.on_key('a'); });
  auto cmds = bus.decoded<evade::cmd_vel_t>("CMD_VEL");
  ASSERT_EQ(cmds.size(), 4u);
  EXPECT_NEAR(cmds.back().v, 0.3, 1e-9);
  EXPECT_NEAR(cmds.back().omega, 0.2, 1e-9);
  EXPECT_EQ(cmds.back().utime, 1010);
  for (int i = 0; i < 20; ++i) bus.input(core, 2000 + i, [&] { core.on_key('s'); });
  EXPECT_NEAR(core.v(), -0.5, 1e-9);  // max_v_mps
  bool known = true;
  bus.input(core, 3000, [&] { known = core.on_key('z'); });
  EXPECT_FALSE(known);
  bus.input(core, 3001, [&] { core.on_key(' '); });
  EXPECT_EQ(core.v(), 0.0);
  EXPECT_EQ(core.omega(), 0.0);
}

TEST(Teleop, WithoutAKeyForHoldSTheCommandFallsToZero) {
  TeleopCore core(params());
  bus::MemoryBus bus;
  bus.add(core);
  bus.advance_to(0);
  EXPECT_TRUE(bus.decoded<evade::cmd_vel_t>("CMD_VEL").empty());  // silent until a key
  bus.input(core, 10'000, [&] { core.on_key('w'); });
  run_to(bus, 10'000, 600'000);
  auto cmds = bus.decoded<evade::cmd_vel_t>("CMD_VEL");
  ASSERT_GE(cmds.size(), 12u);  // 20 Hz
  for (const auto& c : cmds) EXPECT_NEAR(c.v, 0.1, 1e-9) << c.utime;
  bus.clear();
  run_to(bus, 600'000, 700'000);
  cmds = bus.decoded<evade::cmd_vel_t>("CMD_VEL");
  ASSERT_FALSE(cmds.empty());
  EXPECT_EQ(cmds.back().v, 0.0);
  bus.input(core, 800'000, [&] { core.stop(); });
  EXPECT_EQ(bus.decoded<evade::cmd_vel_t>("CMD_VEL").back().v, 0.0);
}

TEST(Estop, RepeatsThenIsDoneOrHolds) {
  EstopCore once(params(), true, "test", false);
  bus::MemoryBus bus;
  bus.add(once);
  run_to(bus, 0, 2'000'000);
  auto stops = bus.decoded<evade::estop_t>("ESTOP");
  ASSERT_EQ(stops.size(), 5u);
  EXPECT_TRUE(stops[0].engaged);
  EXPECT_EQ(stops[0].reason, "test");
  EXPECT_EQ(stops[1].utime - stops[0].utime, 100'000);
  EXPECT_TRUE(once.done());

  EstopCore held(params(), false, "r", true);
  bus::MemoryBus bus2;
  bus2.add(held);
  run_to(bus2, 0, 2'000'000);
  EXPECT_EQ(bus2.decoded<evade::estop_t>("ESTOP").size(), 21u);
  EXPECT_FALSE(held.done());
  EXPECT_FALSE(bus2.decoded<evade::estop_t>("ESTOP")[0].engaged);
}

TEST(Estop, SignedItStopsABaseThatTeleopIsDriving) {
  const std::vector<uint8_t> key(32, 0x17);
  bus::HmacAuth base_auth(key, "base_driver", 2.0), teleop_auth(key, "teleop", 2.0), estop_auth(key, "estop", 2.0);
  base::BaseDriverParams bp;
  base::BaseDriverCore base(bp);
  TeleopCore teleop(params());
  base.set_authenticator(&base_auth);
  teleop.set_authenticator(&teleop_auth);
  bus::MemoryBus bus;
  bus.add(base);
  bus.add(teleop);
  const int64_t t0 = 1'000'000'000;
  bus.input(base, t0, [&] { base.on_link_opened(); });
  // The base answers every 20 ms; the operator holds w every 50 ms.
  auto run = [&](int64_t from, int64_t to) {
    for (int64_t t = from; t < to; t += 10'000) {
      if (t % 20'000 == 0) {
        base::FrameBytes b = base::encode(base::SystemStatus{}, 0);
        bus.input(base, t, [&] { base.on_serial_bytes(b.data(), b.size()); });
      }
      if (t % 50'000 == 0) bus.input(teleop, t, [&] { teleop.on_key('w'); });
      bus.advance_to(t);
    }
  };
  run(t0, t0 + 1'000'000);
  EXPECT_GT(base.commanded().v, 0.2);
  EXPECT_EQ(base.counter("auth_bad_mac") + base.counter("auth_unsigned") + base.counter("auth_old_seq"), 0);
  EstopCore stop(params(), true, "test", false);
  stop.set_authenticator(&estop_auth);
  bus.add(stop);
  bus.advance_to(t0 + 1'000'000);
  EXPECT_TRUE(base.estop_engaged());
  run(t0 + 1'000'000, t0 + 2'000'000);
  EXPECT_EQ(base.commanded().v, 0.0);
  EXPECT_GT(base.counter("cmd_vel_during_estop"), 10);
}

// Both cores come from the whole configuration, as every core does
// (CONTRIBUTING.md, "Add a process"), with its `teleop:` section's values.
TEST(TeleopConfig, TheFactoriesBuildTheCoresFromTheWholeConfig) {
  const auto root = config::load_string(
      "teleop: {rate_hz: 20, linear_step_mps: 0.1, angular_step_radps: 0.2, max_v_mps: 0.5, "
      "max_omega_radps: 1, hold_s: 0.6, estop_rate_hz: 20, estop_repeats: 3}\n",
      "t.yaml");
  const std::unique_ptr<TeleopCore> teleop = TeleopCore::from_config(root);
  EXPECT_EQ(teleop->name(), "teleop");
  const std::unique_ptr<EstopCore> estop = EstopCore::from_config(root, true, "test", false);
  EXPECT_EQ(estop->name(), "estop");
  bus::MemoryBus bus;
  bus.add(*estop);
  run_to(bus, 0, 1'000'000);
  const auto stops = bus.decoded<evade::estop_t>("ESTOP");
  ASSERT_EQ(stops.size(), 3u);                         // estop_repeats
  EXPECT_EQ(stops[1].utime - stops[0].utime, 50'000);  // estop_rate_hz
  EXPECT_TRUE(estop->done());
}

TEST(TeleopConfig, RobotYamlLoadsAndTheSectionIsStrict) {
  const auto root = config::load_robot_config(config::default_config_path());
  const TeleopParams p = TeleopParams::from_config(root);
  EXPECT_DOUBLE_EQ(p.rate_hz, 20.0);
  EXPECT_EQ(p.estop_repeats, 5);
  EXPECT_THROW(TeleopParams::from_config(config::load_string(
                   "teleop: {rate_hz: 20, linear_step_mps: 0.1, angular_step_radps: 0.2, max_v_mps: 0.5, "
                   "max_omega_radps: 1, hold_s: 0.6, estop_rate_hz: 10, estop_repeats: 5, extra: 1}\n",
                   "t.yaml")),
               config::ConfigError);
}

}  // namespace
}  // namespace evade::teleop
