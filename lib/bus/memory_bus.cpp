#include "bus/memory_bus.h"

#include <algorithm>

namespace evade::bus {

void MemoryBus::add(Core& core) {
  core.attach(this);
  cores_.push_back(&core);
}

void MemoryBus::publish(const std::string& channel, int64_t now, std::vector<uint8_t> data) {
  LogEvent e{now, channel, std::move(data)};
  published_.push_back(e);
  queue_.push_back(std::move(e));
}

void MemoryBus::drain() {
  while (!queue_.empty()) {
    LogEvent e = std::move(queue_.front());
    queue_.pop_front();
    for (Core* c : cores_) c->deliver(e.channel, e.data.data(), e.data.size(), e.timestamp);
  }
}

void MemoryBus::advance_to(int64_t now) {
  now_ = std::max(now_, now);
  // One timer at a time across cores, in deadline order (ties: the core
  // added first), draining what each causes before the next.
  while (true) {
    Core* due = nullptr;
    int64_t best = kNever;
    for (Core* c : cores_) {
      c->arm_timers(now_);
      int64_t d = c->next_deadline();
      if (d <= now_ && d < best) {
        best = d;
        due = c;
      }
    }
    if (!due) break;
    due->fire_next(now_);
    drain();
  }
}

void MemoryBus::inject(const std::string& channel, const uint8_t* data, size_t size, int64_t now) {
  advance_to(now);
  for (Core* c : cores_) c->deliver(channel, data, size, now);
  drain();
}

void MemoryBus::input(Core& core, int64_t now, const std::function<void()>& fn) {
  advance_to(now);
  core.input(now, fn);
  drain();
}

std::vector<LogEvent> MemoryBus::take_published() {
  std::vector<LogEvent> out;
  out.swap(published_);
  return out;
}

}  // namespace evade::bus
