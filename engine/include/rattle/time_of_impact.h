// rattle: exact times of impact, one function per pair of geometries.
//
// Every function answers: a circle A moves relative to geometry B, which is at rest, along
// c(t) = c + v t + a t^2 / 2; when, in [0, maxTime], does A first touch B while approaching it? Both
// are given in the same frame. With a = 0 (no gravity, or two bodies under the same gravity) the
// circle-circle and circle-point cases are quadratics and the edge cases linear; with a != 0 edges give
// quadratics and circles and corners quartics, whose first root is found without closed forms (monotone
// pieces between the derivative's roots, then a bracketed solver). The answer follows Bannerman et al., "Stable
// algorithm for event detection in event-driven particle dynamics" (Comput. Part. Mech. 1, 191, 2014):
//   - separated now: the first time the gap closes with A approaching; a tangent touch (a double root,
//     e.g. a pass at exactly the sum of radii) is not an impact;
//   - touching or overlapping by round-off and approaching: impact now (time 0);
//   - touching or overlapping and separating (or moving along the surface): no impact.
// A circle of radius 0 (a point) has no overlap to tell which side of a line it is on, so within the
// round-off of its coordinates a point is on the line: it touches it from the side it comes from (or,
// when the contact was just resolved, the side it leaves to), and a polyline's or polygon's edge reaches
// that far past its corners.
// Roots use cancellation-free forms: t = c / (-b + sqrt(b^2 - a c)), with the discriminant as a
// compensated product (Kahan), so contact times stay accurate when the gap is tiny.
#pragma once

#include <optional>

#include "rattle/geometry.h"

namespace rattle {

/// Relative motion: velocity and (constant) acceleration of A relative to B.
struct Motion {
  Vec2 velocity;
  Vec2 acceleration;
  Motion() = default;
  Motion(Vec2 velocity_, Vec2 acceleration_ = {}) : velocity(velocity_), acceleration(acceleration_) {}  // NOLINT
};

/// No feature (see `resolvedFeature` below).
inline constexpr int kNoFeature = -1;
/// Every feature of B (see `resolvedFeature` below).
inline constexpr int kEveryFeature = -2;

/// A predicted first contact.
struct Impact {
  double time = 0.0;  ///< from the start of the motion, in [0, maxTime]
  Vec2 point;         ///< where A touches B, at `time`, on B's surface
  Vec2 normal;        ///< unit; from B toward A: the direction in which A is pushed
  /// Which part of B is touched. Circle, point, segment: 0. Polyline with n points: segment i is i
  /// (0..n-2), corner k is n-1+k (a circle of radius 0 meets an inner corner, 0 < k < n-1, as the segment
  /// beside it, which reaches past the corner by round-off; in a closed Polyline, whose last point is its
  /// first, the two ends too). Polygon with n points: edge i (from point i to i+1) is i, corner k is n+k
  /// (a circle of radius 0 meets every corner as an edge beside it, which reaches past it by round-off).
  int feature = 0;
};

// `resolvedFeature`: a feature of B whose contact with A was resolved at this very instant. It is taken
// to be separating whatever round-off says about the gap and its rate, so it gives no impact at time 0,
// only a later one (a bounce under gravity comes back). The world passes it so that round-off cannot
// make a pair collide again and again at the same instant. kEveryFeature takes every feature so: a body at
// rest in a corner, touching both walls.

std::optional<Impact> timeOfImpactCircleCircle(const Circle& a, const Motion& motion, const Circle& b, double maxTime,
                                               int resolvedFeature = kNoFeature);
std::optional<Impact> timeOfImpactCirclePoint(const Circle& a, const Motion& motion, const Point& b, double maxTime,
                                              int resolvedFeature = kNoFeature);
/// For a circle of radius 0 the face reaches past both ends by the round-off of the segment's coordinates
/// over the sine of the approach, as a Polyline's segment does at an inner corner: another Segment may
/// meet it there.
std::optional<Impact> timeOfImpactCircleSegment(const Circle& a, const Motion& motion, const Segment& b, double maxTime,
                                                int resolvedFeature = kNoFeature);
std::optional<Impact> timeOfImpactCirclePolyline(const Circle& a, const Motion& motion, const Polyline& b,
                                                 double maxTime, int resolvedFeature = kNoFeature);
/// `b` must be wound counter-clockwise (see normalized()). A circle whose centre is already deep
/// inside the polygon (more than its radius behind every edge) gets no impact. A circle that moves along
/// an edge, its normal velocity and acceleration within round-off, meets that edge at no time (so too
/// the faces of a Segment or a Polyline).
std::optional<Impact> timeOfImpactCirclePolygon(const Circle& a, const Motion& motion, const Polygon& b, double maxTime,
                                                int resolvedFeature = kNoFeature);

/// Dispatches to the function for the pair through one table. `a` and `b` are geometries placed at
/// `positionA` and `positionB`; `relativeMotion` is A's velocity and acceleration minus B's. One of the two must be a
/// circle or a point (a point moves as a circle of radius 0); when only B is, the roles are swapped and
/// the result still reads "normal from B toward A", with `feature` naming a part of A. Other pairs
/// (no circle on either side) have no entry and give nothing. The returned point is where the two touch
/// at `time`, in the frame in which B rests at `positionB`.
std::optional<Impact> timeOfImpact(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                   const Motion& relativeMotion, double maxTime, int resolvedFeature = kNoFeature);

}  // namespace rattle

namespace rattle {

/// When, in [0, maxTime], two placed geometries moving relative to each other (A moves with
/// `relativeMotion`, B rests) first change from overlapping to not or back, given whether they overlap
/// now (as closed sets: touching counts). Used for sensors. Every pair of geometry types is answered:
/// the instants where the two can start or stop touching (a distance reaching a radius, a corner crossing
/// an edge's line) are found as roots of polynomials, and the overlap test at the midpoints between them
/// decides which of those instants change anything. A pair with no circle on either side must move on a
/// straight line (kinematic and static bodies do not fall).
std::optional<double> timeOfOverlapChange(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                          const Motion& relativeMotion, double maxTime, bool overlappingNow);

}  // namespace rattle
