// Private: the time of impact of two plain disks (circles on their bodies' centres, moving in straight
// lines), split in two for the predictive mode's search over a body's neighbours: the time of each pair,
// and the contact point and normal only for the pair that wins (a square root and a division fewer per
// impact found and then beaten by an earlier one).
//
// The arithmetic is timeOfImpactCircleCircle's (time_of_impact.cpp: timeToReach's straight case, then
// pointImpact), expression for expression with the zero acceleration and the zero centre of B written
// in, so the bits are the same; tests/test_predictive_plain.cpp compares the two on random pairs. The
// method is that of Bannerman et al. (Comput. Part. Mech. 1, 191, 2014; /work/shared/NUMERICS.md): an
// overlap by round-off collides now only while approaching, and the root is taken in the form without
// cancellation, t = c / (-b + sqrt(b^2 - A c)).
#pragma once

#include <cmath>

#include "rattle/vec2.h"

namespace rattle::detail {

// b^2 - a c with the error of the product a c compensated (as time_of_impact.cpp's discriminant()).
inline double plainDiscriminant(double b, double a, double c) {
  const double w = a * c;
  const double e = std::fma(-a, c, w);
  const double f = std::fma(b, b, -w);
  return f + e;
}

// The first time in [0, maxTime] at which disks whose centres are `r` apart (A's minus B's), closing at
// relative velocity `v`, come within `reach` (the sum of the radii) while approaching; false for none.
// `c` = |r|^2 - reach^2 and `b` = r.v, which the caller has already worked out for its early rejections.
// `justResolved`: the pair was resolved at this very instant (the LastContact guard), so a touching pair
// is separating and has no event now.
inline bool plainTimeToReach(double c, double b, Vec2 v, double reach, double maxTime, bool justResolved, double& t) {
  if (c <= 0) {
    if (b < 0 && !justResolved) {
      t = 0.0;
      return true;
    }
    return false;
  }
  if (b >= 0) return false;
  const double A = dot(v, v);
  const double disc = plainDiscriminant(b, A, c);
  // A tangent touch, or a pass whose deepest overlap is round-off, is not an event (timeToReach).
  if (!(disc > 1e-12 * A * reach * reach)) return false;
  t = c / (-b + std::sqrt(disc));
  return t <= maxTime;
}

// The contact at time `t` of the impact found from `r`, `v` as above: the point on B's surface and the
// unit normal from B toward A, in B's frame at the search's start (pointImpact with B's centre at 0).
inline void plainContact(Vec2 r, Vec2 v, double radiusB, double t, Vec2& point, Vec2& normal) {
  const Vec2 travel = v * t + Vec2{} * (0.5 * t * t);
  const Vec2 d = r + travel - Vec2{};
  const double len = length(d);
  normal = len > 0 ? d * (1.0 / len) : (length(v) > 0 ? -v * (1.0 / length(v)) : Vec2{1, 0});
  point = Vec2{} + normal * radiusB;
}

}  // namespace rattle::detail
