// One direction of a UART in simulated time: bytes written at t go out one
// after another at the line's byte time (start + 8 data + stop bits at the
// baud rate) behind whatever is still being sent, and each write reaches
// the reader as one chunk when its last byte has arrived.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "closedloop/event_queue.h"

namespace evade::closedloop {

class SerialLine {
 public:
  using Reader = std::function<void(const std::vector<uint8_t>& bytes)>;
  SerialLine(EventQueue& queue, int baud_rate, Reader reader);

  void write(int64_t t, std::vector<uint8_t> bytes);
  double byte_time_us() const { return byte_us_; }
  int64_t bytes_sent() const { return sent_; }

 private:
  EventQueue& q_;
  double byte_us_;
  Reader reader_;
  double free_at_us_ = 0;  // when the last queued byte has gone out
  int64_t sent_ = 0;
};

}  // namespace evade::closedloop
