// rattle: the geometry layer. Shapes, their boxes and areas, and their validation; usable without a world.
//
// Coordinates of a fixture's geometry are relative to its body's position (bodies do not rotate).
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "rattle/vec2.h"

namespace rattle {

/// A single point. Collides like a circle of radius 0.
struct Point {
  Vec2 position;
};

/// A disk: everything within `radius` of `center`. A radius of 0 is allowed (it behaves as a point).
struct Circle {
  Vec2 center;
  double radius = 0.5;
};

/// A line segment from a to b. Only its inside collides: its two ends are not corners, so a disk that
/// meets the segment exactly end-on passes (join segments into a Polyline when the ends must collide).
/// A point crossing its line within round-off of an end (an ulp off, where segments meet end to end in a
/// box) meets its inside. Where exactly two Segments of one body share an end, a point meets their joint
/// as it meets a Polyline's, however acute the corner.
struct Segment {
  Vec2 a;
  Vec2 b{1.0, 0.0};
};

/// Segments joined at corners. The segments, every corner and both ends collide. At least two
/// points, no point equal to the one before it.
struct Polyline {
  std::vector<Vec2> points;
};

/// A convex polygon: a closed region (edges, corners and inside). At least three points, strictly
/// convex (no three consecutive points on a line), given in either winding; the world stores it
/// counter-clockwise.
struct Polygon {
  std::vector<Vec2> points;
};

/// One of the geometries above. The index of the alternative is the GeometryType.
using Geometry = std::variant<Point, Circle, Segment, Polyline, Polygon>;

enum class GeometryType : int { Point = 0, Circle = 1, Segment = 2, Polyline = 3, Polygon = 4 };
inline constexpr int kGeometryTypeCount = 5;

inline GeometryType typeOf(const Geometry& g) { return static_cast<GeometryType>(g.index()); }
const char* nameOf(GeometryType type);

/// An axis-aligned box. An empty box has min > max.
struct Box {
  Vec2 min;
  Vec2 max;

  bool overlaps(const Box& o) const {
    return min.x <= o.max.x && o.min.x <= max.x && min.y <= o.max.y && o.min.y <= max.y;
  }
  bool contains(const Box& o) const {
    return min.x <= o.min.x && min.y <= o.min.y && o.max.x <= max.x && o.max.y <= max.y;
  }
  Box translated(Vec2 d) const { return {min + d, max + d}; }
};

/// The smallest box around both (inline: the hybrid step's first pass calls it for every moving disk).
inline Box unionOf(const Box& a, const Box& b) {
  return {{std::min(a.min.x, b.min.x), std::min(a.min.y, b.min.y)},
          {std::max(a.max.x, b.max.x), std::max(a.max.y, b.max.y)}};
}

/// The smallest box around the geometry.
Box boxOf(const Geometry& g);

/// Area: pi r^2 for a circle, the enclosed area for a polygon, 0 for points, segments and polylines.
double areaOf(const Geometry& g);

/// Why the geometry is invalid, naming the field and value (e.g. "Circle.radius = -1: must be finite
/// and >= 0"), or nothing when it is valid.
std::optional<std::string> validationError(const Geometry& g);

/// The same geometry in the form the world stores: polygons wound counter-clockwise.
/// Call only on a valid geometry.
Geometry normalized(const Geometry& g);

/// Distance from p to the closest point of the geometry (0 inside a polygon or circle).
double distanceTo(const Geometry& g, Vec2 p);

/// Whether two placed geometries intersect as closed sets (touching counts). Every pair of geometry
/// types is answered: circles and points by distance, the rest by the separating-axis test.
bool overlaps(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB);

/// Whether a placed geometry intersects a box (touching counts).
bool overlapsBox(const Geometry& g, Vec2 position, const Box& box);

/// Where a ray first meets a placed geometry.
struct RayCastHit {
  double fraction = 0;  ///< the hit is at origin + fraction * translation, fraction in [0, 1]
  Vec2 point;
  Vec2 normal;  ///< unit, on the side the ray came from
};

/// The first point of origin + t * translation, t in [0, 1], on the geometry. A ray starting inside a
/// circle or polygon hits at fraction 0 with normal -translation/|translation|. Segment and polyline
/// ends count for rays. A zero translation hits only if the origin is on the geometry.
std::optional<RayCastHit> rayCast(const Geometry& g, Vec2 position, Vec2 origin, Vec2 translation);

}  // namespace rattle
