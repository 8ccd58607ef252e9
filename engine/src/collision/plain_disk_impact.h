// Private: the time of impact of two plain disks (circles on their bodies' centres, moving in straight
// lines), split in two for the predictive mode's search over a body's neighbours: the time of each pair,
// and the contact point and normal only for the pair that wins (a square root and a division fewer per
// impact found and then beaten by an earlier one).
//
// The arithmetic is timeOfImpactCircleCircle's (time_of_impact.cpp: timeToReach's straight case, then
// pointImpact), expression for expression with the zero acceleration and the zero centre of B written
// in, so the bits are the same; tests/test_predictive_plain.cpp compares the two on random pairs. The
// method is that of Bannerman et al. (Comput. Part. Mech. 1, 191, 2014; docs/numerics.md): an
// overlap by round-off collides now only while approaching, and the root is taken in the form without
// cancellation, t = c / (-b + sqrt(b^2 - A c)).
#pragma once

#include <cmath>

#include "rattle/vec2.h"

namespace rattle::detail {

// b^2 - a c as Kahan's compensated 2x2 determinant: with w = a c rounded, e = w - a c is exact (one
// fma), so b^2 - a c = (b^2 - w) + (w - a c) loses nothing to cancellation. Error <= 1.5 ulp for exact
// inputs (Jeannerod, Louvet, Muller, Math. Comp. 82, 2013). std::fma is correctly rounded by IEEE 754,
// so this is the same on every build, with or without hardware FMA. time_of_impact.cpp's timeToReach
// uses it too: one kernel for both.
inline double plainDiscriminant(double b, double a, double c) {
  const double w = a * c;
  const double e = std::fma(-a, c, w);
  const double f = std::fma(b, b, -w);
  return f + e;
}

// b^2 - A c for the pair, where b = r.v, A = v.v and c = |r|^2 - reach^2 (worked out by the caller).
// When reach is tiny against the distance |r|, c has rounded reach^2 away and the tangent test with it
// (two disks of radius 1e-10 a unit apart meet head-on at disc = 4e-20 A, below c's rounding); the
// miss-distance form of Lagrange's identity, b^2 - A c = A reach^2 - (r x v)^2 (Haines et al., Ray
// Tracing Gems ch. 7, 2019; docs/numerics.md), keeps it, with r x v as a compensated product.
// Below 2^-20 |r|^2 only, where c's rounding is at most 2^-32 of the discriminant's scale: elsewhere
// the two forms agree to round-off, and the usual one keeps its bits.
inline double reachDiscriminant(Vec2 r, Vec2 v, double b, double A, double c, double reach) {
  if (!(reach * reach < 0x1p-20 * dot(r, r))) return plainDiscriminant(b, A, c);
  const double w = r.y * v.x;
  const double cross = std::fma(r.x, v.y, -w) + std::fma(-r.y, v.x, w);
  return A * (reach * reach) - cross * cross;
}

// The first time in [0, maxTime] at which disks whose centres are `r` apart (A's minus B's), closing at
// relative velocity `v`, come within `reach` (the sum of the radii) while approaching; false for none.
// `c` = |r|^2 - reach^2 and `b` = r.v, which the caller has already worked out for its early rejections.
// `justResolved`: the pair was resolved at this very instant (the LastContact guard), so a touching pair
// is separating and has no event now.
inline bool plainTimeToReach(Vec2 r, double c, double b, Vec2 v, double reach, double maxTime, bool justResolved,
                             double& t) {
  if (c <= 0) {
    if (b < 0 && !justResolved) {
      t = 0.0;
      return true;
    }
    return false;
  }
  // Two points just resolved against each other have parted along one line: round-off may leave them
  // a hair the wrong way round, which is no new meeting.
  if (b >= 0 || (reach == 0 && justResolved)) return false;
  const double A = dot(v, v);
  const double disc = reachDiscriminant(r, v, b, A, c, reach);
  // A tangent touch, or a pass whose deepest overlap is round-off, is not an event (timeToReach); but two
  // points (reach 0) on exactly one line meet head-on at their double root.
  if (!(disc > 1e-12 * A * reach * reach) && !(reach == 0 && disc == 0)) return false;
  t = c / (-b + std::sqrt(disc));
  return t <= maxTime;
}

// The contact at time `t` of the impact found from `r`, `v` as above: the point on B's surface and the
// unit normal from B toward A, in B's frame at the search's start (pointImpact with B's centre at 0).
inline void plainContact(Vec2 r, Vec2 v, double radiusB, double t, Vec2& point, Vec2& normal) {
  const Vec2 travel = v * t + Vec2{} * (0.5 * t * t);
  const Vec2 d = r + travel - Vec2{};
  const double len = length(d);
  // As pointImpact: two points that round-off put a hair past each other meet along the motion.
  const bool backwards = len > 0 && dot(d, v) >= 0 && radiusB == 0 && len <= 0x1p-40 * length(r);
  normal = len > 0 && !backwards ? d * (1.0 / len) : (length(v) > 0 ? -v * (1.0 / length(v)) : Vec2{1, 0});
  point = Vec2{} + normal * radiusB;
}

}  // namespace rattle::detail
