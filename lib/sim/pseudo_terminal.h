// The emulated base's serial port: a pseudo-terminal pair in raw mode at
// 115200 baud whose slave is linked at a path (the device the base driver
// opens). The simulator writes and reads the master; the tests' serial
// peer (test/base/pty_peer.h) is the same class. An I/O adapter, not part
// of the socket-free sim core.
#pragma once

#include <string>

namespace evade::sim {

class PseudoTerminal {
 public:
  // Opens the pair (master non-blocking) and links `link` to the slave,
  // replacing a stale symbolic link; throws std::runtime_error naming the
  // call that failed, or when `link` exists and is not a symbolic link.
  explicit PseudoTerminal(const std::string& link);
  // Closes both ends and removes the link if it still points at this slave.
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  int master() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }

  // Bytes not yet read by whoever has the slave open (or by nobody).
  int unread() const;
  // Drops them: a real serial line does not keep what nobody read.
  void discard_unread();
  // Closes this side's own slave descriptor (a driver's stays open). With
  // no slave open, reading the master gives EIO.
  void close_own_slave();
  // Closes both ends (the driver sees a hang-up) and leaves the link
  // dangling, as when the simulator dies; the destructor then leaves the
  // link alone (a new pty may reuse the slave's name).
  void hang_up();

 private:
  void open_pair();
  void link_slave();

  std::string link_;
  std::string slave_path_;
  int master_ = -1;
  int slave_ = -1;
};

}  // namespace evade::sim
