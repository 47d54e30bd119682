#include "mapping/settled_cells.h"

#include <cmath>
#include <iterator>

namespace evade::mapping {
namespace {

int64_t key(int64_t ix, int64_t iy) { return (ix << 32) ^ (iy & 0xffffffffLL); }

}  // namespace

void SettledCells::update(const ElevationLayers& l, int64_t utime, double settle_s, double gap_s,
                          std::vector<uint8_t>* settled) {
  if (utime < last_utime_ || l.resolution != resolution_) runs_.clear();
  last_utime_ = utime;
  resolution_ = l.resolution;
  const int64_t gap_us = std::llround(gap_s * 1e6), settle_us = std::llround(settle_s * 1e6);
  settled->assign(l.obstacle.size(), 0);
  if (l.resolution <= 0) return;
  const int64_t ox = std::llround(l.origin_x / l.resolution), oy = std::llround(l.origin_y / l.resolution);
  for (int r = 0; r < l.height; ++r)
    for (int c = 0; c < l.width; ++c) {
      const size_t i = l.index(r, c);
      if (l.obstacle[i] != 1) continue;
      const auto [it, fresh] = runs_.try_emplace(key(ox + c, oy + r));
      Run& run = it->second;
      if (fresh || utime - run.last > gap_us) run.first = utime;
      run.last = utime;
      (*settled)[i] = utime - run.first >= settle_us;
    }
  for (auto it = runs_.begin(); it != runs_.end();)
    it = utime - it->second.last > gap_us ? runs_.erase(it) : std::next(it);
}

}  // namespace evade::mapping
