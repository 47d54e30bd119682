// lcm-logger files, read and written in process.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace evade::bus {

struct LogEvent {
  int64_t timestamp;  // us, bus time (lcm-logger's receive time)
  std::string channel;
  std::vector<uint8_t> data;
};

// Reads a whole log. Throws std::runtime_error if it cannot be opened.
std::vector<LogEvent> read_log(const std::string& path);
// Calls fn for each event in order without holding the log in memory.
void for_each_event(const std::string& path, const std::function<void(const LogEvent&)>& fn);

class LogWriter {
 public:
  explicit LogWriter(const std::string& path);  // throws if it cannot be created
  ~LogWriter();
  void write(const LogEvent& e);
  void write(int64_t timestamp, const std::string& channel, const std::vector<uint8_t>& data);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

void write_log(const std::string& path, const std::vector<LogEvent>& events);

}  // namespace evade::bus
