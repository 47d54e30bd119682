#include "base/serial_link.h"

#include <fcntl.h>
#include <libserial/SerialPort.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace evade::base {

namespace {

LibSerial::BaudRate to_libserial_baud(int baud) {
  using B = LibSerial::BaudRate;
  switch (baud) {
    case 9600:
      return B::BAUD_9600;
    case 19200:
      return B::BAUD_19200;
    case 38400:
      return B::BAUD_38400;
    case 57600:
      return B::BAUD_57600;
    case 115200:
      return B::BAUD_115200;
    case 230400:
      return B::BAUD_230400;
    case 460800:
      return B::BAUD_460800;
    default:
      throw std::invalid_argument("unsupported baud rate " + std::to_string(baud));
  }
}

std::string errno_text(int err) { return std::strerror(err); }

// Disposes of a SerialPort whose descriptor may be dead, never letting its
// destructor run Close() on a port that failed to close (see the header).
// Returns true if the object had to be leaked.
bool dispose(std::unique_ptr<LibSerial::SerialPort> port) {
  if (!port) return false;
  if (!port->IsOpen()) return false;  // destructor will not touch the fd
  try {
    port->Close();
    return false;
  } catch (const std::exception&) {
  }
  // Close() threw before closing the descriptor: close it ourselves and
  // leak the object, whose destructor would call Close() once more.
  const int fd = port->GetFileDescriptor();
  if (fd >= 0) ::close(fd);
  (void)port.release();
  return true;
}

}  // namespace

SerialLink::SerialLink(std::string device, int baud_rate, double backoff_min_s, double backoff_max_s)
    : device_(std::move(device)),
      baud_rate_(baud_rate),
      backoff_min_s_(backoff_min_s),
      backoff_max_s_(std::max(backoff_min_s, backoff_max_s)),
      backoff_s_(backoff_min_s) {
  to_libserial_baud(baud_rate_);  // reject an unsupported rate up front
}

SerialLink::~SerialLink() {
  if (port_) leaked_ports_ += dispose(std::move(port_)) ? 1 : 0;
}

SerialLink::OpenResult SerialLink::try_open(int64_t now, std::string* message) {
  if (is_open()) return OpenResult::kAlreadyOpen;
  if (now < next_attempt_) return OpenResult::kNotDue;

  auto fail = [&](const std::string& why) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "; retrying in %.2f s", backoff_s_);
    if (message) *message = "cannot open " + device_ + ": " + why + buf;
    next_attempt_ = now + static_cast<int64_t>(std::llround(backoff_s_ * 1e6));
    backoff_s_ = std::min(backoff_s_ * 2.0, backoff_max_s_);
    return OpenResult::kFailed;
  };

  // libserial 1.0's Open() leaves the descriptor open when a later step
  // fails (e.g. the path is a regular file: TIOCEXCL/tcgetattr fail), and
  // the destructor then aborts; so check that it is a terminal first.
  {
    int probe = ::open(device_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (probe < 0) return fail(errno_text(errno));
    const bool tty = ::isatty(probe) == 1;
    ::close(probe);
    if (!tty) return fail("not a terminal device");
  }

  auto port = std::make_unique<LibSerial::SerialPort>();
  try {
    port->Open(device_);
    port->SetBaudRate(to_libserial_baud(baud_rate_));
    port->SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    port->SetParity(LibSerial::Parity::PARITY_NONE);
    port->SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    port->SetFlowControl(LibSerial::FlowControl::FLOW_CONTROL_NONE);
  } catch (const std::exception& e) {
    leaked_ports_ += dispose(std::move(port)) ? 1 : 0;
    return fail(std::string("libserial: ") + e.what());
  }
  const int fd = port->GetFileDescriptor();

  // Binary frames contain 0x0A and 0x0D: make sure no line discipline
  // rewrites them (cfmakeraw), keeping libserial's speed and 8N1, and keep
  // the descriptor non-blocking so a read never stalls the event loop.
  // VMIN = 1 (not 0) so that a non-blocking read with nothing to read says
  // EAGAIN and a read of 0 bytes unambiguously means a hang-up.
  termios tio{};
  if (::tcgetattr(fd, &tio) == 0) {
    const speed_t ispeed = cfgetispeed(&tio);
    const speed_t ospeed = cfgetospeed(&tio);
    cfmakeraw(&tio);
    cfsetispeed(&tio, ispeed);
    cfsetospeed(&tio, ospeed);
    tio.c_cflag |= CLOCAL | CREAD;
    tio.c_cflag &= ~static_cast<tcflag_t>(CRTSCTS | CSTOPB | PARENB);
    tio.c_cc[VMIN] = 1;
    tio.c_cc[VTIME] = 0;
    if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
      const int err = errno;
      leaked_ports_ += dispose(std::move(port)) ? 1 : 0;
      return fail("tcsetattr: " + errno_text(err));
    }
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags < 0 || ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) < 0) {
    const int err = errno;
    leaked_ports_ += dispose(std::move(port)) ? 1 : 0;
    return fail("fcntl: " + errno_text(err));
  }

  port_ = std::move(port);
  fd_ = fd;
  backoff_s_ = backoff_min_s_;
  if (message) *message = "opened " + device_;
  return OpenResult::kOpened;
}

void SerialLink::close_after_fault(int64_t now) {
  if (port_) leaked_ports_ += dispose(std::move(port_)) ? 1 : 0;
  fd_ = -1;
  backoff_s_ = backoff_min_s_;
  next_attempt_ = now + static_cast<int64_t>(std::llround(backoff_min_s_ * 1e6));
}

bool SerialLink::read_available(int64_t now, std::vector<uint8_t>* out, std::string* reason) {
  if (!is_open()) {
    if (reason) *reason = "port not open";
    return false;
  }
  uint8_t buf[4096];
  while (true) {
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n > 0) {
      out->insert(out->end(), buf, buf + n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
    // With VMIN = 1 and O_NONBLOCK, "no data" is EAGAIN; 0 is end of file:
    // the terminal was hung up (the pty master closed, the adapter gone).
    if (reason) *reason = n == 0 ? "hang-up on " + device_ : "read " + device_ + ": " + errno_text(errno);
    close_after_fault(now);
    return false;
  }
}

bool SerialLink::write(int64_t now, const uint8_t* data, size_t size, std::string* reason) {
  if (!is_open()) {
    if (reason) *reason = "port not open";
    return false;
  }
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      dropped_tx_bytes_ += size - done;
      return true;
    }
    if (reason) *reason = "write " + device_ + ": " + (n < 0 ? errno_text(errno) : std::string("wrote nothing"));
    close_after_fault(now);
    return false;
  }
  return true;
}

}  // namespace evade::base
