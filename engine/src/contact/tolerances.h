// The round-off tolerances every mode's contact handling shares: below them an approach is round-off of
// the arithmetic that found it, not a collision. Named once so that the modes cannot drift apart.
#pragma once

#include <cmath>
#include <limits>

#include <rattle/vec2.h>

namespace rattle::detail {

/// Approach speeds below this fraction of the speeds at play (the fastest body's in the world, or the
/// pair's) are round-off: a resolved pair's normal speed is zero only to about 1e-15 of them.
inline constexpr double kApproachRoundOff = 1e-13;
/// At an event's pop, an approach slower than this times the pair's speeds (the round-off of their
/// difference) is taken as round-off and dismissed; a faster one that is no collision is absorbed.
inline constexpr double kAbsorbRoundOff = 16 * std::numeric_limits<double>::epsilon();
/// A contact that closes no more than this times its coordinates within the whole step is at rest:
/// that decides when everything is nearly still.
inline constexpr double kRestRoundOff = 8 * std::numeric_limits<double>::epsilon();

/// A relative acceleration presses a pair together along its contact normal only beyond this fraction
/// of itself. A normal worked out from two centres is off by the round-off of their coordinates over
/// their distance (1e-14 for disks of radius 0.1 at 10 units from the origin): two disks side by side on
/// a floor, one of them sliding and the other still falling by an ulp, read as pressed together by
/// 1e-13 of g, and the pair was resolved at one instant without end, the resolve changing nothing
/// (fuzz/regressions/world_api/budget-predictive-row-pressed-by-round-off).
inline constexpr double kPressRoundOff = 1e-9;

/// Whether the relative acceleration (a's minus b's) presses the pair together along `normal` (from b
/// toward a) by more than round-off.
inline bool pressedTogether(Vec2 relativeAcceleration, Vec2 normal) {
  // (The square root only when it can matter: every event pop asks, and without gravity the answer is no.)
  const double along = dot(relativeAcceleration, normal);
  return along < 0 && along < -kPressRoundOff * length(relativeAcceleration);
}

}  // namespace rattle::detail
