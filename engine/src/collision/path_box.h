// Private: the box around a body's path inside a step.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "rattle/geometry.h"

namespace rattle::detail {

// The box around a path p + v h + a h^2/2, h in [0, T]: its ends, and on each axis the turning point
// when it falls inside.
Box curvedPathBox(Vec2 p, Vec2 v, Vec2 a, double T);

inline Box pathBox(Vec2 p, Vec2 v, Vec2 a, double T) {
  if (a.x == 0 && a.y == 0) {
    // A straight line (most paths): its two ends. The same box as curvedPathBox's, but for the sign of
    // a zero coordinate (p + v T + 0 turns -0 into +0), which no comparison of boxes sees.
    const Vec2 end = p + v * T;
    return {{std::min(p.x, end.x), std::min(p.y, end.y)}, {std::max(p.x, end.x), std::max(p.y, end.y)}};
  }
  return curvedPathBox(p, v, a, T);
}

// The box grown by the round-off of its coordinates, for a point's (a circle of radius 0): within that
// round-off a point is on a line (time_of_impact.h), so a point an ulp below a floor, on it by that
// rule, must still pair with it. A disk's box holds such a floor already (it reaches a radius down).
inline Box withRoundOff(const Box& b) {
  const double scale = std::max(std::max(std::fabs(b.min.x), std::fabs(b.max.x)),
                                std::max(std::fabs(b.min.y), std::fabs(b.max.y)));
  const double m = 64 * std::numeric_limits<double>::epsilon() * scale;
  return {{b.min.x - m, b.min.y - m}, {b.max.x + m, b.max.y + m}};
}

}  // namespace rattle::detail
