// Private: pairs of dynamic bodies made overlapping are parted by moving them, a little each step
// (separation.cpp says why).
#pragma once

#include "world/world_impl.h"

namespace rattle::detail {

/// At an exact step's start, after refreshSqueezes: moves the two bodies of each exempt pair of dynamic
/// fixtures that still overlap apart along the line of their centres, by at most kSeparationShare of
/// the larger radius a step (shared among a body's overlapping partners), in inverse proportion to
/// their masses so that their centre of mass stays where it is, and never into or through a static
/// fixture. Bodies asleep, sliding, or holding up sleepers are left where they are.
void separateExemptPairs(WorldState& w);

}  // namespace rattle::detail
