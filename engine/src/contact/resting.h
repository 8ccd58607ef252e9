// Private: resting under gravity, sleeping, sliding and waking (resting.cpp says how).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "world/world_impl.h"

namespace rattle::detail {

/// Puts the body to sleep where it is (velocity and acceleration zero), held up by `supporters`, which
/// wake it when they wake (WorldState::dependents).
void putToSleep(WorldState& w, uint32_t body, std::span<const uint32_t> supporters);
/// The predictive mode's guard against a Zeno sequence: counts a collision of `body` in this step.
/// `contactNormal` (toward the body) and `holder` are the contact at hand's, as for supportsAt.
void sleepIfZeno(WorldState& w, uint32_t body, double now, Vec2 contactNormal = {}, uint32_t holder = 0);
/// Wakes the body and everything resting on it (through `dependents`), appending them to `woken`.
void wakeUp(WorldState& w, uint32_t body, double now, std::vector<uint32_t>& woken);
/// wakeUp in two halves, for a call that must make room before it changes anything: the first finds
/// whom to wake (appending to `woken`, passing over those it already holds) and changes nothing; the
/// second wakes woken[from, end) and does not allocate between steps.
void collectWake(const WorldState& w, uint32_t body, std::vector<uint32_t>& woken);
/// (wakeUp's second half.)
void applyWake(WorldState& w, const std::vector<uint32_t>& woken, size_t from, double now);
/// The body slides on the flat feature `feature` of `fixture`: its velocity and gravity lose their
/// parts along `normal`, and the feature is its support until it slides off the end.
void startSliding(WorldState& w, uint32_t body, uint32_t fixture, int feature, Vec2 normal);
/// The body no longer slides: it falls with the whole of gravity again (unless asleep).
void stopSliding(WorldState& w, detail::BodySlot& b);
/// A point (its fixture `fixture`) that still slides after its velocity changed keeps to its face: the
/// velocity loses its part across the face (resting.cpp says why).
void keepSlidingPointOnFace(WorldState& w, detail::BodySlot& b, uint32_t fixture);
/// Whether the face the body remembers (Support) is set and its fixture is still the one it named.
bool remembersLiveFace(const WorldState& w, const detail::BodySlot& b);
/// Whether a point lies on the face it remembers (Support), within the round-off the time of impact allows.
bool pointOnRememberedFace(const WorldState& w, const detail::BodySlot& b, double now);
/// How far a point is from the line of the face it remembers, on the side it remembers (negative
/// beyond it, to round-off); NaN when it remembers no live flat face.
double distanceFromRememberedFace(const WorldState& w, const detail::BodySlot& b, double now);
/// A point meeting a static face at `c`: where the time of impact took it as met at the face's end from
/// beyond it (a joint's reach, time_of_impact.cpp), it moves to that end, the contact's point.
void placePointOnFace(WorldState& w, detail::BodySlot& b, const detail::PredictedContact& c);
/// Puts a body to sleep held by awake bodies at rest (squeeze.cpp: a point caught between a stepped
/// body and a face, or in the pinch of two bodies; response.cpp: a disk in an arch of two with a slow
/// awake disk, leansOnSlowNeighbour), and lists it in WorldState::sleepersOnAwakeBodies with each of
/// them.
void sleepOnAwakeBodies(WorldState& w, uint32_t body, std::span<const uint32_t> supporters);
/// At a step's start: wakes the sleepers of WorldState::sleepersOnAwakeBodies whose supporter moves,
/// and forgets those whose supporter has gone to sleep (its wake wakes them) or that are awake.
void wakeSleepersOfMovingBodies(WorldState& w);
/// Lists every sleeper held by an awake body (what sleepOnAwakeBodies listed), in order: a loaded world's.
void findSleepersOnAwakeBodies(WorldState& w);
/// The side of face `feature` of the static or kinematic `fixture` that a point lying on it is on, when
/// the point knows it: the face it remembers (Support), or another face in a corner with that one, where
/// the point lies on both (resting.cpp says how). A kinematic body's faces are taken where it is at
/// `now`. `side` is that face's unit normal toward the point.
bool pointKnowsSideOfFace(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, int feature, double now,
                          Vec2& side);
/// The outward unit normals of the faces of the polygon `fixture` that a point lies on, within the
/// round-off the time of impact allows (two at its corner): outside a solid polygon, a point's side of
/// its face needs no memory. Returns how many (0 to 2); 0 when the fixture is not a polygon.
int polygonFacesUnderPoint(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, double now,
                           Vec2 (&outward)[2]);
/// The unit normals of the faces of the Segment or Polyline `fixture` that a point lies on, within the
/// round-off the time of impact allows (two at a joint), each on the side facing against `against`: a
/// point on a line has no side of its own, and one that a body's contact (normal `against`, toward the
/// point) drives into the line lies on the side that stops it. Returns how many (0 to 2); 0 for other
/// geometries.
int lineFacesUnderPoint(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, double now, Vec2 against,
                        Vec2 (&normal)[2]);
/// Whether `feature` of the fixture is a straight face (a segment, a polyline's or a polygon's edge).
bool isFlatFeature(const WorldState& w, uint32_t fixture, int feature);
/// A point at the end of the face it slides on, resolved against `feature` of `fixture` there: whether
/// it moves away from that face (true) or could turn back into it. At a polygon's corner it also leaves
/// the face when it moves out through the other face there faster than into this one.
bool leavesCorner(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, int feature, double now);
/// The feature of `fixture` a point on its remembered face is leaving: that face, or kEveryFeature when it
/// sits in a corner of several faces and leaves them all (resting.cpp says why). For a fixture other than
/// the remembered face's, kEveryFeature when it sits on faces of it and leaves them all, else kNoFeature.
/// `leavesRemembered` false: the point moves across its remembered face, which it does not leave; the
/// answer is then the other faces of the fixture it leaves, as for another fixture.
int featureLeftByPoint(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, double now,
                       bool leavesRemembered = true);
/// Whether the static and sleeping bodies the body touches at `now` hold it up against gravity (up lies
/// within the cone of their normals); they are put in `supporters`. `contactNormal` (toward the body) is
/// that of the contact being resolved with `holder`; a point (radius 0), which has no extent to give
/// the direction from what it touches, is held by it and by the face it slides on when they are static.
bool supportsAt(const WorldState& w, uint32_t body, double now, std::vector<uint32_t>& supporters,
                Vec2 contactNormal = {}, uint32_t holder = 0);
/// Whether the body, a disk that the static and sleeping bodies it touches do not hold up alone, is held
/// together with a slow awake disk that touches it and that they, with this body, hold up in turn: an
/// arch of two. Its supporters (sleeping ones and that disk) are put in `supporters`.
bool leansOnSlowNeighbour(const WorldState& w, uint32_t body, double now, std::vector<uint32_t>& supporters);
/// A point that moves into a static face (`vn` < 0, its normal velocity at contact `c`) no faster than
/// the contact's rest tolerance, a contact dismissed as at rest, stops there; true when it did (its
/// velocity changed at c.time).
bool stopPointAtRest(WorldState& w, const detail::PredictedContact& c, double vn);
/// When the sliding body leaves the end of its face, if it does before dt.
std::optional<double> slideEndTime(const WorldState& w, const detail::BodySlot& b, double now, double dt);

}  // namespace rattle::detail
