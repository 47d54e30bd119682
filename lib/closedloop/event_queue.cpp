#include "closedloop/event_queue.h"

#include <algorithm>

#include "bus/core.h"

namespace evade::closedloop {

void EventQueue::at(int64_t t, Fn fn) {
  heap_.push_back(Event{std::max(t, now_), seq_++, std::move(fn)});
  std::push_heap(heap_.begin(), heap_.end(), Later{});
}

bool EventQueue::run_next() {
  if (heap_.empty()) return false;
  std::pop_heap(heap_.begin(), heap_.end(), Later{});
  Event e = std::move(heap_.back());
  heap_.pop_back();
  now_ = e.t;
  ++run_;
  e.fn();
  return true;
}

int64_t EventQueue::next_time() const { return heap_.empty() ? bus::kNever : heap_.front().t; }

}  // namespace evade::closedloop
