// Private: squeezes (squeeze.cpp says what they are). Their state, the exempt pairs and the wedged
// bodies, is plain data in WorldState, which both exact modes read.
#pragma once

#include <algorithm>
#include <cstdint>

#include "collision/closest_point.h"
#include "world/world_impl.h"

namespace rattle::detail {

/// Two dynamic bodies that overlap by more than this fraction of the larger radius when they meet were
/// made overlapping (a fixture created, a body set, over the other): events leave a pair touching, and
/// the solves of islands and jams leave at most Islands::kJamResidual (0.01) of a radius, well below it.
inline constexpr double kMadeOverlapping = 0.05;
/// Whether two circle-like fixtures overlap that deeply.
inline bool madeOverlapping(const CircleOverlap& o) { return o.depth > kMadeOverlapping * std::max(o.ra, o.rb); }

/// A contact of two dynamic bodies made overlapping (deeper than kMadeOverlapping of the larger radius),
/// or overlapping deeply with one of them stopped against a static face at this instant, the pair the
/// last contact of one of them earlier in this step, or one of them past kSqueezeCollisions collisions
/// in the step: they pass through each other (exempt, as a squeeze's pair, until separateExemptPairs
/// has parted them). Else false.
bool passesThrough(WorldState& w, const detail::PredictedContact& c);
/// A pair of dynamic bodies made overlapping (deeper than kMadeOverlapping of the larger radius at
/// `now`): exempts it and returns true. Exact events would bounce each body of a wave of units spawned
/// at one point off every other in turn, each bounce predicting it against all of them again (a cost
/// cubic in their number: bench/README.md, "Parting pairs made overlapping"); separateExemptPairs parts
/// such a pair by moving it instead.
bool exemptIfMadeOverlapping(WorldState& w, uint32_t fa, uint32_t fb, double now);
/// Exempts the pair of fixtures from collisions until they no longer overlap (refreshSqueezes), and
/// counts a squeeze.
void exemptFromCollisions(WorldState& w, uint32_t fa, uint32_t fb);
/// Without gravity, whether the body's cluster jams after Islands::kJamCollisions rather than the
/// collapse guard's count (jam.cpp, and the predictive mode's hand-over): the game drives it, or it was
/// stopped against a static face this step past kSqueezeCollisions (squeezeAt), caught in a collapse
/// against the wall.
bool jamsAsDriven(const WorldState& w, uint32_t body);
/// Whether the pair of fixtures is exempt from collisions because of a squeeze.
bool squeezeExempt(const WorldState& w, uint32_t fa, uint32_t fb);
/// At a step's start: forgets the squeezes whose pairs no longer overlap (or are gone), and starts the
/// bodies' counts again.
void refreshSqueezes(WorldState& w);
/// Counts the contact's collision for its dynamic body; when it is a squeeze, stops the body along
/// the contact's normal, exempts the pair and returns true (the caller predicts the body again).
bool squeezeAt(WorldState& w, const detail::PredictedContact& c);
/// After a collision of a point with a stepped body (an island's member) and the island's solve after
/// it: a point past kSqueezeCollisions collisions in the step that still moves into the stepped body
/// stops doing so, at the velocity the island left that body (never faster than it was). Caught between
/// that body, at rest or leaving so slowly that it would leave a sleeper there at most
/// Islands::kJamResidual of its radius below by the step's end `dt`, and the face the point remembers (on
/// the face, or in the cusp the body leaves against it), the point takes the velocity nearest its own
/// that meets both contacts, and sleeps there when that is slow and the two hold it up
/// (sleepOnAwakeBodies).
/// Caught so against a face by a stepped body that moves along it too fast to hold it, not closing on it,
/// where the two hold it up, the point is carried: that velocity and no acceleration for the rest of the
/// step (WorldState::carriedPoints), until restoreCarriedPoints.
void stopPointAtSteppedBody(WorldState& w, const detail::PredictedContact& c, double dt);
/// At the step's end `end`, before the last pass: gives the points stopPointAtSteppedBody carried their
/// gravity back, their clocks moved to `end` first, and empties the list.
void restoreCarriedPoints(WorldState& w, double end);

}  // namespace rattle::detail
