// Private: the box around a body's path inside a step.
#pragma once

#include <algorithm>

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

}  // namespace rattle::detail
