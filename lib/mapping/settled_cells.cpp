#include "mapping/settled_cells.h"

#include <cmath>
#include <iterator>

namespace evade::mapping {
namespace {

// Lattice indices beyond this (over 100 000 km at 0.1 m) do not fit a key.
constexpr double kMaxLattice = 1 << 30;

// The lattice index of coordinate v at resolution res; false when it is
// not finite or out of the keys' range.
bool lattice(double v, double res, int64_t* out) {
  const double q = std::round(v / res);
  if (!std::isfinite(q) || std::fabs(q) > kMaxLattice) return false;
  *out = static_cast<int64_t>(q);
  return true;
}

// Both indices in one key, 32 bits each (two's complement).
int64_t key(int64_t ix, int64_t iy) {
  const uint64_t k = (static_cast<uint64_t>(ix) << 32) ^ (static_cast<uint64_t>(iy) & 0xffffffffULL);
  return static_cast<int64_t>(k);
}

}  // namespace

void SettledCells::update(const ElevationLayers& l, int64_t utime, double settle_s, double gap_s,
                          std::vector<uint8_t>* settled) {
  if (utime < last_utime_ || l.resolution != resolution_) runs_.clear();
  last_utime_ = utime;
  resolution_ = l.resolution;
  const int64_t gap_us = std::llround(gap_s * 1e6), settle_us = std::llround(settle_s * 1e6);
  settled->assign(l.obstacle.size(), 0);
  int64_t ox = 0, oy = 0;
  if (!(l.resolution > 0) || !lattice(l.origin_x, l.resolution, &ox) || !lattice(l.origin_y, l.resolution, &oy) ||
      l.width > kMaxLattice || l.height > kMaxLattice) {
    runs_.clear();  // no lattice to remember cells by: nothing settles
    return;
  }
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
