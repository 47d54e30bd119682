// In-process, deterministic bus: the test double, and the engine behind
// log replay. Cores added to it hear each other (as on LCM, a core also
// hears itself on the channels it subscribes to). Time moves only when the
// caller says so: inject() at a time, or advance_to().
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "bus/core.h"
#include "bus/log.h"

namespace evade::bus {

class MemoryBus : public Sink {
 public:
  void add(Core& core);

  // Fires timers due up to `now`, delivers the message to every subscriber,
  // then delivers whatever that caused, until the bus is quiet.
  void inject(const std::string& channel, const uint8_t* data, size_t size, int64_t now);
  void inject(const std::string& channel, const std::vector<uint8_t>& data, int64_t now) {
    inject(channel, data.data(), data.size(), now);
  }
  template <class Msg>
  void inject(const std::string& channel, const Msg& msg, int64_t now) {
    inject(channel, encode(msg), now);
  }
  // Runs external input into one core (see Core::input), then drains.
  void input(Core& core, int64_t now, const std::function<void()>& fn);
  void advance_to(int64_t now);

  // Everything the cores published, in order, with its bus time.
  const std::vector<LogEvent>& published() const { return published_; }
  std::vector<LogEvent> take_published();
  template <class Msg>
  std::vector<Msg> decoded(const std::string& channel) const {
    std::vector<Msg> out;
    for (const auto& e : published_) {
      if (e.channel != channel) continue;
      Msg m;
      if (decode(e.data.data(), e.data.size(), &m)) out.push_back(m);
    }
    return out;
  }
  void clear() { published_.clear(); }

  void publish(const std::string& channel, int64_t now, std::vector<uint8_t> data) override;

 private:
  void drain();
  std::vector<Core*> cores_;
  std::deque<LogEvent> queue_;
  std::vector<LogEvent> published_;
  int64_t now_ = 0;
};

}  // namespace evade::bus
