#include "collision/path_box.h"

namespace rattle::detail {

Box curvedPathBox(Vec2 p, Vec2 v, Vec2 a, double T) {
  auto at = [&](double h) { return p + v * h + a * (0.5 * h * h); };
  const Vec2 end = at(T);
  Box box{{std::min(p.x, end.x), std::min(p.y, end.y)}, {std::max(p.x, end.x), std::max(p.y, end.y)}};
  // One axis at a time: the turning point h = -v/a, when it falls inside (0, T).
  auto turn = [&](double vAxis, double aAxis, double& lo, double& hi, double Vec2::*axis) {
    if (aAxis == 0) return;
    const double h = -vAxis / aAxis;
    if (!(h > 0 && h < T)) return;
    const double x = at(h).*axis;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  };
  turn(v.x, a.x, box.min.x, box.max.x, &Vec2::x);
  turn(v.y, a.y, box.min.y, box.max.y, &Vec2::y);
  return box;
}

}  // namespace rattle::detail
