// The round-off tolerances every mode's contact handling shares: below them an approach is round-off of
// the arithmetic that found it, not a collision. Named once so that the modes cannot drift apart.
#pragma once

#include <limits>

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

}  // namespace rattle::detail
