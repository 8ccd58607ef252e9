// Private: the collision response every mode's events share (response.cpp says what it covers).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "collision/closest_point.h"
#include "rattle/time_of_impact.h"
#include "world/world_impl.h"

namespace rattle::detail {

/// Resolves the contact at c.time: Newton's law with the pair's restitution (or e = 1 in a collapse,
/// the TC model), the round-off clean-up, then resting (sleep, slide or a bounce at restingSpeed);
/// bodies it wakes are appended to `woken`; `zenoGuard`: the predictive mode's (sleepIfZeno). The
/// ContactEvent is the caller's. stepEnd: where the hybrid step's stepped bodies end their straight paths (time since the step's
/// start); negative where no body is stepped (the predictive mode).
void resolve(WorldState& w, const detail::PredictedContact& c, std::vector<uint32_t>& woken, bool zenoGuard = false,
             double stepEnd = -1);
/// Takes out an approach `vn` (< 0) too small to be a collision, inelastically, at c.time; false when
/// neither body can take an impulse (nothing changed).
bool absorb(WorldState& w, const detail::PredictedContact& c, double vn);
/// A point's side of a feature of what cannot move (Support), kept at each contact with it.
void rememberFace(WorldState& w, const detail::PredictedContact& c);
/// The feature of `other` that `own` cannot be approaching now (TimeOfImpact's resolvedFeature): the
/// face it slides on, the one the pair was last resolved on at this instant, or a point's remembered
/// face it moves away from.
int resolvedFeature(const WorldState& w, const detail::BodySlot& a, const detail::BodySlot& b, uint32_t own,
                    uint32_t other, double now);
/// predictImpact's rare part: `impact`, met at once, dropped when it is a point's contact with a face
/// read from the wrong side (response.cpp says when), and the fixture's other faces asked instead.
/// "At once" is before the point has moved beyond the round-off of its position. predictImpact asks
/// only about impacts sooner than kMisreadWindow, a cheap gate wide enough that the test decides. At
/// 1e-6 s it was not: a point resolved against a moving box's wall 1,000 units out, pulled off the wall
/// by a twentieth of gravity, drifted 6e-13 (a tenth of its round-off) in the 1.1e-6 s before it met the
/// wall's outer face, and left the box.
inline constexpr double kMisreadWindow = 1e-3;
void dropMisreadFace(const WorldState& w, const detail::BodySlot& a, uint32_t own, uint32_t other, double now,
                     double maxTime, int resolved, std::optional<Impact>& impact);

/// fixtureTimeOfImpact's rare part: a point against a Segment, whose neighbours the world may know.
std::optional<Impact> pointSegmentTimeOfImpact(const WorldState& w, uint32_t own, Vec2 positionOwn, uint32_t other,
                                               Vec2 positionOther, const Motion& relativeMotion, double maxTime,
                                               int resolved);
/// timeOfImpact of fixture `own` at `positionOwn` with fixture `other` at `positionOther`, with what the
/// world knows of `other` beyond its geometry: for a point, the neighbours of a Segment
/// (WorldState::segmentNeighbours). Small enough to inline into predictImpact's callers, the rare part
/// out of line: inlined whole, the compiler stopped inlining predictImpact into the hybrid step.
[[gnu::always_inline]] inline std::optional<Impact> fixtureTimeOfImpact(const WorldState& w, uint32_t own,
                                                                        Vec2 positionOwn, uint32_t other,
                                                                        Vec2 positionOther,
                                                                        const Motion& relativeMotion,
                                                                        double maxTime, int resolved) {
  const Geometry& ga = w.fixtures[own].geometry;
  const Geometry& gb = w.fixtures[other].geometry;
  if (std::holds_alternative<Segment>(gb) && isPoint(ga)) [[unlikely]] {
    return pointSegmentTimeOfImpact(w, own, positionOwn, other, positionOther, relativeMotion, maxTime, resolved);
  }
  return timeOfImpact(ga, positionOwn, gb, positionOther, relativeMotion, maxTime, resolved);
}

/// The first contact of fixture `own` (of body a) with `other` (of body b) from `now` to now + maxTime, along
/// their paths, `resolved` left out (resolvedFeature): the time of impact, less a point's contact with
/// a face read from the wrong side (dropMisreadFace). Inline, and one object returned on every path: the
/// caller reads the flag byte the time of impact wrote, with no copy between (a copied optional is read
/// back as a wider word just after it was written, a stalled load that cost the bench's bullets 7%).
[[gnu::always_inline]] inline std::optional<Impact> predictImpact(const WorldState& w, const detail::BodySlot& a,
                                                                  const detail::BodySlot& b, uint32_t own,
                                                                  uint32_t other, double now, double maxTime,
                                                                  int resolved) {
  const Motion relative{w.velocityAt(a, now) - w.velocityAt(b, now), a.acceleration - b.acceleration};
  std::optional<Impact> impact =
      fixtureTimeOfImpact(w, own, w.positionAt(a, now), other, w.positionAt(b, now), relative, maxTime, resolved);
  if (impact && impact->time < kMisreadWindow && isPoint(w.fixtures[own].geometry)) [[unlikely]] {
    dropMisreadFace(w, a, own, other, now, maxTime, resolved, impact);
  }
  return impact;
}
/// The ContactEvent of fixtures a and b (either order) at `time`; `normal` points from b toward a.
ContactEvent contactEventOf(const WorldState& w, uint32_t a, uint32_t b, double time, Vec2 point, Vec2 normal,
                            double impulse);

/// The relative normal velocity (a's minus b's along n, which points from b toward a) of their paths at
/// time t: where one of the two is stepped and the other is not, the slower approach of the straight
/// path's and of the parabola's it stands in for, ending at stepEnd (response.cpp says why). stepEnd < 0
/// (no stepped bodies): the straight one. HybridStep::joinsIsland reads this one where the paths close fast.
inline double pathNormalVelocity(const WorldState& w, const BodySlot& a, const BodySlot& b, Vec2 n, double t,
                                 double stepEnd) {
  const double straight = dot(w.velocityAt(a, t) - w.velocityAt(b, t), n);
  if (stepEnd < 0 || a.stepped == b.stepped) return straight;
  const Vec2 g = w.def.gravity * (stepEnd - t);  // what the stepped one has taken ahead of its parabola
  const double parabola = straight + dot(a.stepped ? -g : g, n);
  return std::max(straight, parabola);
}

/// `path`, the paths' reading of bodies ia and ib at time t (pathNormalVelocity), or where the stepped one of
/// the two has been stepped since the step's start, the slower of that and the approach it would have on the
/// parabola it began the step on (response.cpp says why).
inline double slowerOnStartParabola(const WorldState& w, uint32_t ia, uint32_t ib, Vec2 n, double t, double stepEnd,
                                    double path) {
  const BodySlot& a = w.bodies[ia];
  const BodySlot& b = w.bodies[ib];
  if (stepEnd < 0 || a.stepped == b.stepped) return path;
  const uint32_t stepped = a.stepped ? ia : ib;
  if (!w.bodies[stepped].steppedSinceStart) return path;
  const Vec2 onStartParabola = w.stepStartVelocity[stepped] + w.def.gravity * t;
  const double start = a.stepped ? dot(onStartParabola - w.velocityAt(b, t), n)
                                 : dot(w.velocityAt(a, t) - onStartParabola, n);
  return std::max(path, start);
}

/// The relative normal velocity that a contact's impulse is computed from at time t, of bodies ia and ib:
/// the paths' reading, or the start parabola's where that is slower (slowerOnStartParabola).
inline double impactNormalVelocity(const WorldState& w, uint32_t ia, uint32_t ib, Vec2 n, double t, double stepEnd) {
  const double path = pathNormalVelocity(w, w.bodies[ia], w.bodies[ib], n, t, stepEnd);
  return slowerOnStartParabola(w, ia, ib, n, t, stepEnd, path);
}

}  // namespace rattle::detail
