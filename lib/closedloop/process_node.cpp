#include "closedloop/process_node.h"

#include <algorithm>
#include <stdexcept>

namespace evade::closedloop {

ProcessNode::ProcessNode(bus::Core& core, EventQueue& queue, ComputeModel model, std::set<std::string> conflated)
    : core_(core), q_(queue), model_(std::move(model)), conflated_(std::move(conflated)) {
  core_.attach(this);
  core_.set_measure_latency(false);  // HEALTH from steady-clock latency would differ run to run
}

void ProcessNode::start(int64_t t) {
  core_.arm_timers(t);
  schedule_timer();
}

void ProcessNode::deliver(const std::string& channel, const Bytes& data) {
  arrive(Work{Kind::kMessage, q_.now(), channel, data, nullptr});
}

void ProcessNode::input(std::function<void()> fn, const std::string& source) {
  arrive(Work{Kind::kInput, q_.now(), source, nullptr, std::move(fn)});
}

void ProcessNode::publish(const std::string& channel, int64_t now, std::vector<uint8_t> data) {
  outputs_.push_back(bus::LogEvent{now, channel, std::move(data)});
}

void ProcessNode::arrive(Work w) {
  if (!busy_) {
    run(std::move(w));
    return;
  }
  if (w.kind == Kind::kMessage && conflated_.count(w.channel)) {
    auto same = [&](const Work& o) { return o.kind == Kind::kMessage && o.channel == w.channel; };
    waiting_.erase(std::remove_if(waiting_.begin(), waiting_.end(), same), waiting_.end());
  }
  waiting_.push_back(std::move(w));
}

void ProcessNode::run(Work w) {
  busy_ = true;
  outputs_.clear();
  const int64_t t = q_.now();
  const double c0 = clock_ ? clock_() : 0.0;
  switch (w.kind) {
    case Kind::kMessage:
      core_.deliver(w.channel, w.data->data(), w.data->size(), t);
      break;
    case Kind::kInput:
      core_.input(t, w.fn, w.channel);
      break;
    case Kind::kTimer:
      core_.fire_next(t);
      break;
  }
  if (clock_ && profiler_) profiler_(outputs_, clock_() - c0);
  const int64_t d = model_ ? model_(outputs_) : 0;
  if (d < 0) throw std::logic_error(core_.name() + ": negative compute time");
  ++callbacks_;
  compute_us_ += d;
  leaving_ = std::move(outputs_);
  outputs_.clear();
  if (cpu_)
    cpu_->run(d, [this] { finish(); });
  else
    q_.at(t + d, [this] { finish(); });
}

// The callback has had its compute time: its outputs leave now.
void ProcessNode::finish() {
  const int64_t leave = q_.now();
  for (auto& o : leaving_) router_(o.channel, leave, std::make_shared<const std::vector<uint8_t>>(std::move(o.data)));
  leaving_.clear();
  if (after_) after_(leave);
  on_free();
}

// Free again: what waited runs first, unless a timer came due before it
// arrived.
void ProcessNode::on_free() {
  busy_ = false;
  const int64_t deadline = core_.next_deadline();
  const bool timer_due = deadline <= q_.now();
  if (!waiting_.empty() && !(timer_due && deadline <= waiting_.front().arrived)) {
    Work w = std::move(waiting_.front());
    waiting_.pop_front();
    run(std::move(w));
  } else if (timer_due) {
    run(Work{Kind::kTimer, q_.now(), {}, nullptr, nullptr});
  } else {
    schedule_timer();
  }
}

void ProcessNode::schedule_timer() {
  const int64_t d = core_.next_deadline();
  if (d == bus::kNever || d >= timer_at_) return;
  timer_at_ = d;
  const uint64_t gen = ++timer_gen_;
  q_.at(d, [this, gen] {
    if (gen != timer_gen_) return;  // superseded by an earlier deadline
    timer_at_ = bus::kNever;
    if (busy_) return;  // on_free() fires it
    if (core_.next_deadline() <= q_.now())
      run(Work{Kind::kTimer, q_.now(), {}, nullptr, nullptr});
    else
      schedule_timer();
  });
}

}  // namespace evade::closedloop
