#include "closedloop/cpu.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace evade::closedloop {

namespace {
// A job whose remaining work is below this (us) is done: completion times
// are whole microseconds, so the last step may overshoot by a fraction.
constexpr double kDoneUs = 1e-6;
}  // namespace

Cpu::Cpu(EventQueue& queue, double cores, double background_cores)
    : q_(queue), cores_(cores), background_(background_cores) {
  if (!(cores_ > 0.0) || !(background_ >= 0.0)) throw std::invalid_argument("Cpu: cores > 0, background >= 0");
}

double Cpu::rate() const {
  if (jobs_.empty()) return 0.0;
  return std::min(1.0, cores_ / (static_cast<double>(jobs_.size()) + background_));
}

void Cpu::run(int64_t work_us, std::function<void()> done) {
  if (work_us < 0) throw std::logic_error("Cpu: negative work");
  advance();
  jobs_.push_back(Job{static_cast<double>(work_us), std::move(done)});
  schedule_next();
}

// Counts the time since last_ off every running job at the current rate.
void Cpu::advance() {
  const int64_t now = q_.now();
  if (now > last_ && !jobs_.empty()) {
    const double given = static_cast<double>(now - last_) * rate();
    for (Job& j : jobs_) {
      work_done_us_ += std::clamp(j.remaining_us, 0.0, given);  // not the rounding's overshoot
      j.remaining_us -= given;
    }
  }
  last_ = now;
}

// One completion event, at the first whole microsecond by which the job
// with the least work left is done; earlier events are superseded.
void Cpu::schedule_next() {
  const uint64_t gen = ++gen_;
  if (jobs_.empty()) return;
  double least = jobs_.front().remaining_us;
  for (const Job& j : jobs_) least = std::min(least, j.remaining_us);
  const int64_t dt = least <= kDoneUs ? 0 : static_cast<int64_t>(std::ceil(least / rate() - 1e-9));
  q_.at(q_.now() + dt, [this, gen] {
    if (gen == gen_) complete();
  });
}

void Cpu::complete() {
  advance();
  std::vector<std::function<void()>> finished;
  auto it = jobs_.begin();
  while (it != jobs_.end()) {
    if (it->remaining_us <= kDoneUs) {
      finished.push_back(std::move(it->done));
      it = jobs_.erase(it);
    } else {
      ++it;
    }
  }
  schedule_next();
  for (auto& f : finished) f();
}

}  // namespace evade::closedloop
