#include "closedloop/serial_line.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace evade::closedloop {

SerialLine::SerialLine(EventQueue& queue, int baud_rate, Reader reader)
    : q_(queue), byte_us_(baud_rate > 0 ? 10.0 * 1e6 / baud_rate : 0.0), reader_(std::move(reader)) {
  if (baud_rate <= 0) throw std::invalid_argument("serial line: baud rate must be positive");
}

void SerialLine::write(int64_t t, std::vector<uint8_t> bytes) {
  if (bytes.empty()) return;
  const double start = std::max(static_cast<double>(t), free_at_us_);
  free_at_us_ = start + byte_us_ * static_cast<double>(bytes.size());
  sent_ += static_cast<int64_t>(bytes.size());
  auto chunk = std::make_shared<std::vector<uint8_t>>(std::move(bytes));
  q_.at(static_cast<int64_t>(std::ceil(free_at_us_)), [this, chunk] { reader_(*chunk); });
}

}  // namespace evade::closedloop
