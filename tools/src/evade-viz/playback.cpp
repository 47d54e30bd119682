#include "playback.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace evade::viz {

bool Controls::on_key(const std::string& k, double seek_step_s) {
  static const std::string layer_keys = "zmtynbiv";
  if (k.size() == 1 && layer_keys.find(k[0]) != std::string::npos) {
    const size_t l = layer_keys.find(k[0]);
    layers[l] = !layers[l];
  } else if (k == "k") {
    follow = !follow;
  } else if (k == "space") {
    paused = !paused;
  } else if (k == "period") {
    paused = true;
    ++steps;
  } else if (k == "bracketleft") {
    speed = std::max(1.0 / 16, speed / 2);
  } else if (k == "bracketright") {
    speed = std::min(16.0, speed * 2);
  } else if (k == "Left") {
    seek_by_s -= seek_step_s;
  } else if (k == "Right") {
    seek_by_s += seek_step_s;
  } else if (k == "Home") {
    seek_to_start = true;
    seek_by_s = 0.0;
  } else {
    return false;
  }
  return true;
}

std::string Controls::status(double position_s, double duration_s) const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "t %.1f / %.1f s  x%g  %s  camera %s  (keys: space . [ ] Left Right Home k)",
                position_s, duration_s, speed, paused ? "paused" : "playing", follow ? "follows" : "free");
  return buf;
}

LogTimeline::LogTimeline(std::vector<bus::LogEvent> events) : events_(std::move(events)) {
  std::stable_sort(events_.begin(), events_.end(),
                   [](const bus::LogEvent& a, const bus::LogEvent& b) { return a.timestamp < b.timestamp; });
  if (!events_.empty()) {
    start_utime_ = events_.front().timestamp;
    duration_s_ = double(events_.back().timestamp - start_utime_) * 1e-6;
  }
}

void LogTimeline::seek(WorldState* w, double t_s) {
  position_s_ = std::clamp(t_s, 0.0, duration_s_);
  const int64_t until = start_utime_ + std::llround(position_s_ * 1e6);
  w->reset();
  std::map<std::string, size_t> newest;
  size_t scans[2] = {events_.size(), events_.size()};  // the last two LIDAR_SCANs
  size_t i = 0;
  for (; i < events_.size() && events_[i].timestamp <= until; ++i) {
    const auto& e = events_[i];
    if (e.channel == "ODOMETRY") {
      w->apply(e.channel, e.data.data(), e.data.size(), e.timestamp);
    } else if (e.channel == "LIDAR_SCAN") {
      scans[0] = scans[1];
      scans[1] = i;
    } else {
      newest[e.channel] = i;
    }
  }
  next_ = i;
  std::vector<size_t> replay;
  for (const auto& [ch, idx] : newest) replay.push_back(idx);
  for (size_t s : scans)
    if (s < events_.size()) replay.push_back(s);
  std::sort(replay.begin(), replay.end());
  for (size_t idx : replay) {
    const auto& e = events_[idx];
    w->apply(e.channel, e.data.data(), e.data.size(), e.timestamp);
  }
}

void LogTimeline::advance(WorldState* w, double dt_s) {
  position_s_ = std::clamp(position_s_ + dt_s, 0.0, duration_s_);
  const int64_t until = start_utime_ + std::llround(position_s_ * 1e6);
  for (; next_ < events_.size() && events_[next_].timestamp <= until; ++next_) {
    const auto& e = events_[next_];
    w->apply(e.channel, e.data.data(), e.data.size(), e.timestamp);
  }
}

}  // namespace evade::viz
