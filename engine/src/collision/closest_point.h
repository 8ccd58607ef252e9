// Private: the closest point of a placed geometry to a point, for resting contacts and the discrete mode.
#pragma once

#include <limits>
#include <optional>

#include "rattle/geometry.h"

namespace rattle::detail {

struct Closest {
  Vec2 point;
  bool collidable;  // a segment's end is not a corner: it cannot hold anything up
};

inline Closest closestOnSegment(Vec2 a, Vec2 b, Vec2 p, bool endsCollide) {
  const Vec2 d = b - a;
  const double t = dot(p - a, d) / dot(d, d);
  if (t <= 0) return {a, endsCollide};
  if (t >= 1) return {b, endsCollide};
  return {a + d * t, true};
}

// The closest point to q of each convex piece of a polyline (its segments) or a polygon (its edges), in
// the geometry's own frame, in order. Says whether the geometry has such pieces, and whether q is inside
// the polygon (then none is listed).
enum class Pieces { NotPieced, Inside, Listed };
template <class Found>
Pieces forEachConvexPiece(const Geometry& g, Vec2 q, Found&& found) {
  if (const auto* s = std::get_if<Polyline>(&g)) {
    for (size_t i = 0; i + 1 < s->points.size(); ++i) found(closestOnSegment(s->points[i], s->points[i + 1], q, true));
    return Pieces::Listed;
  }
  if (const auto* s = std::get_if<Polygon>(&g)) {
    const size_t n = s->points.size();
    bool inside = true;
    for (size_t i = 0; i < n && inside; ++i) inside = !(cross(s->points[(i + 1) % n] - s->points[i], q - s->points[i]) < 0);
    if (inside) return Pieces::Inside;
    for (size_t i = 0; i < n; ++i) found(closestOnSegment(s->points[i], s->points[(i + 1) % n], q, true));
    return Pieces::Listed;
  }
  return Pieces::NotPieced;
}

// The closest point of a placed geometry to p, or nothing when p is inside it (a polygon or circle).
inline std::optional<Closest> closestPoint(const Geometry& g, Vec2 position, Vec2 p) {
  const Vec2 q = p - position;
  std::optional<Closest> best;
  auto keep = [&](Closest c) {
    if (!best || lengthSquared(q - c.point) < lengthSquared(q - best->point)) best = c;
  };
  if (const auto* s = std::get_if<Point>(&g)) {
    keep({s->position, true});
  } else if (const auto* s = std::get_if<Circle>(&g)) {
    const Vec2 r = q - s->center;
    const double len = length(r);
    if (len <= s->radius) return std::nullopt;
    keep({s->center + r * (s->radius / len), true});
  } else if (const auto* s = std::get_if<Segment>(&g)) {
    keep(closestOnSegment(s->a, s->b, q, false));
  } else if (forEachConvexPiece(g, q, keep) == Pieces::Inside) {
    return std::nullopt;
  }
  if (best) best->point += position;
  return best;
}

// The closest point of each convex piece of a placed geometry to p (forEachConvexPiece), and for the
// other geometries closestPoint's one. A disk resting in a corner of one Polyline touches its floor and
// its wall at once, where closestPoint sees only one of them.
template <class Found>
void forEachClosestPoint(const Geometry& g, Vec2 position, Vec2 p, Found&& found) {
  const Pieces pieces = forEachConvexPiece(g, p - position, [&](Closest c) {
    c.point += position;
    found(c);
  });
  if (pieces != Pieces::NotPieced) return;
  if (const auto c = closestPoint(g, position, p)) found(*c);
}

/// The centre and radius of a circle-like geometry (a point is a circle of radius 0).
inline Vec2 circleCentre(const Geometry& g) {
  if (const auto* c = std::get_if<Circle>(&g)) return c->center;
  return std::get<Point>(g).position;
}
inline double circleRadius(const Geometry& g) {
  if (const auto* c = std::get_if<Circle>(&g)) return c->radius;
  return 0;
}
/// Two circle-like geometries of bodies at `pa` and `pb`: their centres and radii, and how deep they
/// overlap (negative: the gap between them).
struct CircleOverlap {
  Vec2 ca, cb;
  double ra, rb;
  double depth;
};
inline CircleOverlap circleOverlap(const Geometry& ga, Vec2 pa, const Geometry& gb, Vec2 pb) {
  const Vec2 ca = pa + circleCentre(ga), cb = pb + circleCentre(gb);
  const double ra = circleRadius(ga), rb = circleRadius(gb);
  return {ca, cb, ra, rb, ra + rb - length(ca - cb)};
}
/// A Point or a circle of radius 0: no extent, so no overlap to tell its side of a line it lies on.
inline bool isPoint(const Geometry& g) {
  if (const auto* c = std::get_if<Circle>(&g)) return c->radius == 0;
  return std::holds_alternative<Point>(g);
}
/// A few ulps, relative: what round-off puts in a quantity worked out from numbers of a given size.
inline constexpr double kRoundOffUlps = 16 * std::numeric_limits<double>::epsilon();

/// At an event's pop, an approach slower than this times the pair's speeds (the round-off of their
/// difference) is taken as round-off and dismissed; a faster one that is no collision is absorbed.
inline constexpr double kAbsorbRoundOff = kRoundOffUlps;

/// A relative acceleration presses a pair together along its contact normal only beyond this fraction
/// of itself. A normal worked out from two centres is off by the round-off of their coordinates over
/// their distance (1e-14 for disks of radius 0.1 at 10 units from the origin): two disks side by side on
/// a floor, one of them sliding and the other still falling by an ulp, read as pressed together by
/// 1e-13 of g, and the pair was resolved at one instant without end, the resolve changing nothing
/// (fuzz/regressions/world_api/budget-predictive-row-pressed-by-round-off).
inline constexpr double kPressRoundOff = 1e-9;

/// What round-off can put in a distance computed from these coordinates: a few ulps of each. A point
/// (isPoint) this near a line is on it, for its times of impact, its slide's ends and its corners alike.
inline double pointRoundOff(Vec2 a, Vec2 b, Vec2 c = {}) {
  return kRoundOffUlps * (length(a) + length(b) + length(c));
}

/// What round-off can put in a position reached at `speed` by a time read from a clock at `clock`: a
/// few ulps of the clock, travelled at that speed. Beyond pointRoundOff for fast bodies or late times.
inline double timeRoundOff(double clock, double speed) { return kRoundOffUlps * clock * speed; }

}  // namespace rattle::detail
