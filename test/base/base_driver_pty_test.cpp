// The base driver against a pseudo-terminal peer: the core on the in-memory
// bus (bus time is simulated, so the test is deterministic) and the real
// serial path (libserial open, raw fd I/O) to a pty whose master plays the
// Scout. Covers exact command bytes on the wire, status frames in pieces and
// with garbage, and a hang-up followed by a reconnect at the same path.
#include <gtest/gtest.h>
#include <libserial/SerialPort.h>
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>

#include "base/base_driver_core.h"
#include "base/serial_link.h"
#include "bus/memory_bus.h"
#include "evade/base_status_t.hpp"
#include "evade/cmd_vel_t.hpp"
#include "evade/odometry_t.hpp"
#include "pty_peer.h"

namespace evade::base {
namespace {

using testing::PtyPeer;
using testing::TempDir;
using testing::wait_readable;

constexpr int64_t kT0 = 1'000'000'000;
constexpr int64_t kTick = 20'000;

evade::cmd_vel_t cmd(double v, double omega) {
  evade::cmd_vel_t m{};  // utime: set by Driver::tick (late commands are ignored)
  m.v = v;
  m.omega = omega;
  return m;
}

// The driver side: core + link, as procs/base_driver/main.cpp wires them,
// but on bus time chosen by the test.
struct Driver {
  Driver(const std::string& device, const VelocityLimits& limits)
      : core(make_params(device, limits)), link(device, 115200, 0.1, 2.0) {
    core.set_measure_latency(false);
    bus.add(core);
  }
  static BaseDriverParams make_params(const std::string& device, const VelocityLimits& limits) {
    BaseDriverParams p;
    p.device = device;
    p.limits = limits;
    return p;
  }
  SerialLink::OpenResult open(int64_t t) {
    std::string msg;
    auto r = link.try_open(t, &msg);
    last_message = msg;
    if (r == SerialLink::OpenResult::kOpened) bus.input(core, t, [&] { core.on_link_opened(); });
    return r;
  }
  // One command period: a status frame from the base (alive: the link is
  // ok, or every motion frame would be zero) and CMD_VEL just before the
  // tick, then the tick, then the queued bytes go out on the port.
  void tick(int k, evade::cmd_vel_t c) {
    const FrameBytes status = encode(SystemStatus{}, 0);
    bus.input(core, kT0 + k * kTick - 2, [&] { core.on_serial_bytes(status.data(), status.size()); });
    c.utime = kT0 + k * kTick - 1;
    bus.inject(kCmdVelChannel, c, kT0 + k * kTick - 1);
    bus.advance_to(kT0 + k * kTick);
    flush(kT0 + k * kTick);
  }
  void flush(int64_t t) {
    auto tx = core.take_tx();
    std::string why;
    if (!tx.empty()) {
      ASSERT_TRUE(link.write(t, tx.data(), tx.size(), &why)) << why;
    }
  }
  // Reads whatever the port has (waiting for it first) into the core.
  bool receive(int64_t t) {
    if (!wait_readable(link.fd())) return true;
    std::vector<uint8_t> rx;
    std::string why;
    bool ok = link.read_available(t, &rx, &why);
    if (!rx.empty()) bus.input(core, t, [&] { core.on_serial_bytes(rx.data(), rx.size()); });
    if (!ok) {
      lost_reason = why;
      bus.input(core, t, [&] { core.on_link_lost(why); });
    }
    return ok;
  }
  bus::MemoryBus bus;
  BaseDriverCore core;
  SerialLink link;
  std::string last_message;
  std::string lost_reason;
};

const VelocityLimits kReversible{-1.0, 1.0, 0.5, 1000.0, 1000.0, 1000.0};  // no ramp: one tick reaches the target

TEST(BaseDriverPty, CommandFramesHaveExactBytes) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  PtyPeer base(dir + "/scout");
  Driver d(dir + "/scout", kReversible);
  d.bus.advance_to(kT0);
  ASSERT_EQ(d.open(kT0), SerialLink::OpenResult::kOpened) << d.last_message;

  struct Case {
    double v, omega;
    const char* bytes;
  } cases[] = {
      {0.75, -0.2618, "5A A5 0A 55 01 02 00 32 CE 00 00 00 61"},   // 50 %, -50 %
      {2.0, 1.0, "5A A5 0A 55 01 02 00 43 60 00 00 01 05"},        // clamped: 1.0 m/s = 67 %, 0.5 rad/s = 96 %
      {-0.3, 0.1, "5A A5 0A 55 01 02 00 EC 13 00 00 02 62"},       // reverse: -20 %, 19.1 % -> 19
      {-5.0, -5.0, "5A A5 0A 55 01 02 00 BD A0 00 00 03 C1"},      // clamped to -1.0 m/s, -0.5 rad/s
      {0.0074, -0.001, "5A A5 0A 55 01 02 00 00 00 00 00 04 65"},  // below half a percent: 0
  };
  int k = 1;
  for (const Case& c : cases) {
    d.tick(k++, cmd(c.v, c.omega));
    auto got = base.read_exact(kFrameSize);
    EXPECT_EQ(to_hex(got.data(), got.size()), c.bytes) << "v=" << c.v << " omega=" << c.omega;
  }
  EXPECT_TRUE(base.drain().empty());  // one frame per tick, nothing else
}

TEST(BaseDriverPty, ForwardOnlyRobotNeverCommandsReverse) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  PtyPeer base(dir + "/scout");
  VelocityLimits forward = kReversible;
  forward.min_v_mps = 0.0;  // as in config/robot.yaml
  Driver d(dir + "/scout", forward);
  d.bus.advance_to(kT0);
  ASSERT_EQ(d.open(kT0), SerialLink::OpenResult::kOpened) << d.last_message;
  d.tick(1, cmd(-0.5, -0.6));
  auto got = base.read_exact(kFrameSize);
  EXPECT_EQ(to_hex(got.data(), got.size()), "5A A5 0A 55 01 02 00 00 A0 00 00 00 01");
}

TEST(BaseDriverPty, StatusInPiecesAndGarbageBecomesOdometry) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  PtyPeer base(dir + "/scout");
  Driver d(dir + "/scout", kReversible);
  d.bus.advance_to(kT0);
  ASSERT_EQ(d.open(kT0), SerialLink::OpenResult::kOpened) << d.last_message;

  // 10 motion-status frames at 1 m/s straight, 20 ms apart, each preceded by
  // garbage, and written in two pieces that split the frame.
  int64_t t = kT0 + 1000;
  for (int i = 0; i < 10; ++i) {
    std::vector<uint8_t> bytes = {0x00, 0x5A, 0x11, 0xA5};  // 4 noise bytes
    FrameBytes f = encode(MotionStatus{1000, 0}, static_cast<uint8_t>(i));
    bytes.insert(bytes.end(), f.begin(), f.end());
    const size_t cut = 4 + static_cast<size_t>(i % 12) + 1;
    base.write(bytes.data(), cut);
    ASSERT_TRUE(d.receive(t));
    base.write(bytes.data() + cut, bytes.size() - cut);
    ASSERT_TRUE(d.receive(t));  // the rest arrives; stamped at the same time
    t += 20'000;
  }
  auto odo = d.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 10u);
  for (size_t i = 0; i < odo.size(); ++i) {
    EXPECT_NEAR(odo[i].x, 0.02 * static_cast<double>(i), 1e-12);
    EXPECT_DOUBLE_EQ(odo[i].v, 1.0);
  }
  EXPECT_EQ(d.core.counter("serial_noise_bytes"), 40);
  EXPECT_TRUE(d.core.link_ok());
}

TEST(BaseDriverPty, HangUpThenReconnectAtTheSamePath) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  const std::string path = dir + "/scout";
  auto base = std::make_unique<PtyPeer>(path);
  Driver d(path, kReversible);
  d.bus.advance_to(kT0);
  ASSERT_EQ(d.open(kT0), SerialLink::OpenResult::kOpened) << d.last_message;
  base->write(encode(MotionStatus{500, 0}, 0));
  ASSERT_TRUE(d.receive(kT0 + 1000));
  EXPECT_TRUE(d.core.link_ok());
  d.tick(1, cmd(0.75, 0.0));
  EXPECT_EQ(base->read_exact(kFrameSize).size(), kFrameSize);

  // The simulator exits: master closed, symlink left dangling.
  base->hang_up();
  const int64_t t_lost = kT0 + 2 * kTick;
  EXPECT_FALSE(d.receive(t_lost));
  EXPECT_NE(d.lost_reason.find("hang-up"), std::string::npos) << d.lost_reason;
  EXPECT_FALSE(d.link.is_open());
  EXPECT_FALSE(d.core.link_ok());
  EXPECT_FALSE(d.core.port_open());
  auto odo = d.bus.decoded<evade::odometry_t>(kOdometryChannel);
  ASSERT_EQ(odo.size(), 2u);
  EXPECT_EQ(odo.back().v, 0.0);             // considered stopped
  EXPECT_EQ(odo.back().utime, kT0 + 1000);  // stamped with the last real odometry: not fresh
  EXPECT_FALSE(d.bus.decoded<evade::base_status_t>(kBaseStatusChannel).back().link_ok);
  // libserial could not Close() the hung-up port: the link leaked the object
  // instead of letting its destructor abort the process (we are still here).
  EXPECT_EQ(d.link.leaked_ports(), 1u);

  // While the device is gone, reopening fails (and is retried later), and
  // the commands have nowhere to go.
  EXPECT_EQ(d.open(t_lost), SerialLink::OpenResult::kNotDue);  // back-off
  EXPECT_EQ(d.open(d.link.next_attempt()), SerialLink::OpenResult::kFailed);
  EXPECT_NE(d.last_message.find("No such file"), std::string::npos) << d.last_message;
  d.tick(3, cmd(0.75, 0.0));
  EXPECT_TRUE(d.core.take_tx().empty());

  // The simulator comes back on a new pty, linked at the same path.
  base = std::make_unique<PtyPeer>(path);
  ASSERT_EQ(d.open(d.link.next_attempt()), SerialLink::OpenResult::kOpened) << d.last_message;
  const int64_t t_back = d.link.next_attempt() + kTick;
  base->write(encode(MotionStatus{500, 0}, 1));
  ASSERT_TRUE(d.receive(t_back));
  EXPECT_TRUE(d.core.link_ok());
  // Commands reach the new master: one frame per tick, carrying CMD_VEL.
  d.core.take_tx();
  base->drain();
  const int k0 = static_cast<int>((t_back - kT0) / kTick) + 2;
  d.tick(k0, cmd(0.75, 0.0));
  d.tick(k0 + 1, cmd(0.75, 0.0));
  std::vector<MotionCommand> sent;
  auto got = base->read_exact(2 * kFrameSize);
  StreamParser parser;
  parser.feed(got.data(), got.size(), [&](const Frame& f) {
    MotionCommand mc;
    if (from_frame(f, &mc)) sent.push_back(mc);
  });
  ASSERT_EQ(sent.size(), 2u);
  EXPECT_EQ(sent[1].linear_percent, 50);
  // Odometry restarted from where it stopped, without integrating the gap.
  odo = d.bus.decoded<evade::odometry_t>(kOdometryChannel);
  EXPECT_DOUBLE_EQ(odo.back().x, odo[odo.size() - 2].x);
  EXPECT_DOUBLE_EQ(odo.back().v, 0.5);
}

TEST(BaseDriverPty, WriteAfterHangUpReportsTheLoss) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  PtyPeer base(dir + "/scout");
  SerialLink link(dir + "/scout", 115200, 0.1, 2.0);
  ASSERT_EQ(link.try_open(0, nullptr), SerialLink::OpenResult::kOpened);
  base.hang_up();
  const uint8_t byte = 0;
  std::string why;
  EXPECT_FALSE(link.write(5, &byte, 1, &why));
  EXPECT_NE(why.find("Input/output error"), std::string::npos) << why;
  EXPECT_FALSE(link.is_open());
  EXPECT_EQ(link.next_attempt(), 5 + 100'000);
}

TEST(BaseDriverPty, MissingDeviceIsRetriedWithBackOff) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  SerialLink link(dir + "/absent", 115200, 0.1, 1.0);
  std::string msg;
  int64_t t = 0;
  std::vector<int64_t> attempts;
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(link.try_open(t, &msg), SerialLink::OpenResult::kFailed);
    attempts.push_back(t);
    EXPECT_EQ(link.try_open(link.next_attempt() - 1, &msg), SerialLink::OpenResult::kNotDue);
    t = link.next_attempt();
  }
  // 0.1, 0.2, 0.4, 0.8, then capped at 1.0 s.
  EXPECT_EQ(attempts, (std::vector<int64_t>{0, 100'000, 300'000, 700'000, 1'500'000, 2'500'000, 3'500'000}));
  link.try_open(t, &msg);
  EXPECT_NE(msg.find("retrying in 1.00 s"), std::string::npos) << msg;
  // The device appears: the next due attempt opens it and resets the back-off.
  PtyPeer base(dir + "/absent");
  EXPECT_EQ(link.try_open(link.next_attempt(), &msg), SerialLink::OpenResult::kOpened) << msg;
  EXPECT_DOUBLE_EQ(link.current_backoff_s(), 0.1);
}

TEST(BaseDriverPty, NonTerminalDeviceIsRefusedWithoutAborting) {
  TempDir tmp;
  const std::string& dir = tmp.path;
  std::ofstream(dir + "/file") << "not a serial port";
  SerialLink link(dir + "/file", 115200, 0.1, 2.0);
  std::string msg;
  EXPECT_EQ(link.try_open(0, &msg), SerialLink::OpenResult::kFailed);
  EXPECT_NE(msg.find("not a terminal"), std::string::npos) << msg;
}

// The failure this design avoids (libserial 1.0, Debian 12): a plain
// libserial SerialPort destroyed after a hang-up takes the process down.
TEST(BaseDriverPtyDeathTest, PlainLibSerialAbortsAfterHangUp) {
  GTEST_FLAG_SET(death_test_style, "fast");  // fork only: the child uses the parent's temp dir
  TempDir tmp;
  const std::string& dir = tmp.path;
  EXPECT_DEATH(
      {
        PtyPeer base(dir + "/scout");
        {
          LibSerial::SerialPort port;
          port.Open(dir + "/scout");
          base.hang_up();
        }  // ~SerialPort -> Close() throws EIO from a destructor
      },
      "");
}

}  // namespace
}  // namespace evade::base
