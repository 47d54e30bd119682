// Counts the LiDAR returns each solid gives per revolution of the sensor,
// for SIM_TRUTH's `lidar_returns` (what the perception metrics call
// visible). Sensor-model independent: the simulator reports each return
// with the revolution it belongs to (revolutions counted from the sweep's
// start, so the first one is complete when the second begins).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace evade::sim {

class ReturnCounter {
 public:
  // A return from solid `index` during revolution `revolution` (revolutions
  // only increase; a higher one closes the current count).
  void add(int64_t revolution, size_t index);
  // Closes the revolutions before `revolution` (no return in it yet).
  void reach(int64_t revolution);
  // Returns per solid in the last complete revolution, `solids` entries
  // (0 for a solid that gave none); -1 for every solid before the first
  // revolution is complete.
  std::vector<int32_t> last_complete(size_t solids) const;

 private:
  int64_t current_ = 0;
  bool any_complete_ = false;
  std::vector<int32_t> counting_, complete_;
};

}  // namespace evade::sim
