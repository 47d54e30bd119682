// The simulator's I/O adapters: the emulated base's pseudo-terminal and
// the LiDAR destination parser (lib/sim/pseudo_terminal.h, udp_sender.h).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "sim/pseudo_terminal.h"
#include "sim/udp_sender.h"

namespace {

namespace fs = std::filesystem;
using evade::sim::PseudoTerminal;

struct TempDir {
  TempDir() {
    char tmpl[] = "/tmp/evade_sim_io_test_XXXXXX";
    if (!::mkdtemp(tmpl)) throw std::runtime_error("mkdtemp failed");
    path = tmpl;
  }
  ~TempDir() { fs::remove_all(path); }
  std::string path;
};

TEST(SimPseudoTerminal, LinksTheSlaveAndPassesBytesBothWaysUnchanged) {
  TempDir tmp;
  const std::string link = tmp.path + "/scout";
  PseudoTerminal pty(link);
  ASSERT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link).string(), pty.slave_path());
  const int port = ::open(link.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(port, 0);
  const uint8_t frame[] = {0x5A, 0xA5, 0x0A, 0x0D, 0x00, 0xFF};  // raw mode: CR, LF, NUL pass as they are
  ASSERT_EQ(::write(pty.master(), frame, sizeof frame), static_cast<ssize_t>(sizeof frame));
  pollfd p{port, POLLIN, 0};
  ASSERT_EQ(::poll(&p, 1, 2000), 1);
  uint8_t got[16] = {};
  ASSERT_EQ(::read(port, got, sizeof got), static_cast<ssize_t>(sizeof frame));
  EXPECT_EQ(std::memcmp(got, frame, sizeof frame), 0);
  ASSERT_EQ(::write(port, frame, 2), 2);
  pollfd m{pty.master(), POLLIN, 0};
  ASSERT_EQ(::poll(&m, 1, 2000), 1);
  EXPECT_EQ(::read(pty.master(), got, sizeof got), 2);
  ::close(port);
}

TEST(SimPseudoTerminal, UnreadBytesAreCountedAndDiscarded) {
  TempDir tmp;
  PseudoTerminal pty(tmp.path + "/scout");
  const uint8_t bytes[40] = {};
  ASSERT_EQ(::write(pty.master(), bytes, sizeof bytes), 40);
  for (int i = 0; i < 100 && pty.unread() < 40; ++i) ::usleep(1000);
  EXPECT_EQ(pty.unread(), 40);
  pty.discard_unread();
  EXPECT_EQ(pty.unread(), 0);
}

TEST(SimPseudoTerminal, ReplacesAStaleLinkButNeverARealFile) {
  TempDir tmp;
  const std::string link = tmp.path + "/scout";
  fs::create_symlink("/dev/pts/does-not-exist", link);
  {
    PseudoTerminal pty(link);
    EXPECT_EQ(fs::read_symlink(link).string(), pty.slave_path());
  }
  EXPECT_FALSE(fs::exists(fs::symlink_status(link)));  // its own link removed at the end
  const std::string file = tmp.path + "/file";
  std::ofstream(file) << "keep";
  EXPECT_THROW(PseudoTerminal{file}, std::runtime_error);
  std::ifstream in(file);
  std::string content;
  in >> content;
  EXPECT_EQ(content, "keep");
}

TEST(SimPseudoTerminal, HangUpLeavesTheLinkToTheNextPty) {
  TempDir tmp;
  const std::string link = tmp.path + "/scout";
  auto first = std::make_unique<PseudoTerminal>(link);
  first->hang_up();
  EXPECT_TRUE(fs::is_symlink(link));  // dangling, as when the simulator dies
  PseudoTerminal second(link);        // may reuse the first slave's name
  first.reset();
  ASSERT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(fs::read_symlink(link).string(), second.slave_path());
}

TEST(SimLidarDestination, HostPortParsedStrictly) {
  std::string host;
  int port = 0;
  EXPECT_TRUE(evade::sim::parse_host_port("127.0.0.1:2368", &host, &port));
  EXPECT_EQ(host, "127.0.0.1");
  EXPECT_EQ(port, 2368);
  EXPECT_TRUE(evade::sim::parse_host_port("robot:1", &host, &port));
  EXPECT_EQ(host, "robot");
  EXPECT_EQ(port, 1);
  for (const char* bad : {"127.0.0.1", ":2368", "h:0", "h:65536", "h:23x", "h:", "h:-5"})
    EXPECT_FALSE(evade::sim::parse_host_port(bad, &host, &port)) << bad;
}

TEST(SimLidarDestination, UnresolvableHostIsAnError) {
  EXPECT_THROW(evade::sim::UdpSender("no-such-host.invalid", 2368), std::runtime_error);
}

}  // namespace
