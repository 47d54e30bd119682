// Obstacle cells that have stayed put (the occluders of hidden_regions.h
// are built from these only). A cell of the odometry frame's lattice (the
// map is snapped to it, elevation_map.cpp) is settled once it has been an
// obstacle in every map for at least settle_s, a gap of up to gap_s between
// two sightings allowed (the sparse rings and a passer-by's shadow leave
// such gaps). Static structure (a wall, a parked vehicle, a standing group)
// settles; a person walking at speed u covers a cell for about
// (their diameter + a cell) / u, under settle_s when u is at walking pace,
// so a moving crowd casts no region however wide it is.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "mapping/elevation_map.h"

namespace evade::mapping {

class SettledCells {
 public:
  // Takes one map's obstacle layer, stamped utime, and writes per cell of
  // that layer 1 where the cell is settled, else 0. A utime before the last
  // one, or a different resolution, forgets what was seen before; so does a
  // map whose corner is not finite or lies beyond the lattice's range
  // (2^30 cells from the origin), in which nothing is settled.
  void update(const ElevationLayers& layers, int64_t utime, double settle_s, double gap_s,
              std::vector<uint8_t>* settled);
  void clear() { runs_.clear(); }
  size_t size() const { return runs_.size(); }

 private:
  struct Run {
    int64_t first = 0, last = 0;  // us, the first and the latest sighting of this run
  };
  std::unordered_map<int64_t, Run> runs_;  // by lattice cell
  int64_t last_utime_ = 0;
  double resolution_ = 0;
};

}  // namespace evade::mapping
