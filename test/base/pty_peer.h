// Test helper: the far end of a serial line, the simulator's own
// pseudo-terminal (lib/sim/pseudo_terminal.h). The master is "the base";
// the slave (raw mode) is what the driver opens, through a symlink at a
// fixed path, as the simulator does it.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/pseudo_terminal.h"

namespace evade::base::testing {

class PtyPeer {
 public:
  // Creates a pty and points `link_path` at its slave (replacing a stale link).
  explicit PtyPeer(const std::string& link_path) : pty_(link_path) {}

  // Closes both ends (the driver sees a hang-up) and leaves the symlink
  // dangling, as when the simulator dies.
  void hang_up() { pty_.hang_up(); }

  void write(const uint8_t* data, size_t size) {
    size_t done = 0;
    while (done < size) {
      ssize_t n = ::write(master(), data + done, size - done);
      if (n > 0) {
        done += static_cast<size_t>(n);
      } else if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
        pollfd p{master(), POLLOUT, 0};
        ::poll(&p, 1, 100);
      } else {
        throw std::runtime_error("pty master write failed");
      }
    }
  }
  template <class Bytes>
  void write(const Bytes& b) {
    write(b.data(), b.size());
  }

  // Reads exactly n bytes, waiting up to `timeout_ms` in total (a generous
  // bound for the kernel to pass bytes across the pty, not a timing check).
  std::vector<uint8_t> read_exact(size_t n, int timeout_ms = 5000) {
    std::vector<uint8_t> out;
    auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (out.size() < n && std::chrono::steady_clock::now() < deadline) {
      uint8_t buf[256];
      ssize_t r = ::read(master(), buf, std::min(sizeof buf, n - out.size()));
      if (r > 0) {
        out.insert(out.end(), buf, buf + r);
        continue;
      }
      pollfd p{master(), POLLIN, 0};
      ::poll(&p, 1, 20);
    }
    return out;
  }
  // Everything readable now, after a short settle (for "nothing more came").
  std::vector<uint8_t> drain(int settle_ms = 50) {
    std::vector<uint8_t> out;
    pollfd p{master(), POLLIN, 0};
    while (::poll(&p, 1, settle_ms) > 0) {
      uint8_t buf[256];
      ssize_t r = ::read(master(), buf, sizeof buf);
      if (r <= 0) break;
      out.insert(out.end(), buf, buf + r);
    }
    return out;
  }

  int master() const { return pty_.master(); }
  const std::string& slave_name() const { return pty_.slave_path(); }

 private:
  evade::sim::PseudoTerminal pty_;
};

// A fresh directory under /tmp, removed with everything in it at scope exit.
struct TempDir {
  TempDir() {
    char tmpl[] = "/tmp/evade_base_test_XXXXXX";
    if (!::mkdtemp(tmpl)) throw std::runtime_error("mkdtemp failed");
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string path;
};

// Waits until `fd` is readable (or hung up), up to timeout_ms.
inline bool wait_readable(int fd, int timeout_ms = 5000) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, timeout_ms) > 0;
}

}  // namespace evade::base::testing
