// Geometry overlap tests and ray casts: overlaps(), overlapsBox() and rayCast() for every geometry.
//
// Every geometry is a closed set (a segment includes its ends, a polygon its edges and inside), so two
// geometries that only touch overlap, and a ray that grazes one hits it.
//
// Frames. Overlap tests put both geometries in world coordinates (vertex + position: one rounding per
// coordinate, the same whichever argument comes first; a disk's world centre is then taken into the other
// geometry's frame for distanceTo). A pair is always evaluated with the lower GeometryType first, and the
// tests for two geometries of the same type are symmetric expressions, so overlaps(a, pa, b, pb) and
// overlaps(b, pb, a, pa) compute the same values and can never disagree. Ray casts instead move the ray
// into the geometry's frame (origin - position, computed once), which costs nothing per vertex.
//
// Overlap kernels.
//  - A point is a circle of radius 0, and a disk of radius r meets a closed set X exactly when
//    dist(centre, X) <= r. distanceTo() gives that distance for every geometry (0 inside a polygon).
//  - Segments and polygons are convex: two compact convex sets are disjoint exactly when a line
//    separates them strictly, and in 2D such a line can be taken parallel to an edge of their Minkowski
//    difference A - B, whose edge directions are those of A's and B's edges: the separating-axis theorem
//    (Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996; Ericson, Real-Time Collision Detection, 2005,
//    sections 4.4 and 5.2). So polygon-polygon tests both polygons' edge normals. A segment is a polygon
//    of zero width: against a polygon the Minkowski difference has the polygon's edges plus the
//    segment's direction, so the segment's normal is the one extra axis. Two parallel segments have a
//    Minkowski difference that is itself a segment, and their normals cannot see a gap along their common
//    line; the x and y axes (the two boxes) can, because a line that is not vertical projects monotonically
//    onto x (and a vertical one onto y), so collinear segments are apart along their line exactly when
//    their boxes are apart. Every test starts with the boxes: a redundant axis never gives a wrong answer
//    (the projections of intersecting sets always overlap), and it is the cheapest rejection.
//  - A polyline is the union of its closed segments.
// Separation is decided only by a strict inequality (every vertex strictly beyond the axis' line), so
// touching sets are never separated. Edge normals are left unnormalized: the sign of a projection is
// all a separation test needs, and skipping the square root avoids its rounding.
//
// Ray-cast kernels work with the translation scaled by a power of two (exact, see ScaledRay), so no
// dot product of the translation with itself can overflow or underflow, and solve in closed form:
// line-line intersection by Cramer's rule for segments, half-plane clipping (Cyrus and Beck, "Generalized
// two- and three-dimensional clipping", Computers & Graphics 3, 1978) for polygons, and the quadratic
// |m + t d|^2 = r^2 in its cancellation-free form for circles.
//
// Nothing here allocates: polygon and polyline vertices are read in place through the Placed view.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "collision/plain_disk_impact.h"
#include "rattle/geometry.h"

namespace rattle {

namespace {

// The normal reported when there is no direction to report one against: a zero translation that starts
// on the geometry. Any fixed unit vector would do; this is the one time_of_impact.cpp uses for
// coincident centres.
constexpr Vec2 kNoDirection{1.0, 0.0};

// The vertices of a geometry placed at `offset`, read without copying.
struct Placed {
  const Vec2* points;
  size_t count;
  Vec2 offset;
  Vec2 operator[](size_t i) const { return points[i] + offset; }
};

// Twice the signed area (shoelace formula); positive for counter-clockwise winding.
double twiceSignedArea(const std::vector<Vec2>& points) {
  double sum = 0.0;
  for (size_t i = 0, n = points.size(); i < n; ++i) sum += cross(points[i], points[(i + 1) % n]);
  return sum;
}

// +1 for a counter-clockwise polygon, -1 for a clockwise one: the world stores polygons counter-clockwise,
// but the free functions accept either winding, as validationError() does.
double orientationOf(const Polygon& p) { return twiceSignedArea(p.points) >= 0 ? 1.0 : -1.0; }

// v / |v|, scaled first by its largest component so that |v|^2 neither overflows nor underflows.
// `fallback` for the zero vector.
Vec2 unit(Vec2 v, Vec2 fallback) {
  const double s = std::max(std::fabs(v.x), std::fabs(v.y));
  if (!(s > 0)) return fallback;
  const Vec2 w{v.x / s, v.y / s};
  const double len = length(w);
  return {w.x / len, w.y / len};
}

// ---- Overlap kernels -------------------------------------------------------------------------------------

// Whether some edge line of polygon `poly` (orientation `orient`) has every vertex of `other` strictly
// outside it: then that line separates the two. For a counter-clockwise polygon the inside of edge a->b is
// on its left, where cross(b - a, v - a) > 0.
bool polygonEdgeSeparates(Placed poly, double orient, Placed other) {
  for (size_t i = 0; i < poly.count; ++i) {
    const Vec2 a = poly[i];
    const Vec2 e = poly[i + 1 == poly.count ? 0 : i + 1] - a;
    bool allOutside = true;
    for (size_t j = 0; j < other.count && allOutside; ++j) allOutside = orient * cross(e, other[j] - a) < 0;
    if (allOutside) return true;
  }
  return false;
}

// Whether the line of segment `seg` (two placed points) has every vertex of `other` strictly on one side
// of it.
bool segmentSeparates(Placed seg, Placed other) {
  const Vec2 a = seg[0];
  const Vec2 d = seg[1] - a;
  bool allLeft = true, allRight = true;
  for (size_t j = 0; j < other.count; ++j) {
    const double side = cross(d, other[j] - a);
    allLeft = allLeft && side > 0;
    allRight = allRight && side < 0;
  }
  return allLeft || allRight;
}

// Whether the boxes of two placed vertex lists are strictly apart: the separating-axis test on the x and
// y axes. Cheap, so it comes first everywhere; for two segments it is also the axis along their line.
bool boxesApart(Placed a, Placed b) {
  double aMinX = a[0].x, aMaxX = aMinX, aMinY = a[0].y, aMaxY = aMinY;
  for (size_t i = 1; i < a.count; ++i) {
    const Vec2 p = a[i];
    aMinX = std::min(aMinX, p.x), aMaxX = std::max(aMaxX, p.x);
    aMinY = std::min(aMinY, p.y), aMaxY = std::max(aMaxY, p.y);
  }
  double bMinX = b[0].x, bMaxX = bMinX, bMinY = b[0].y, bMaxY = bMinY;
  for (size_t i = 1; i < b.count; ++i) {
    const Vec2 p = b[i];
    bMinX = std::min(bMinX, p.x), bMaxX = std::max(bMaxX, p.x);
    bMinY = std::min(bMinY, p.y), bMaxY = std::max(bMaxY, p.y);
  }
  return aMaxX < bMinX || bMaxX < aMinX || aMaxY < bMinY || bMaxY < aMinY;
}

bool segmentSegment(Placed s, Placed t) {
  // The boxes are not only a quick rejection here: they are the axes that see a gap between collinear
  // segments.
  if (boxesApart(s, t)) return false;
  return !segmentSeparates(s, t) && !segmentSeparates(t, s);
}

bool segmentPolygon(Placed s, Placed poly, double orient) {
  if (boxesApart(s, poly)) return false;
  return !segmentSeparates(s, poly) && !polygonEdgeSeparates(poly, orient, s);
}

bool polygonPolygon(Placed p, double op, Placed q, double oq) {
  if (boxesApart(p, q)) return false;
  return !polygonEdgeSeparates(p, op, q) && !polygonEdgeSeparates(q, oq, p);
}

// A point or circle, placed: the geometries tested by distance.
struct Round {
  Vec2 center;
  double radius;
};

std::optional<Round> roundOf(const Geometry& g, Vec2 position) {
  if (const auto* p = std::get_if<Point>(&g)) return Round{p->position + position, 0.0};
  if (const auto* c = std::get_if<Circle>(&g)) return Round{c->center + position, c->radius};
  return std::nullopt;
}

bool roundOverlaps(Round r, const Geometry& g, Vec2 position) {
  // Two disks meet when their centres are at most r1 + r2 apart. |-d| has the same bits as |d|, so the
  // test is symmetric.
  if (auto q = roundOf(g, position)) return length(r.center - q->center) <= r.radius + q->radius;
  return distanceTo(g, r.center - position) <= r.radius;
}

// Both geometries are segments, polylines or polygons, and typeOf(a) <= typeOf(b).
bool overlapsConvexPieces(const Geometry& a, Vec2 pa, const Geometry& b, Vec2 pb) {
  if (const auto* s = std::get_if<Segment>(&a)) {
    const Vec2 ends[2] = {s->a, s->b};
    const Placed sa{ends, 2, pa};
    if (const auto* t = std::get_if<Segment>(&b)) {
      const Vec2 tends[2] = {t->a, t->b};
      return segmentSegment(sa, Placed{tends, 2, pb});
    }
    if (const auto* l = std::get_if<Polyline>(&b)) {
      for (size_t i = 0; i + 1 < l->points.size(); ++i)
        if (segmentSegment(sa, Placed{l->points.data() + i, 2, pb})) return true;
      return false;
    }
    const auto& q = std::get<Polygon>(b);
    return segmentPolygon(sa, Placed{q.points.data(), q.points.size(), pb}, orientationOf(q));
  }
  if (const auto* l = std::get_if<Polyline>(&a)) {
    if (const auto* m = std::get_if<Polyline>(&b)) {
      for (size_t i = 0; i + 1 < l->points.size(); ++i) {
        const Placed si{l->points.data() + i, 2, pa};
        for (size_t j = 0; j + 1 < m->points.size(); ++j)
          if (segmentSegment(si, Placed{m->points.data() + j, 2, pb})) return true;
      }
      return false;
    }
    const auto& q = std::get<Polygon>(b);
    const Placed pq{q.points.data(), q.points.size(), pb};
    const double oq = orientationOf(q);
    for (size_t i = 0; i + 1 < l->points.size(); ++i)
      if (segmentPolygon(Placed{l->points.data() + i, 2, pa}, pq, oq)) return true;
    return false;
  }
  const auto& p = std::get<Polygon>(a);
  const auto& q = std::get<Polygon>(b);
  return polygonPolygon(Placed{p.points.data(), p.points.size(), pa}, orientationOf(p),
                        Placed{q.points.data(), q.points.size(), pb}, orientationOf(q));
}

// ---- Ray-cast kernels ------------------------------------------------------------------------------------

// The ray origin + t * translation, t in [0, 1], in the geometry's frame, with the translation scaled by
// 2^-exponent so that its largest component lies in [1, 2). Scaling by a power of two is exact (barring a
// component 2^1022 times smaller than the other), so kernels solve for tau = t * 2^exponent with the
// scaled direction and convert back with ldexp, exactly; |d|^2 is then in [1, 8) and cannot overflow or
// underflow, whatever the magnitude of the translation.
struct ScaledRay {
  Vec2 origin;
  Vec2 d;
  int exponent = 0;
  bool zero = false;  // zero translation: only the origin is tested
  Vec2 against;       // -translation / |translation|: the normal of a hit from inside or end-on

  double fraction(double tau) const { return std::ldexp(tau, -exponent); }
};

ScaledRay scaledRay(Vec2 origin, Vec2 translation) {
  ScaledRay r;
  r.origin = origin;
  const double largest = std::max(std::fabs(translation.x), std::fabs(translation.y));
  if (!(largest > 0)) {
    r.zero = true;
    r.against = kNoDirection;
    return r;
  }
  r.exponent = std::ilogb(largest);
  r.d = {std::ldexp(translation.x, -r.exponent), std::ldexp(translation.y, -r.exponent)};
  r.against = unit(-r.d, kNoDirection);
  return r;
}

struct LocalHit {
  double fraction;
  Vec2 normal;
};

// A point is hit only when the ray passes exactly through it: w = p - o parallel to d (cross product
// exactly zero) and tau = w.d / d.d in [0, 2^exponent].
std::optional<LocalHit> rayPoint(const ScaledRay& ray, Vec2 p) {
  const Vec2 w = p - ray.origin;
  if (ray.zero) {
    if (w.x == 0 && w.y == 0) return LocalHit{0.0, ray.against};
    return std::nullopt;
  }
  if (cross(ray.d, w) != 0) return std::nullopt;
  const double tau = dot(w, ray.d) / dot(ray.d, ray.d);
  if (!(tau >= 0)) return std::nullopt;
  const double t = ray.fraction(tau);
  if (!(t <= 1)) return std::nullopt;
  return LocalHit{t, ray.against};
}

// |m|^2 - r^2, accurate even when the origin is near the surface and the difference cancels. Each square
// is split into its rounded value and its exact rounding error (one fma each), the two large squares are
// added with Knuth's TwoSum (which also yields its exact error), and the large terms then cancel exactly
// (Sterbenz: |m|^2 and r^2 within a factor 2 of each other) before the small errors are added back
// (Ogita, Rump, Oishi, "Accurate sum and dot product", SIAM J. Sci. Comput. 26, 2005). Plain
// m.m - r*r would lose all its digits for an origin 1e-12 from a unit circle; this keeps them, so the
// fraction of a ray starting just outside is right to a few ulps.
double circleValue(Vec2 m, double r) {
  const double px = m.x * m.x, ex = std::fma(m.x, m.x, -px);
  const double py = m.y * m.y, ey = std::fma(m.y, m.y, -py);
  const double pr = r * r, er = std::fma(r, r, -pr);
  const double s = px + py;
  const double bb = s - px;
  const double es = (px - (s - bb)) + (py - bb);
  return (s - pr) + (((es + ex) + ey) - er);
}

// |m + tau d|^2 = r^2 with m = o - c: A tau^2 + 2 b tau + c = 0, A = d.d, b = m.d, c = m.m - r^2.
std::optional<LocalHit> rayCircle(const ScaledRay& ray, Vec2 center, double radius) {
  // A circle of radius 0 behaves as a point; the quadratic would reach the same answer only up to the
  // rounding of its square root.
  if (radius == 0) return rayPoint(ray, center);
  const Vec2 m = ray.origin - center;
  // The same inside test as distanceTo (max(0, |m| - r) == 0), so a ray and a point query agree on
  // where the circle is.
  const double len = length(m);
  if (ray.zero) {
    if (len <= radius) return LocalHit{0.0, ray.against};
    return std::nullopt;
  }
  const double b = dot(m, ray.d);
  if (len < radius) return LocalHit{0.0, ray.against};  // starts inside
  if (len == radius) {
    // Starts on the circle: moving in, it meets the surface now, with the surface normal; moving along
    // or out, it is on the circle all the same.
    return LocalHit{0.0, b < 0 ? unit(m, ray.against) : ray.against};
  }
  // Outside. |m + tau d| is convex in tau with its minimum at -b/A: b >= 0 means it never comes closer.
  if (!(b < 0)) return std::nullopt;
  const double a = dot(ray.d, ray.d);
  const double c = circleValue(m, radius);
  const double disc = detail::plainDiscriminant(b, a, c);  // the compensated b^2 - a c (plain_disk_impact.h)
  if (disc < 0) return std::nullopt;  // passes by; disc == 0 is a tangent graze, which hits (closed set)
  // The smaller root (-b - sqrt(disc)) / A cancels when c -> 0 (origin near the surface); its conjugate
  // form c / (-b + sqrt(disc)) adds two non-negative terms (Press et al., Numerical Recipes, 5.6).
  double tau = c / (-b + std::sqrt(disc));
  if (!(tau > 0)) tau = 0.0;  // c rounded to <= 0 although |m| > r: the origin is on the surface
  const double t = ray.fraction(tau);
  if (!(t <= 1)) return std::nullopt;
  return LocalHit{t, unit(m + tau * ray.d, ray.against)};
}

// The closed segment [a, b], from either side. o + tau d = a + s (b - a) solved by Cramer's rule:
// with e = a - o and den = cross(d, b - a), tau = cross(e, b - a) / den and s = cross(e, d) / den.
std::optional<LocalHit> raySegment(const ScaledRay& ray, Vec2 a, Vec2 b) {
  const Vec2 u = b - a;
  const Vec2 e = a - ray.origin;
  if (ray.zero) {
    // The origin on the segment: on its line and between its ends.
    const Vec2 w = ray.origin - a;
    const double s = dot(w, u);
    if (cross(u, w) == 0 && s >= 0 && s <= dot(u, u)) return LocalHit{0.0, ray.against};
    return std::nullopt;
  }
  const double den = cross(ray.d, u);
  if (den != 0) {
    const double tau = cross(e, u) / den;
    const double s = cross(e, ray.d) / den;
    if (!(tau >= 0) || !(s >= 0) || !(s <= 1)) return std::nullopt;
    const double t = ray.fraction(tau);
    if (!(t <= 1)) return std::nullopt;
    // perpendicular(u) . d = cross(u, d) = -den: perpendicular(u) faces the ray when den > 0.
    const Vec2 n = unit(den > 0 ? perpendicular(u) : -perpendicular(u), ray.against);
    return LocalHit{t, n};
  }
  // Parallel. On another line: never meets. On the same line: the segment's ends project onto the ray
  // at tau = (end - o).d / d.d, and the first point of the overlap of [0, 2^exponent] with their span is
  // hit end-on (or at 0 if the origin is on the segment), where the segment has no side to report.
  if (cross(e, ray.d) != 0) return std::nullopt;
  const double dd = dot(ray.d, ray.d);
  const double ta = dot(e, ray.d) / dd;
  const double tb = dot(b - ray.origin, ray.d) / dd;
  const double lo = std::min(ta, tb), hi = std::max(ta, tb);
  const double tau = std::max(lo, 0.0);
  if (!(tau <= hi)) return std::nullopt;
  const double t = ray.fraction(tau);
  if (!(t <= 1)) return std::nullopt;
  return LocalHit{t, ray.against};
}

std::optional<LocalHit> rayPolyline(const ScaledRay& ray, const std::vector<Vec2>& points) {
  std::optional<LocalHit> best;
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    auto hit = raySegment(ray, points[i], points[i + 1]);
    // Strictly nearer only: on a tie (a corner) the lower segment index wins, the same on every run.
    if (hit && (!best || hit->fraction < best->fraction)) best = hit;
  }
  return best;
}

// Cyrus-Beck clipping of the ray against the polygon's edge half-planes. For edge i from a to a + e,
// the signed (unnormalized) depth of o + tau d inside it is side + tau * rate with side = k cross(e, o - a)
// and rate = k cross(e, d), k the orientation. The ray is inside the polygon for tau in [enter, exit]:
// enter is the largest tau at which it crosses into a half-plane it starts outside of (rate > 0), exit the
// smallest tau at which it leaves one (rate < 0). It hits when enter <= exit and enter <= 2^exponent; if it
// entered no half-plane it started inside (fraction 0, normal -direction).
std::optional<LocalHit> rayPolygon(const ScaledRay& ray, const Polygon& polygon) {
  const std::vector<Vec2>& p = polygon.points;
  const size_t n = p.size();
  const double k = orientationOf(polygon);
  double enter = 0.0;
  double exit = std::numeric_limits<double>::infinity();
  size_t enterEdge = n;  // none
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = p[i];
    const Vec2 e = p[i + 1 == n ? 0 : i + 1] - a;
    const double side = k * cross(e, ray.origin - a);
    const double rate = k * cross(e, ray.d);
    if (rate > 0) {
      // Starting outside (or on) this edge's line and crossing into it at tau = -side / rate. Starting
      // inside it constrains nothing for tau >= 0.
      if (side <= 0) {
        const double tau = side == 0 ? 0.0 : -side / rate;
        // Strictly later only: at a corner the lower edge index wins, the same on every run.
        if (enterEdge == n || tau > enter) enter = tau, enterEdge = i;
      }
    } else if (rate < 0) {
      if (side < 0) return std::nullopt;  // outside this half-plane and leaving it
      exit = std::min(exit, side / -rate);
    } else if (side < 0) {
      return std::nullopt;  // outside this half-plane and parallel to its line
    }
  }
  if (!(enter <= exit)) return std::nullopt;
  const double t = ray.fraction(enter);
  if (!(t <= 1)) return std::nullopt;
  if (enterEdge == n) return LocalHit{0.0, ray.against};  // the origin is in the polygon
  const Vec2 e = p[enterEdge + 1 == n ? 0 : enterEdge + 1] - p[enterEdge];
  // The outward normal: the edge direction turned clockwise for a counter-clockwise polygon.
  return LocalHit{t, unit(Vec2{k * e.y, -k * e.x}, ray.against)};
}

}  // namespace

bool overlaps(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB) {
  // Lower type first, so that both argument orders run the same code on the same values.
  if (a.index() > b.index()) return overlaps(b, positionB, a, positionA);
  if (auto r = roundOf(a, positionA)) return roundOverlaps(*r, b, positionB);
  return overlapsConvexPieces(a, positionA, b, positionB);
}

bool overlapsBox(const Geometry& g, Vec2 position, const Box& box) {
  // An empty box (min > max, or NaN) holds nothing.
  if (!(box.min.x <= box.max.x) || !(box.min.y <= box.max.y)) return false;
  // The box as a counter-clockwise polygon, tested with the x and y axes (its edge normals) and the
  // geometry's own axes. A box of zero width or height is a segment or a point; its x and y axes are
  // still its Minkowski-difference normals, so the tests stay exact for it.
  const Vec2 corners[4] = {box.min, {box.max.x, box.min.y}, box.max, {box.min.x, box.max.y}};
  const Placed boxPlaced{corners, 4, Vec2{}};
  if (const auto* p = std::get_if<Point>(&g)) {
    const Vec2 q = p->position + position;
    return box.min.x <= q.x && q.x <= box.max.x && box.min.y <= q.y && q.y <= box.max.y;
  }
  if (const auto* c = std::get_if<Circle>(&g)) {
    // The closest point of a box to a point is the point clamped to the box, coordinate by coordinate.
    const Vec2 center = c->center + position;
    const Vec2 closest{std::clamp(center.x, box.min.x, box.max.x), std::clamp(center.y, box.min.y, box.max.y)};
    return length(center - closest) <= c->radius;
  }
  if (const auto* s = std::get_if<Segment>(&g)) {
    const Vec2 ends[2] = {s->a, s->b};
    const Placed seg{ends, 2, position};
    return !boxesApart(seg, boxPlaced) && !segmentSeparates(seg, boxPlaced);
  }
  if (const auto* l = std::get_if<Polyline>(&g)) {
    for (size_t i = 0; i + 1 < l->points.size(); ++i) {
      const Placed seg{l->points.data() + i, 2, position};
      if (!boxesApart(seg, boxPlaced) && !segmentSeparates(seg, boxPlaced)) return true;
    }
    return false;
  }
  const auto& q = std::get<Polygon>(g);
  const Placed poly{q.points.data(), q.points.size(), position};
  return !boxesApart(poly, boxPlaced) && !polygonEdgeSeparates(poly, orientationOf(q), boxPlaced);
}

std::optional<RayCastHit> rayCast(const Geometry& g, Vec2 position, Vec2 origin, Vec2 translation) {
  const ScaledRay ray = scaledRay(origin - position, translation);
  std::optional<LocalHit> hit;
  if (const auto* p = std::get_if<Point>(&g)) {
    hit = rayPoint(ray, p->position);
  } else if (const auto* c = std::get_if<Circle>(&g)) {
    hit = rayCircle(ray, c->center, c->radius);
  } else if (const auto* s = std::get_if<Segment>(&g)) {
    hit = raySegment(ray, s->a, s->b);
  } else if (const auto* l = std::get_if<Polyline>(&g)) {
    hit = rayPolyline(ray, l->points);
  } else {
    hit = rayPolygon(ray, std::get<Polygon>(g));
  }
  if (!hit) return std::nullopt;
  // Reported in world coordinates, at the fraction along the caller's own ray. Adding +0 turns a -0
  // fraction (from 0 / negative or 0 * negative) into +0, so equal hits have equal bits.
  const double fraction = hit->fraction + 0.0;
  return RayCastHit{fraction, origin + fraction * translation, hit->normal};
}

}  // namespace rattle
