// The base's serial port: opened and configured with libserial (115200 8N1,
// raw, no flow control), read and written through its raw file descriptor
// (non-blocking), reopened with exponential back-off when missing or lost.
//
// Why the raw fd and the careful ownership: libserial 1.0 cannot survive a
// hang-up. When the peer goes away (USB adapter unplugged, the simulator's
// pty master closed), SerialPort::Read throws runtime_error("Success"),
// SerialPort::Close() fails in its tcsetattr (EIO) and throws *before*
// closing the descriptor, and ~SerialPort calls Close() again, so the
// exception leaves a destructor and std::terminate aborts the process.
// Therefore:
//  - I/O is ::read/::write on GetFileDescriptor(): a hang-up is then an
//    ordinary return value (read 0 or EIO, write EIO, POLLHUP), not an
//    exception thrown from somewhere in libserial;
//  - on a fault we try Close() once, inside try/catch; if it succeeds the
//    object is destroyed normally. If it throws, the SerialPort object is
//    deliberately leaked after we ::close() its descriptor ourselves:
//    destroying it would call Close() again on a dead (or, worse, reused)
//    descriptor and abort. The leak is one small object per hang-up of a
//    dead device, bounded by how often someone pulls the cable.
//  - a clean shutdown of a live port destroys it normally (Close restores
//    the saved termios settings).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace LibSerial {
class SerialPort;
}

namespace evade::base {

class SerialLink {
 public:
  // Back-off: the first attempt is due at once; each failed attempt doubles
  // the wait, from backoff_min_s up to backoff_max_s; a successful open
  // resets it; after a loss the next attempt is backoff_min_s later.
  SerialLink(std::string device, int baud_rate, double backoff_min_s, double backoff_max_s);
  ~SerialLink();
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  enum class OpenResult { kAlreadyOpen, kNotDue, kOpened, kFailed };
  // Tries to open the device if it is closed and an attempt is due at `now`
  // (us). On kFailed, *message says why and when the next attempt is.
  OpenResult try_open(int64_t now, std::string* message);
  int64_t next_attempt() const { return next_attempt_; }
  double current_backoff_s() const { return backoff_s_; }

  bool is_open() const { return fd_ >= 0; }
  int fd() const { return fd_; }
  const std::string& device() const { return device_; }

  // Appends every byte available now to *out. Returns false if the link is
  // lost (hang-up, I/O error); the port is then closed and *reason set.
  bool read_available(int64_t now, std::vector<uint8_t>* out, std::string* reason);
  // Writes without blocking. Returns false if the link is lost (closed, as
  // above). Bytes the driver cannot take right now (a full buffer) are
  // dropped and counted: a late motion command is worse than a missing one,
  // the next one follows within a command period.
  bool write(int64_t now, const uint8_t* data, size_t size, std::string* reason);
  uint64_t dropped_tx_bytes() const { return dropped_tx_bytes_; }
  // How many SerialPort objects were leaked because Close() threw.
  uint64_t leaked_ports() const { return leaked_ports_; }

  // Closes after a fault (see the header comment); safe on a dead device.
  void close_after_fault(int64_t now);

 private:
  std::string device_;
  int baud_rate_;
  double backoff_min_s_;
  double backoff_max_s_;
  double backoff_s_;
  int64_t next_attempt_ = 0;
  std::unique_ptr<LibSerial::SerialPort> port_;
  int fd_ = -1;
  uint64_t dropped_tx_bytes_ = 0;
  uint64_t leaked_ports_ = 0;
};

}  // namespace evade::base
