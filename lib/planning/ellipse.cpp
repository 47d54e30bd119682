#include "planning/ellipse.h"

#include <cmath>

namespace evade::planning {

bool Ellipse::contains(double px, double py, double grow) const {
  const double c = std::cos(theta), s = std::sin(theta);
  const double dx = px - x, dy = py - y;
  const double u = (dx * c + dy * s) / (a + grow), v = (-dx * s + dy * c) / (b + grow);
  return u * u + v * v <= 1.0;
}

}  // namespace evade::planning
