// The scenario generator's random numbers: std::mt19937_64 (its output
// sequence is fixed by the C++ standard) seeded with the scenario seed, and
// transforms written here rather than std::uniform_*_distribution, whose
// output the standard leaves to each library. So a family and seed give
// the same draws on every platform.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "sim/scenario_gen_params.h"

namespace evade::sim::gen {

class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}

  // [0, 1): the top 53 bits of one engine output.
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  // [lo, hi) (lo when lo == hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  double uniform(const Range& r) { return uniform(r.lo, r.hi); }
  // An integer in [lo, hi], both included.
  int integer(int lo, int hi) {
    int v = lo + static_cast<int>(std::floor(unit() * (static_cast<double>(hi) - lo + 1.0)));
    return v > hi ? hi : v;
  }
  int integer(const Count& c) { return integer(c.lo, c.hi); }
  // True with probability p.
  bool chance(double p) { return unit() < p; }
  // +1 or -1, even odds.
  int sign() { return chance(0.5) ? 1 : -1; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace evade::sim::gen
