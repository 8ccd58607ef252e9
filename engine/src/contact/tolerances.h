// The round-off tolerances every mode's contact handling shares: below them an approach is round-off of
// the arithmetic that found it, not a collision. Named once so that the modes cannot drift apart.
#pragma once

#include <cmath>
#include <limits>

#include <rattle/vec2.h>

// kAbsorbRoundOff and kPressRoundOff live beside the geometry's round-off: the times of impact use them too.
#include "collision/closest_point.h"

namespace rattle::detail {

/// Approach speeds below this fraction of the speeds at play (the fastest body's in the world, or the
/// pair's) are round-off: a resolved pair's normal speed is zero only to about 1e-15 of them.
inline constexpr double kApproachRoundOff = 1e-13;
/// A contact that closes no more than this times its coordinates within the whole step is at rest:
/// that decides when everything is nearly still.
inline constexpr double kRestRoundOff = 8 * std::numeric_limits<double>::epsilon();

/// Whether the relative acceleration (a's minus b's) presses the pair together along `normal` (from b
/// toward a) by more than round-off.
inline bool pressedTogether(Vec2 relativeAcceleration, Vec2 normal) {
  // (The square root only when it can matter: every event pop asks, and without gravity the answer is no.)
  const double along = dot(relativeAcceleration, normal);
  return along < 0 && along < -kPressRoundOff * length(relativeAcceleration);
}

}  // namespace rattle::detail
