// Private: pairs of dynamic bodies made overlapping are parted by moving them, a little each step
// (separation.cpp says why).
#pragma once

#include "world/world_impl.h"

namespace rattle::detail {

/// At an exact step's start, after refreshSqueezes: moves the two bodies of each exempt pair of dynamic
/// fixtures that still overlap apart, by at most kSeparationShare of the larger radius a step, in
/// inverse proportion to their masses, and never into or through a static fixture. Without gravity
/// along the line of their centres (the share split among a body's overlapping partners), so that their
/// centre of mass stays where it is; under gravity level, square to gravity (each body's displacement
/// bounded by the share), one body taking all of it when the other may not move, and not a pair with a
/// point in it (the point falls through). Bodies asleep, holding up sleepers, or sliding (but on a level
/// face under gravity) are left where they are; under gravity a sleeper in such a pair whose other body
/// is awake is woken first. Fills WorldState::beingParted with the bodies moved.
void separateExemptPairs(WorldState& w);

}  // namespace rattle::detail
