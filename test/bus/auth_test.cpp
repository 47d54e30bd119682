// Authenticated channels (lib/bus/auth.h): what is signed verifies, and
// forged, replayed, reordered, stale or unsigned messages never reach a
// core's handler, each counted in HEALTH.
#include "bus/auth.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bus/lcm_schema.h"
#include "bus/memory_bus.h"
#include "evade/cmd_vel_t.hpp"
#include "evade/estop_t.hpp"
#include "evade/odometry_t.hpp"
#include "evade/path_t.hpp"
#include "evade/prediction_list_t.hpp"

namespace evade::bus {
namespace {

std::vector<uint8_t> key_a() { return std::vector<uint8_t>(32, 0xa5); }
std::vector<uint8_t> key_b() { return std::vector<uint8_t>(32, 0x5a); }

// Counts the CMD_VEL messages its handler sees.
class Receiver : public Core {
 public:
  Receiver() : Core("receiver") {
    subscribe<evade::cmd_vel_t>("CMD_VEL", [this](const evade::cmd_vel_t& m) { seen.push_back(m.v); });
  }
  std::vector<double> seen;
};

std::vector<uint8_t> signed_cmd(HmacAuth& signer, int64_t utime, double v, int64_t now) {
  evade::cmd_vel_t m{};
  m.utime = utime;
  m.v = v;
  std::vector<uint8_t> data = encode(m);
  EXPECT_TRUE(signer.sign("CMD_VEL", now, &data));
  return data;
}

TEST(Auth, SignedMessageDecodesAndCarriesSenderAndSeq) {
  HmacAuth signer(key_a(), "planner", 2.0);
  auto data = signed_cmd(signer, 1000, 0.5, 1000);
  evade::cmd_vel_t m{};
  ASSERT_TRUE(decode(data.data(), data.size(), &m));
  EXPECT_EQ(m.auth_sender, "planner");
  EXPECT_EQ(m.auth_seq, 1000);
  EXPECT_DOUBLE_EQ(m.v, 0.5);
  HmacAuth receiver(key_a(), "base_driver", 2.0);
  EXPECT_EQ(receiver.verify("CMD_VEL", data.data(), data.size(), 1000), AuthVerdict::kOk);
}

TEST(Auth, SequenceIncreasesEvenWithinOneMicrosecond) {
  HmacAuth signer(key_a(), "planner", 2.0);
  evade::cmd_vel_t a, b;
  auto d1 = signed_cmd(signer, 5, 0.1, 5);
  auto d2 = signed_cmd(signer, 5, 0.2, 5);
  ASSERT_TRUE(decode(d1.data(), d1.size(), &a));
  ASSERT_TRUE(decode(d2.data(), d2.size(), &b));
  EXPECT_EQ(a.auth_seq, 5);
  EXPECT_EQ(b.auth_seq, 6);
}

TEST(Auth, ForgedMessagesAreRejected) {
  HmacAuth signer(key_a(), "planner", 2.0);
  HmacAuth receiver(key_a(), "base_driver", 2.0);
  auto good = signed_cmd(signer, 1000, 0.5, 1000);
  // Signed with another key.
  HmacAuth attacker(key_b(), "planner", 2.0);
  auto other_key = signed_cmd(attacker, 1000, 0.5, 2000);
  EXPECT_EQ(receiver.verify("CMD_VEL", other_key.data(), other_key.size(), 1000), AuthVerdict::kBadMac);
  // One bit of the speed changed.
  auto tampered = good;
  tampered[8 + 8] ^= 0x01;
  EXPECT_EQ(receiver.verify("CMD_VEL", tampered.data(), tampered.size(), 1000), AuthVerdict::kBadMac);
  // A good CMD_VEL sent on another authenticated channel.
  EXPECT_EQ(receiver.verify("ESTOP", good.data(), good.size(), 1000), AuthVerdict::kBadMac);
  // Unsigned (what an old tool or a core without the bus sends).
  evade::cmd_vel_t m{};
  m.utime = 1000;
  auto plain = encode(m);
  EXPECT_EQ(receiver.verify("CMD_VEL", plain.data(), plain.size(), 1000), AuthVerdict::kUnsigned);
  // The good one still passes after all that.
  EXPECT_EQ(receiver.verify("CMD_VEL", good.data(), good.size(), 1000), AuthVerdict::kOk);
}

TEST(Auth, ReplayedAndReorderedMessagesAreRejectedPerSender) {
  HmacAuth planner(key_a(), "planner", 2.0);
  HmacAuth teleop(key_a(), "teleop", 2.0);
  HmacAuth receiver(key_a(), "base_driver", 2.0);
  auto first = signed_cmd(planner, 1000, 0.1, 1000);
  auto second = signed_cmd(planner, 2000, 0.2, 2000);
  auto other = signed_cmd(teleop, 1500, 0.3, 1500);
  EXPECT_EQ(receiver.verify("CMD_VEL", second.data(), second.size(), 2000), AuthVerdict::kOk);
  EXPECT_EQ(receiver.verify("CMD_VEL", first.data(), first.size(), 2000), AuthVerdict::kOldSeq);    // reordered
  EXPECT_EQ(receiver.verify("CMD_VEL", second.data(), second.size(), 2000), AuthVerdict::kOldSeq);  // replayed
  // Another sender's sequence is its own.
  EXPECT_EQ(receiver.verify("CMD_VEL", other.data(), other.size(), 2000), AuthVerdict::kOk);
}

TEST(Auth, MessagesOutsideTheWindowOnBusTimeAreRejected) {
  HmacAuth signer(key_a(), "planner", 2.0);
  HmacAuth receiver(key_a(), "base_driver", 2.0);
  const int64_t t = 100'000'000;
  auto old = signed_cmd(signer, t - 2'000'001, 0.1, t - 2'000'001);
  auto future = signed_cmd(signer, t + 2'000'001, 0.1, t + 2'000'001);
  auto extreme = signed_cmd(signer, INT64_MIN, 0.1, t + 2'000'002);
  auto edge = signed_cmd(signer, t - 2'000'000, 0.1, t + 2'000'003);
  EXPECT_EQ(receiver.verify("CMD_VEL", old.data(), old.size(), t), AuthVerdict::kOutsideWindow);
  EXPECT_EQ(receiver.verify("CMD_VEL", future.data(), future.size(), t), AuthVerdict::kOutsideWindow);
  EXPECT_EQ(receiver.verify("CMD_VEL", extreme.data(), extreme.size(), t), AuthVerdict::kOutsideWindow);
  EXPECT_EQ(receiver.verify("CMD_VEL", edge.data(), edge.size(), t), AuthVerdict::kOk);
  // A log replayed later runs on the log's bus time: the same old message
  // is fine to a receiver whose bus time is the log's.
  HmacAuth replay(key_a(), "base_driver", 2.0);
  EXPECT_EQ(replay.verify("CMD_VEL", old.data(), old.size(), t - 2'000'001), AuthVerdict::kOk);
}

TEST(Auth, EveryAuthenticatedTypeSignsAndVerifies) {
  HmacAuth signer(key_a(), "elevation_map", 2.0);
  HmacAuth receiver(key_a(), "planner", 2.0);
  auto check = [&](const std::string& ch, std::vector<uint8_t> data) {
    ASSERT_TRUE(signer.sign(ch, 7, &data)) << ch;
    EXPECT_TRUE(well_formed(data.data(), data.size())) << ch;
    EXPECT_EQ(receiver.verify(ch, data.data(), data.size(), 7), AuthVerdict::kOk) << ch;
    // The layout auth.h relies on: utime first, the three fields last.
    auto v = LcmSchema::evade().decode(data.data(), data.size());
    ASSERT_TRUE(v) << ch;
    const auto& f = v->fields;
    ASSERT_GE(f.size(), 4u) << ch;
    EXPECT_EQ(f.front().first, "utime") << ch;
    EXPECT_EQ(f[f.size() - 3].first, "auth_sender") << ch;
    EXPECT_EQ(f[f.size() - 3].second.s, "elevation_map") << ch;
    EXPECT_EQ(f[f.size() - 2].first, "auth_seq") << ch;
    EXPECT_EQ(f[f.size() - 1].first, "auth_mac") << ch;
    data[data.size() - 1] ^= 0x80;
    EXPECT_EQ(receiver.verify(ch, data.data(), data.size(), 7), AuthVerdict::kBadMac) << ch;
  };
  evade::odometry_t o{};
  o.utime = 7;
  check("ODOMETRY", encode(o));
  evade::path_t p{};
  p.utime = 7;
  p.n = 2;
  p.x = {0, 1};
  p.y = {0, 0};
  check("ROUTE", encode(p));
  evade::prediction_list_t pl{};
  pl.utime = 7;
  check("OBSTACLE_PREDICTIONS", encode(pl));
  evade::estop_t e{};
  e.utime = 7;
  e.engaged = true;
  check("ESTOP", encode(e));
  evade::cmd_vel_t c{};
  c.utime = 7;
  check("CMD_VEL", encode(c));
  EXPECT_EQ(authenticated_channels().size(), 5u);
}

TEST(Auth, AChannelWithoutAuthenticationIsLeftAlone) {
  HmacAuth signer(key_a(), "tracker", 2.0);
  std::vector<uint8_t> data = {1, 2, 3};
  EXPECT_TRUE(signer.sign("OBSTACLES", 1, &data));
  EXPECT_EQ(data, (std::vector<uint8_t>{1, 2, 3}));
  EXPECT_EQ(signer.verify("OBSTACLES", data.data(), data.size(), 1), AuthVerdict::kOk);
}

TEST(Auth, ACoreNeverSeesARejectedMessageAndHealthCountsEachKind) {
  HmacAuth planner(key_a(), "planner", 2.0);
  HmacAuth attacker(key_b(), "planner", 2.0);
  HmacAuth receiver_auth(key_a(), "base_driver", 2.0);
  Receiver rx;
  rx.set_authenticator(&receiver_auth);
  MemoryBus bus;
  bus.add(rx);
  const int64_t t = 10'000'000;
  auto good = signed_cmd(planner, t, 0.4, t);
  bus.inject("CMD_VEL", good, t);
  bus.inject("CMD_VEL", good, t + 1);                                            // replayed
  bus.inject("CMD_VEL", signed_cmd(attacker, t + 2, 9.0, t + 2), t + 2);         // forged
  bus.inject("CMD_VEL", signed_cmd(planner, t - 5'000'000, 9.0, t + 3), t + 3);  // stale
  evade::cmd_vel_t plain{};
  plain.utime = t + 4;
  plain.v = 9.0;
  bus.inject("CMD_VEL", plain, t + 4);  // unsigned
  ASSERT_EQ(rx.seen.size(), 1u);
  EXPECT_DOUBLE_EQ(rx.seen[0], 0.4);
  EXPECT_EQ(rx.counter("auth_old_seq"), 1);
  EXPECT_EQ(rx.counter("auth_bad_mac"), 1);
  EXPECT_EQ(rx.counter("auth_outside_window"), 1);
  EXPECT_EQ(rx.counter("auth_unsigned"), 1);
}

TEST(Auth, ACorePublishesSignedWhenItHasAnAuthenticator) {
  class Sender : public Core {
   public:
    Sender() : Core("route") {
      every(100'000, [this] {
        evade::path_t p{};
        p.utime = now();
        publish("ROUTE", p);
      });
    }
  } tx;
  HmacAuth auth(key_a(), "route", 2.0);
  tx.set_authenticator(&auth);
  MemoryBus bus;
  bus.add(tx);
  bus.advance_to(0);  // timers start at the first bus time seen
  bus.advance_to(250'000);
  auto routes = bus.decoded<evade::path_t>("ROUTE");
  ASSERT_EQ(routes.size(), 3u);
  HmacAuth receiver(key_a(), "planner", 2.0);
  int ok = 0;
  for (const auto& e : bus.published())
    if (e.channel == "ROUTE")
      ok += receiver.verify("ROUTE", e.data.data(), e.data.size(), e.timestamp) == AuthVerdict::kOk;
  EXPECT_EQ(ok, 3);
  EXPECT_EQ(routes[2].auth_sender, "route");
}

TEST(Auth, TailParsingNeedsAWellFormedSenderName) {
  AuthTail t;
  std::vector<uint8_t> shortish(40, 0);
  EXPECT_FALSE(parse_tail(shortish.data(), shortish.size(), &t));
  HmacAuth signer(key_a(), "a", 2.0);
  auto d = signed_cmd(signer, 1, 0.0, 1);
  ASSERT_TRUE(parse_tail(d.data(), d.size(), &t));
  EXPECT_EQ(t.sender, "a");
  EXPECT_THROW(HmacAuth(key_a(), "no spaces", 2.0), std::invalid_argument);
  EXPECT_THROW(HmacAuth(std::vector<uint8_t>(16, 1), "planner", 2.0), std::invalid_argument);
}

class KeyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("evade_auth_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text, mode_t mode) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    ::chmod(p.c_str(), mode);
    return p;
  }
  std::filesystem::path dir_;
};

std::string message_of(const std::string& path) {
  try {
    load_key(path);
  } catch (const KeyError& e) {
    return e.what();
  }
  return "";
}

TEST_F(KeyFile, AnOwnerOnlyHexKeyLoads) {
  const std::string hex(64, 'a');
  auto key = load_key(write("k", hex + "\n", 0600));
  EXPECT_EQ(key, std::vector<uint8_t>(32, 0xaa));
  EXPECT_EQ(load_key(write("k4", hex, 0400)).size(), 32u);
}

TEST_F(KeyFile, MissingExposedShortOrGarbledKeysAreRefusedWithAClearReason) {
  const std::string hex(64, 'a');
  EXPECT_NE(message_of((dir_ / "none").string()).find("no key file"), std::string::npos);
  EXPECT_NE(message_of((dir_ / "none").string()).find("tools/setup key"), std::string::npos);
  EXPECT_NE(message_of(write("g", hex, 0640)).find("group or others (mode 640)"), std::string::npos);
  EXPECT_NE(message_of(write("o", hex, 0604)).find("chmod 600"), std::string::npos);
  EXPECT_NE(message_of(write("s", std::string(62, 'a'), 0600)).find("31 bytes"), std::string::npos);
  EXPECT_NE(message_of(write("x", std::string(64, 'z'), 0600)).find("not hexadecimal"), std::string::npos);
  EXPECT_NE(message_of(dir_.string()).find("not a regular file"), std::string::npos);
}

TEST_F(KeyFile, ThePathComesFromTheEnvironmentElseTheConfigWithHome) {
  AuthParams p;
  p.key_file = "~/.config/evade/bus.key";
  const char* saved = std::getenv("EVADE_BUS_KEY");
  const std::string keep = saved ? saved : "";
  ::unsetenv("EVADE_BUS_KEY");
  ::setenv("HOME", "/home/robot", 1);
  EXPECT_EQ(key_path(p), "/home/robot/.config/evade/bus.key");
  ::setenv("EVADE_BUS_KEY", "/tmp/k", 1);
  EXPECT_EQ(key_path(p), "/tmp/k");
  if (saved)
    ::setenv("EVADE_BUS_KEY", keep.c_str(), 1);
  else
    ::unsetenv("EVADE_BUS_KEY");
}

TEST(AuthConfig, TheSectionIsStrict) {
  auto root =
      config::load_string("bus:\n  allowed_interfaces: [lo]\n  auth:\n    key_file: /k\n    window_s: 1.5\n", "t.yaml");
  auto p = AuthParams::from_config(root);
  EXPECT_EQ(p.key_file, "/k");
  EXPECT_DOUBLE_EQ(p.window_s, 1.5);
  EXPECT_THROW(AuthParams::from_config(config::load_string(
                   "bus:\n  auth:\n    key_file: /k\n    window_s: 1.5\n    channels: [X]\n", "t.yaml")),
               config::ConfigError);
  EXPECT_THROW(
      AuthParams::from_config(config::load_string("bus:\n  auth:\n    key_file: /k\n    window_s: 0\n", "t.yaml")),
      config::ConfigError);
}

}  // namespace
}  // namespace evade::bus
