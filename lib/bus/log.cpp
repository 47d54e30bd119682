#include "bus/log.h"

#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

namespace evade::bus {

void for_each_event(const std::string& path, const std::function<void(const LogEvent&)>& fn) {
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error("cannot open log " + path);
  while (const lcm::LogEvent* ev = log.readNextEvent()) {
    LogEvent e;
    e.timestamp = ev->timestamp;
    e.channel = ev->channel;
    const auto* p = static_cast<const uint8_t*>(ev->data);
    e.data.assign(p, p + ev->datalen);
    fn(e);
  }
}

std::vector<LogEvent> read_log(const std::string& path) {
  std::vector<LogEvent> out;
  for_each_event(path, [&](const LogEvent& e) { out.push_back(e); });
  return out;
}

struct LogWriter::Impl {
  explicit Impl(const std::string& path) : log(path, "w") {}
  lcm::LogFile log;
  int64_t eventnum = 0;
};

LogWriter::LogWriter(const std::string& path) : impl_(std::make_unique<Impl>(path)) {
  if (!impl_->log.good()) throw std::runtime_error("cannot create log " + path);
}

LogWriter::~LogWriter() = default;

void LogWriter::write(int64_t timestamp, const std::string& channel, const std::vector<uint8_t>& data) {
  lcm::LogEvent ev;
  ev.eventnum = impl_->eventnum++;
  ev.timestamp = timestamp;
  ev.channel = channel;
  ev.datalen = static_cast<int32_t>(data.size());
  ev.data = const_cast<uint8_t*>(data.data());
  impl_->log.writeEvent(&ev);
}

void LogWriter::write(const LogEvent& e) { write(e.timestamp, e.channel, e.data); }

void write_log(const std::string& path, const std::vector<LogEvent>& events) {
  LogWriter w(path);
  for (const auto& e : events) w.write(e);
}

}  // namespace evade::bus
