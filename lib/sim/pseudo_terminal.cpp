#include "sim/pseudo_terminal.h"

#include <fcntl.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace evade::sim {
namespace {

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what + ": " + std::strerror(errno)); }

}  // namespace

PseudoTerminal::PseudoTerminal(const std::string& link) : link_(link) {
  try {
    open_pair();
    link_slave();
  } catch (...) {
    hang_up();
    throw;
  }
}

void PseudoTerminal::open_pair() {
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (master_ < 0) fail("posix_openpt");
  if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0) fail("grantpt/unlockpt");
  const char* name = ::ptsname(master_);
  if (!name) throw std::runtime_error("ptsname failed");
  slave_path_ = name;
  // Our own slave descriptor stays open for the whole run: with no slave
  // open, reading the master gives EIO, and a driver that closes and
  // reopens the port must find it as it was.
  slave_ = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (slave_ < 0) fail("open " + slave_path_);
  termios tio{};
  if (::tcgetattr(slave_, &tio) != 0) fail("tcgetattr");
  ::cfmakeraw(&tio);  // no echo, no newline rewriting: binary frames pass unchanged
  ::cfsetispeed(&tio, B115200);
  ::cfsetospeed(&tio, B115200);
  if (::tcsetattr(slave_, TCSANOW, &tio) != 0) fail("tcsetattr");
}

void PseudoTerminal::link_slave() {
  struct stat st {};
  if (::lstat(link_.c_str(), &st) == 0) {
    // Replace a stale link from an earlier run; never delete a real file or device.
    if (!S_ISLNK(st.st_mode)) throw std::runtime_error(link_ + " exists and is not a symbolic link; not replacing it");
    ::unlink(link_.c_str());
  }
  if (::symlink(slave_path_.c_str(), link_.c_str()) != 0) fail("symlink " + link_ + " -> " + slave_path_);
}

PseudoTerminal::~PseudoTerminal() {
  char target[256];
  ssize_t n = ::readlink(link_.c_str(), target, sizeof(target) - 1);
  if (n > 0) {
    target[n] = 0;
    if (!slave_path_.empty() && slave_path_ == target) ::unlink(link_.c_str());  // only our own link
  }
  hang_up();
}

int PseudoTerminal::unread() const {
  int n = 0;
  return slave_ >= 0 && ::ioctl(slave_, FIONREAD, &n) == 0 ? n : 0;
}

void PseudoTerminal::discard_unread() {
  if (slave_ >= 0) ::tcflush(slave_, TCIFLUSH);
}

void PseudoTerminal::close_own_slave() {
  if (slave_ >= 0) ::close(slave_);
  slave_ = -1;
}

void PseudoTerminal::hang_up() {
  close_own_slave();
  if (master_ >= 0) ::close(master_);
  master_ = -1;
  // The slave's name is free for the next pty: a link to it is no longer ours.
  slave_path_.clear();
}

}  // namespace evade::sim
