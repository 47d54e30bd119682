// The tracker process core: ELEVATION_MAP -> OBSTACLES.
#pragma once

#include "bus/core.h"
#include "config/config.h"
#include "evade/grid_map_t.hpp"
#include "evade/obstacle_list_t.hpp"
#include "tracking/tracker.h"

namespace evade::tracking {

class TrackerCore : public bus::Core {
 public:
  explicit TrackerCore(const TrackerParams& params);
  static std::unique_ptr<TrackerCore> from_config(const config::Node& root);
  const Tracker& tracker() const { return tracker_; }
  static constexpr double kMaxEpsCells = 20.0;

 private:
  void on_map(const evade::grid_map_t& m);
  Tracker tracker_;
  TrackerStats reported_;
  std::vector<int8_t> obstacle_;
};

}  // namespace evade::tracking
