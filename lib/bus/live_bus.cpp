#include "bus/live_bus.h"

#include <poll.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <stdexcept>

namespace evade::bus {
namespace {
constexpr int kMaxDrain = 1000;  // messages handled in one go before timers and fds get a turn
}  // namespace

std::string default_lcm_url() {
  const char* env = std::getenv("LCM_DEFAULT_URL");
  return (env && *env) ? std::string(env) : std::string(kDefaultLcmUrl);
}

namespace {
class SystemClock : public Clock {
 public:
  int64_t wall_us() const override {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
  }
  int64_t monotonic_us() const override {
    return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};
const SystemClock g_system_clock;
struct Anchor {
  const Clock* clock = &g_system_clock;
  bool set = false;
  int64_t wall0 = 0, mono0 = 0;
};
Anchor g_anchor;
}  // namespace

int64_t bus_utime() {
  const int64_t mono = g_anchor.clock->monotonic_us();
  if (!g_anchor.set) {
    g_anchor.wall0 = g_anchor.clock->wall_us();
    g_anchor.mono0 = mono;
    g_anchor.set = true;
  }
  return g_anchor.wall0 + (mono - g_anchor.mono0);
}

void set_clock(const Clock* clock) {
  g_anchor.clock = clock ? clock : &g_system_clock;
  g_anchor.set = false;
}

LiveBus::LiveBus(const std::string& url) : lcm_(std::make_unique<lcm::LCM>(url)) {
  if (!lcm_->good()) throw std::runtime_error("cannot start LCM on " + url);
}

LiveBus::~LiveBus() = default;

void LiveBus::add(Core& core) {
  core.attach(this);
  cores_.push_back(&core);
  for (const auto& ch : core.channels()) {
    // One LCM subscription per channel, shared by every core that reads it.
    bool already = false;
    for (Core* c : cores_)
      if (c != &core)
        for (const auto& other : c->channels()) already |= (other == ch);
    if (!already) lcm_->subscribe(ch, &LiveBus::on_message, this);
  }
}

void LiveBus::conflate(const std::string& channel) { conflated_[channel]; }

void LiveBus::deliver(const std::string& channel, const uint8_t* data, size_t size) {
  int64_t now = bus_utime();
  for (Core* c : cores_) c->deliver(channel, data, size, now);
}

void LiveBus::on_message(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
  const auto* data = static_cast<const uint8_t*>(rbuf->data);
  auto it = conflated_.find(channel);
  if (it != conflated_.end() && draining_) {
    it->second.assign(data, data + rbuf->data_size);  // newer replaces older
    return;
  }
  deliver(channel, data, rbuf->data_size);
}

void LiveBus::publish(const std::string& channel, int64_t, std::vector<uint8_t> data) {
  lcm_->publish(channel, data.data(), static_cast<unsigned int>(data.size()));
}

void LiveBus::add_fd(int fd, std::function<void(int64_t now)> fn) { fds_[fd] = std::move(fn); }

void LiveBus::remove_fd(int fd) { fds_.erase(fd); }

void LiveBus::wake_at(int64_t utime) { wake_at_ = std::min(wake_at_, utime); }

void LiveBus::spin_once(int timeout_ms) {
  int64_t now = bus_utime();
  for (Core* c : cores_) c->advance_to(now);
  int64_t deadline = wake_at_;
  for (Core* c : cores_) deadline = std::min(deadline, c->next_deadline());
  if (deadline != kNever) {
    int64_t wait_ms = (deadline - now + 999) / 1000;
    timeout_ms = static_cast<int>(std::clamp<int64_t>(wait_ms, 0, timeout_ms));
  }
  std::vector<pollfd> pfds;
  pfds.push_back(pollfd{lcm_->getFileno(), POLLIN, 0});
  for (const auto& [fd, fn] : fds_) pfds.push_back(pollfd{fd, POLLIN, 0});
  int r = ::poll(pfds.data(), pfds.size(), timeout_ms);
  now = bus_utime();
  if (wake_at_ <= now) wake_at_ = kNever;
  if (r > 0) {
    // Everything already queued is handled before the timers run, so that
    // a core that fell behind (a long solve) acts on the newest inputs.
    if (pfds[0].revents & POLLIN) {
      draining_ = true;
      lcm_->handle();
      for (int n = 1; n < kMaxDrain && lcm_->handleTimeout(0) > 0; ++n) {
      }
      draining_ = false;
      for (auto& [channel, held] : conflated_) {
        if (held.empty()) continue;
        std::vector<uint8_t> msg;
        msg.swap(held);
        deliver(channel, msg.data(), msg.size());
      }
    }
    for (size_t i = 1; i < pfds.size(); ++i) {
      if (!(pfds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      auto it = fds_.find(pfds[i].fd);  // a handler may have removed it
      if (it != fds_.end()) {
        auto fn = it->second;
        fn(bus_utime());
      }
    }
  }
  now = bus_utime();
  for (Core* c : cores_) c->advance_to(now);
}

void LiveBus::run(const std::atomic<bool>& stop) {
  while (!stop.load()) spin_once(50);
}

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }
}  // namespace

const std::atomic<bool>& stop_on_signals() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  return g_stop;
}

}  // namespace evade::bus
