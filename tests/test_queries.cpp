// Tests for the query layer: overlaps(), overlapsBox() and rayCast() on every geometry (suites Overlap*),
// and the World queries rayCastFirst, rayCastAll, overlapBox, overlapCircle and overlapPoint (Query*).
//
// References. Hand-made cases have answers known exactly (touching, apart by 1e-9, contained, crossing).
// The randomized tests compare against references written here independently of the engine's algorithms:
//  - overlaps: the distance between the two shapes by brute force (closest points between every pair of
//    edges, proper crossings by orientation signs, containment by a point-in-polygon test), minus the
//    radii; the shapes overlap when that gap is <= 0. Cases within 1e-9 of touching are not judged,
//    except in the near-touch test, which moves one shape along the closest-point direction to a gap of
//    exactly +-1e-9 and judges by the recomputed reference.
//  - rayCast: sphere tracing along the ray with the reference distance (each step advances by the
//    distance to the shape, so it never passes the first contact), which gives the first hit within
//    1e-13; grazing rays that take too many steps to decide are not judged.
//  - World queries: brute-force loops over the same fixtures with the geometry functions above.
// Random numbers come from std::mt19937_64 through our own mapping to [0, 1) (std distributions differ
// between standard libraries), so every run sees the same cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "common/format.h"
#include "rattle/rattle.h"

namespace {

using rattle::Box;
using rattle::Circle;
using rattle::Geometry;
using rattle::GeometryType;
using rattle::Point;
using rattle::Polygon;
using rattle::Polyline;
using rattle::RayCastHit;
using rattle::Segment;
using rattle::Vec2;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------------------
// Random numbers

struct Random {
  std::mt19937_64 rng;
  explicit Random(uint64_t seed) : rng(seed) {}
  double uniform(double lo, double hi) {
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;  // [0, 1)
    return lo + (hi - lo) * u;
  }
  int integer(int lo, int hi) {  // [lo, hi]
    return lo + static_cast<int>(rng() % static_cast<uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  Vec2 vec(double lo, double hi) { return {uniform(lo, hi), uniform(lo, hi)}; }
  Vec2 direction() {
    const double a = uniform(0.0, 2.0 * std::numbers::pi);
    return {std::cos(a), std::sin(a)};
  }
};

Geometry randomPolygon(Random& r, Vec2 c, double radius) {
  // Distinct points on a circle are strictly convex; at least 0.25 rad between neighbours keeps them well
  // away from collinear.
  for (;;) {
    const int n = r.integer(3, 6);
    std::vector<double> angles;
    for (int i = 0; i < n; ++i) angles.push_back(r.uniform(0.0, 2.0 * std::numbers::pi));
    std::sort(angles.begin(), angles.end());
    bool ok = true;
    for (int i = 0; i < n; ++i) {
      const double next = i + 1 < n ? angles[i + 1] : angles[0] + 2.0 * std::numbers::pi;
      if (next - angles[i] < 0.25) ok = false;
    }
    if (!ok) continue;
    Polygon p;
    for (double a : angles) p.points.push_back({c.x + radius * std::cos(a), c.y + radius * std::sin(a)});
    if (r.chance(0.5)) std::reverse(p.points.begin(), p.points.end());  // either winding
    if (!rattle::validationError(p)) return p;
  }
}

Geometry randomGeometry(Random& r, GeometryType type, double scale = 1.0) {
  const Vec2 c = r.vec(-0.5 * scale, 0.5 * scale);
  switch (type) {
    case GeometryType::Point:
      return Point{c};
    case GeometryType::Circle:
      return Circle{c, r.uniform(0.05, 1.0) * scale};
    case GeometryType::Segment:
      return Segment{c, c + r.uniform(0.2, 3.0) * scale * r.direction()};
    case GeometryType::Polyline: {
      Polyline l;
      l.points.push_back(c);
      const int n = r.integer(2, 6);
      for (int i = 1; i < n; ++i) l.points.push_back(l.points.back() + r.uniform(0.2, 1.5) * scale * r.direction());
      return l;
    }
    case GeometryType::Polygon:
      return randomPolygon(r, c, r.uniform(0.3, 1.5) * scale);
  }
  return Point{};
}

// ---------------------------------------------------------------------------------------------------------
// Reference geometry, written independently of overlap.cpp: everything is reduced to edges (a point or
// a circle's centre is an edge of zero length), plus the insides of polygons.

struct RefShape {
  std::vector<Vec2> points;  // world coordinates
  bool loop = false;         // a polygon: the last point joins the first, and the inside counts
  double radius = 0;         // a circle
};

RefShape refShapeOf(const Geometry& g, Vec2 position) {
  RefShape s;
  auto place = [&](const std::vector<Vec2>& pts) {
    for (Vec2 p : pts) s.points.push_back(p + position);
  };
  if (auto* p = std::get_if<Point>(&g)) s.points = {p->position + position};
  if (auto* c = std::get_if<Circle>(&g)) s.points = {c->center + position}, s.radius = c->radius;
  if (auto* e = std::get_if<Segment>(&g)) s.points = {e->a + position, e->b + position};
  if (auto* l = std::get_if<Polyline>(&g)) place(l->points);
  if (auto* q = std::get_if<Polygon>(&g)) place(q->points), s.loop = true;
  return s;
}

struct Edge {
  Vec2 a, b;
};

std::vector<Edge> edgesOf(const RefShape& s) {
  std::vector<Edge> edges;
  if (s.points.size() == 1) return {{s.points[0], s.points[0]}};
  for (size_t i = 0; i + 1 < s.points.size(); ++i) edges.push_back({s.points[i], s.points[i + 1]});
  if (s.loop) edges.push_back({s.points.back(), s.points.front()});
  return edges;
}

// Closest point of the segment [a, b] (possibly a == b) to p, by clamped projection.
Vec2 refClosestOnSegment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double dd = rattle::dot(d, d);
  if (dd == 0) return a;
  const double t = std::clamp(rattle::dot(p - a, d) / dd, 0.0, 1.0);
  return a + t * d;
}

double orient(Vec2 a, Vec2 b, Vec2 c) { return rattle::cross(b - a, c - a); }

bool refInsidePolygon(const RefShape& s, Vec2 p) {
  // Inside or on a convex polygon of either winding: never strictly on both sides of edges.
  bool left = false, right = false;
  for (const Edge& e : edgesOf(s)) {
    const double o = orient(e.a, e.b, p);
    left = left || o > 0;
    right = right || o < 0;
  }
  return !(left && right);
}

struct Closest {
  double distance;
  Vec2 onA, onB;
};

// Distance between two segments: 0 if they properly cross, else the closest of the four end-to-segment
// distances (two non-crossing segments in the plane are closest at an end of one of them).
Closest refSegmentDistance(Edge s, Edge t) {
  const double d1 = orient(t.a, t.b, s.a), d2 = orient(t.a, t.b, s.b);
  const double d3 = orient(s.a, s.b, t.a), d4 = orient(s.a, s.b, t.b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return {0.0, s.a, s.a};
  }
  Closest best{kInf, {}, {}};
  auto consider = [&](Vec2 onA, Vec2 onB) {
    const double d = rattle::length(onA - onB);
    if (d < best.distance) best = {d, onA, onB};
  };
  consider(s.a, refClosestOnSegment(s.a, t.a, t.b));
  consider(s.b, refClosestOnSegment(s.b, t.a, t.b));
  consider(refClosestOnSegment(t.a, s.a, s.b), t.a);
  consider(refClosestOnSegment(t.b, s.a, s.b), t.b);
  return best;
}

// Distance between the cores (no radii): 0 when they intersect.
Closest refCoreDistance(const RefShape& a, const RefShape& b) {
  if (a.loop && refInsidePolygon(a, b.points[0])) return {0.0, b.points[0], b.points[0]};
  if (b.loop && refInsidePolygon(b, a.points[0])) return {0.0, a.points[0], a.points[0]};
  Closest best{kInf, {}, {}};
  for (const Edge& ea : edgesOf(a))
    for (const Edge& eb : edgesOf(b)) {
      const Closest c = refSegmentDistance(ea, eb);
      if (c.distance < best.distance) best = c;
    }
  return best;
}

// Distance from p to the shape (0 inside a polygon or circle).
double refDistance(const RefShape& s, Vec2 p) {
  if (s.loop && refInsidePolygon(s, p)) return 0.0;
  double best = kInf;
  for (const Edge& e : edgesOf(s)) best = std::min(best, rattle::length(p - refClosestOnSegment(p, e.a, e.b)));
  return std::max(0.0, best - s.radius);
}

// ---------------------------------------------------------------------------------------------------------
// Helpers

std::string describe(const Geometry& g, Vec2 position) {
  std::string s = std::string(rattle::nameOf(rattle::typeOf(g))) + " at " + rattle::detail::str(position) + ":";
  auto pts = [&](const std::vector<Vec2>& p) {
    for (Vec2 v : p) s += " " + rattle::detail::str(v);
  };
  if (auto* p = std::get_if<Point>(&g)) s += " " + rattle::detail::str(p->position);
  if (auto* c = std::get_if<Circle>(&g)) s += " " + rattle::detail::str(c->center) + " r " + rattle::detail::str(c->radius);
  if (auto* e = std::get_if<Segment>(&g)) pts({e->a, e->b});
  if (auto* l = std::get_if<Polyline>(&g)) pts(l->points);
  if (auto* q = std::get_if<Polygon>(&g)) pts(q->points);
  return s;
}

// Checks overlaps() in both argument orders, and again with both geometries moved by the same offset
// (positions that are not zero, with a shift whose sums stay exact for the values used here).
void expectOverlap(const Geometry& a, const Geometry& b, bool expected, Vec2 pa = {}, Vec2 pb = {}) {
  SCOPED_TRACE(describe(a, pa) + "  vs  " + describe(b, pb));
  EXPECT_EQ(rattle::overlaps(a, pa, b, pb), expected);
  EXPECT_EQ(rattle::overlaps(b, pb, a, pa), expected);
  const Vec2 shift{8.0, -4.0};
  EXPECT_EQ(rattle::overlaps(a, pa + shift, b, pb + shift), expected) << "shifted";
  EXPECT_EQ(rattle::overlaps(b, pb + shift, a, pa + shift), expected) << "shifted";
}

Polygon square(Vec2 min, Vec2 max) { return Polygon{{min, {max.x, min.y}, max, {min.x, max.y}}}; }
Polygon clockwise(Polygon p) {
  std::reverse(p.points.begin(), p.points.end());
  return p;
}

constexpr double kEps = 1e-9;

// ---------------------------------------------------------------------------------------------------------
// overlaps(): every pair of geometry types by hand

TEST(OverlapPairs, PointPoint) {
  expectOverlap(Point{{1, 2}}, Point{{1, 2}}, true);
  expectOverlap(Point{{1, 2}}, Point{{0, 0}}, true, {}, {1, 2});  // placed by position
  expectOverlap(Point{{1, 2}}, Point{{1, 2 + kEps}}, false);
  expectOverlap(Point{{1, 2}}, Point{{1 - kEps, 2}}, false);
}

TEST(OverlapPairs, PointCircle) {
  const Circle c{{0, 0}, 1};
  expectOverlap(Point{{1, 0}}, c, true);            // on the circle
  expectOverlap(Point{{0, -1}}, c, true);
  expectOverlap(Point{{1 + kEps, 0}}, c, false);    // just outside
  expectOverlap(Point{{0.2, 0.3}}, c, true);        // inside
  expectOverlap(Point{{0, 0}}, c, true);            // at the centre
  expectOverlap(Point{{3, 0}}, c, true, {}, {2, 0});  // the circle placed by position
  expectOverlap(Point{{2, 0}}, Circle{{2, 0}, 0}, true);   // radius 0: a point
  expectOverlap(Point{{2, kEps}}, Circle{{2, 0}, 0}, false);
}

TEST(OverlapPairs, PointSegment) {
  const Segment s{{-1, 0}, {1, 0}};
  expectOverlap(Point{{0.5, 0}}, s, true);  // on it
  expectOverlap(Point{{1, 0}}, s, true);    // an end: closed
  expectOverlap(Point{{-1, 0}}, s, true);
  expectOverlap(Point{{1 + kEps, 0}}, s, false);  // beyond the end, on its line
  expectOverlap(Point{{0, kEps}}, s, false);      // beside it
  expectOverlap(Point{{1, 1}}, Segment{{0, 0}, {2, 2}}, true);  // diagonal, exactly on it
  expectOverlap(Point{{1, 1 + kEps}}, Segment{{0, 0}, {2, 2}}, false);
}

TEST(OverlapPairs, PointPolyline) {
  const Polyline l{{{0, 0}, {2, 0}, {2, 2}}};
  expectOverlap(Point{{2, 0}}, l, true);  // a corner
  expectOverlap(Point{{1, 0}}, l, true);
  expectOverlap(Point{{2, 2}}, l, true);  // an end
  expectOverlap(Point{{1, 1}}, l, false);  // in the bend: a polyline has no inside
  expectOverlap(Point{{2 + kEps, 1}}, l, false);
  expectOverlap(Point{{2, 2 + kEps}}, l, false);
}

TEST(OverlapPairs, PointPolygon) {
  for (const Polygon& g : {square({0, 0}, {2, 2}), clockwise(square({0, 0}, {2, 2}))}) {
    expectOverlap(Point{{1, 1}}, g, true);  // inside
    expectOverlap(Point{{2, 1}}, g, true);  // on an edge
    expectOverlap(Point{{2, 2}}, g, true);  // a corner
    expectOverlap(Point{{2 + kEps, 1}}, g, false);
    expectOverlap(Point{{1, -kEps}}, g, false);
    expectOverlap(Point{{5, 5}}, g, true, {}, {4, 4});  // the polygon placed by position
  }
  // A slanted edge: (0,0)-(4,0)-(0,4); (2,2) lies exactly on the hypotenuse.
  const Polygon t{{{0, 0}, {4, 0}, {0, 4}}};
  expectOverlap(Point{{2, 2}}, t, true);
  expectOverlap(Point{{2, 2 + kEps}}, t, false);
}

TEST(OverlapPairs, CircleCircle) {
  const Circle a{{0, 0}, 1};
  expectOverlap(a, Circle{{2, 0}, 1}, true);  // touching
  expectOverlap(a, Circle{{0, -3}, 2}, true);
  expectOverlap(a, Circle{{2 + kEps, 0}, 1}, false);
  expectOverlap(a, Circle{{1.5, 0}, 1}, true);   // crossing
  expectOverlap(a, Circle{{0.5, 0}, 3}, true);   // one inside the other
  expectOverlap(a, Circle{{0, 0}, 0.25}, true);  // concentric
  expectOverlap(a, Circle{{0, 0}, 1}, true, {}, {2, 0});  // placed by position: touching
  expectOverlap(a, Circle{{0, 0}, 1}, false, {}, {0, 2 + kEps});
}

TEST(OverlapPairs, CircleSegment) {
  const Segment s{{-1, 0}, {1, 0}};
  expectOverlap(Circle{{0, 1}, 1}, s, true);  // touching its side
  expectOverlap(Circle{{0, -1}, 1}, s, true);
  expectOverlap(Circle{{0, 1 + kEps}, 1}, s, false);
  expectOverlap(Circle{{2, 0}, 1}, s, true);  // touching an end, end-on: ends belong to the set
  expectOverlap(Circle{{2 + kEps, 0}, 1}, s, false);
  expectOverlap(Circle{{0, 0.5}, 1}, s, true);  // crossing
  expectOverlap(Circle{{0, 0}, 5}, s, true);    // the segment inside the circle
  expectOverlap(Circle{{0, 0}, 0}, s, true);    // radius 0 on the segment
}

TEST(OverlapPairs, CirclePolyline) {
  // A closed square loop: the polyline is only its outline.
  const Polyline loop{{{0, 0}, {4, 0}, {4, 4}, {0, 4}, {0, 0}}};
  expectOverlap(Circle{{2, 2}, 1}, loop, false);  // inside the loop, touching nothing
  expectOverlap(Circle{{2, 2}, 2}, loop, true);   // touching all four sides from inside
  expectOverlap(Circle{{2, 2}, 2 - kEps}, loop, false);
  expectOverlap(Circle{{0, 2}, 1}, loop, true);  // crossing a side
  expectOverlap(Circle{{5, 5}, 1}, loop, false);  // near a corner: the distance is sqrt(2)
  expectOverlap(Circle{{5, 4}, 1}, loop, true);   // touching the corner (4, 4)
  expectOverlap(Circle{{2, 2}, 10}, loop, true);  // the whole loop inside the circle
}

TEST(OverlapPairs, CirclePolygon) {
  for (const Polygon& g : {square({0, 0}, {2, 2}), clockwise(square({0, 0}, {2, 2}))}) {
    expectOverlap(Circle{{3, 1}, 1}, g, true);  // touching an edge
    expectOverlap(Circle{{3 + kEps, 1}, 1}, g, false);
    expectOverlap(Circle{{3, 2}, 1}, g, true);  // touching a corner, end-on
    expectOverlap(Circle{{2, 3 + kEps}, 1}, g, false);
    expectOverlap(Circle{{1, 1}, 0.25}, g, true);  // inside the polygon
    expectOverlap(Circle{{1, 1}, 10}, g, true);    // the polygon inside the circle
    expectOverlap(Circle{{2, 1}, 0.5}, g, true);   // crossing an edge
    expectOverlap(Circle{{3, 1}, 1}, g, true, {4, 4}, {4, 4});
  }
}

TEST(OverlapPairs, SegmentSegment) {
  const Segment s{{0, 0}, {2, 0}};
  expectOverlap(s, Segment{{1, 0}, {1, 1}}, true);  // T: an end on the other's inside
  expectOverlap(s, Segment{{1, kEps}, {1, 1}}, false);
  expectOverlap(Segment{{0, 0}, {2, 2}}, Segment{{0, 2}, {2, 0}}, true);  // crossing
  expectOverlap(Segment{{0, 0}, {1, 1}}, Segment{{1, 1}, {2, 0}}, true);  // end to end at an angle
  expectOverlap(Segment{{0, 0}, {1, 1}}, Segment{{1 + kEps, 1}, {2, 0}}, false);
  // Collinear: touching end to end, a gap, overlapping, one inside the other.
  expectOverlap(Segment{{0, 0}, {1, 0}}, Segment{{1, 0}, {2, 0}}, true);
  expectOverlap(Segment{{0, 0}, {1, 0}}, Segment{{1 + kEps, 0}, {2, 0}}, false);
  expectOverlap(Segment{{0, 0}, {1, 0}}, Segment{{2, 0}, {1 + kEps, 0}}, false);
  expectOverlap(Segment{{0, 0}, {2, 0}}, Segment{{0.5, 0}, {3, 0}}, true);
  expectOverlap(Segment{{0, 0}, {4, 0}}, Segment{{2, 0}, {1, 0}}, true);
  // Collinear on a diagonal: only the direction axes can see the gap.
  expectOverlap(Segment{{0, 0}, {1, 1}}, Segment{{2, 2}, {3, 3}}, false);
  expectOverlap(Segment{{0, 0}, {1, 1}}, Segment{{1, 1}, {3, 3}}, true);
  // Parallel, apart by 1e-9.
  expectOverlap(s, Segment{{0, kEps}, {2, kEps}}, false);
  expectOverlap(s, Segment{{0, 0}, {2, 0}}, true, {}, {1, 0});  // placed: overlapping on [1, 2]
  expectOverlap(s, Segment{{0, 0}, {2, 0}}, false, {}, {2 + kEps, 0});
}

TEST(OverlapPairs, SegmentPolyline) {
  const Polyline l{{{0, 0}, {2, 0}, {2, 2}}};
  expectOverlap(Segment{{2, 0}, {3, -1}}, l, true);  // at the corner, from outside
  expectOverlap(Segment{{2 + kEps, 0}, {3, -1}}, l, false);
  expectOverlap(Segment{{1, -1}, {1, 1}}, l, true);  // crossing
  expectOverlap(Segment{{0.5, 0.5}, {1.5, 1.5}}, l, false);  // in the bend
  expectOverlap(Segment{{-1, 0}, {0, 0}}, l, true);  // collinear, touching the first end
  expectOverlap(Segment{{-1, 0}, {-kEps, 0}}, l, false);
  expectOverlap(Segment{{2, 2}, {3, 3}}, l, true);  // at the last end
}

TEST(OverlapPairs, SegmentPolygon) {
  for (const Polygon& g : {square({0, 0}, {2, 2}), clockwise(square({0, 0}, {2, 2}))}) {
    expectOverlap(Segment{{2, 1}, {3, 1}}, g, true);  // touching an edge end-on
    expectOverlap(Segment{{2 + kEps, 1}, {3, 1}}, g, false);
    expectOverlap(Segment{{0.5, 0.5}, {1.5, 1.5}}, g, true);  // inside
    expectOverlap(Segment{{-1, 1}, {3, 1}}, g, true);         // crossing through
    expectOverlap(Segment{{2, -1}, {2, 3}}, g, true);         // along an edge's line
    expectOverlap(Segment{{2 + kEps, -1}, {2 + kEps, 3}}, g, false);
    // Through the corner (2, 2) on the line x + y = 4, and moved off it by 1e-9: only the segment's
    // normal separates the latter (both boxes and every edge normal overlap).
    expectOverlap(Segment{{1.5, 2.5}, {2.5, 1.5}}, g, true);
    expectOverlap(Segment{{1.5 + kEps, 2.5}, {2.5 + kEps, 1.5}}, g, false);
  }
}

TEST(OverlapPairs, PolylinePolyline) {
  const Polyline l{{{0, 0}, {2, 0}, {2, 2}}};
  expectOverlap(l, Polyline{{{1, -1}, {1, 1}, {3, 1}}}, true);  // crossing twice
  expectOverlap(l, Polyline{{{2, 2}, {3, 3}, {4, 2}}}, true);   // end to end
  expectOverlap(l, Polyline{{{2, 2 + kEps}, {3, 3}, {4, 2}}}, false);
  expectOverlap(l, Polyline{{{3, -1}, {2, 0}, {3, 1}}}, true);  // corner to corner
  expectOverlap(l, Polyline{{{3, -1}, {2 + kEps, 0}, {3, 1}}}, false);
  expectOverlap(l, Polyline{{{0.5, 0.5}, {1.5, 0.5}, {1.5, 1.5}}}, false);  // inside the bend
  // A small loop inside a large one: polylines have no inside.
  const Polyline big{{{-5, -5}, {5, -5}, {5, 5}, {-5, 5}, {-5, -5}}};
  const Polyline small{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}}};
  expectOverlap(big, small, false);
  expectOverlap(big, small, true, {}, {4, 0});  // moved onto the big loop's side
}

TEST(OverlapPairs, PolylinePolygon) {
  const Polygon g = square({0, 0}, {2, 2});
  const Polyline around{{{-1, -1}, {3, -1}, {3, 3}, {-1, 3}, {-1, -1}}};
  expectOverlap(around, g, false);  // the polygon inside the loop
  expectOverlap(Polyline{{{0.5, 0.5}, {1.5, 0.5}, {1, 1.5}}}, g, true);  // the polyline inside the polygon
  expectOverlap(Polyline{{{3, 0}, {2, 2}, {3, 4}}}, g, true);  // touching a corner with a corner
  expectOverlap(Polyline{{{3, 0}, {2 + kEps, 2}, {3, 4}}}, g, false);
  expectOverlap(Polyline{{{-1, 1}, {1, 1}, {1, 3}}}, g, true);  // crossing
  expectOverlap(clockwise(g), Polyline{{{3, 0}, {2, 2}, {3, 4}}}, true);
}

TEST(OverlapPairs, PolygonPolygon) {
  const Polygon g = square({0, 0}, {1, 1});
  for (const Polygon& h : {g, clockwise(g)}) {
    expectOverlap(h, square({1, 0}, {2, 1}), true);  // sharing an edge
    expectOverlap(h, square({1 + kEps, 0}, {2, 1}), false);
    expectOverlap(h, square({1, 1}, {2, 2}), true);  // sharing a corner
    expectOverlap(h, square({1, 1 + kEps}, {2, 2}), false);
    expectOverlap(h, square({0.25, 0.25}, {0.5, 0.5}), true);  // contained
    expectOverlap(h, square({-1, -1}, {3, 3}), true);          // containing
    expectOverlap(h, square({0.5, 0.5}, {1.5, 1.5}), true);    // crossing
    expectOverlap(h, square({0, 0}, {1, 1}), true, {}, {1, 1});
    // A triangle whose hypotenuse x + y = 2 passes through the square's corner (1, 1), then moved off by
    // 1e-9 in x: the boxes and the square's normals still overlap, only the hypotenuse's normal separates.
    const Polygon tri{{{2, 0}, {2, 2}, {0, 2}}};
    expectOverlap(h, tri, true);
    expectOverlap(h, tri, false, {}, {kEps, 0});
    expectOverlap(h, clockwise(tri), false, {}, {kEps, 0});
  }
}

// ---------------------------------------------------------------------------------------------------------
// overlapsBox()

TEST(OverlapBox, EveryGeometryAgainstABox) {
  const Box box{{0, 0}, {2, 1}};
  auto check = [&](const Geometry& g, bool expected, Vec2 position = {}) {
    SCOPED_TRACE(describe(g, position));
    EXPECT_EQ(rattle::overlapsBox(g, position, box), expected);
  };
  check(Point{{2, 1}}, true);  // a corner
  check(Point{{1, 0.5}}, true);
  check(Point{{2 + kEps, 1}}, false);
  check(Circle{{3, 0.5}, 1}, true);  // touching the right side
  check(Circle{{3 + kEps, 0.5}, 1}, false);
  check(Circle{{3, 2}, 1}, false);  // near a corner: distance sqrt(2)
  check(Circle{{2, 2}, 1}, true);   // touching the corner (2, 1)
  check(Circle{{1, 0.5}, 10}, true);  // the box inside
  check(Segment{{2, 1}, {3, 2}}, true);  // end on the corner
  check(Segment{{2 + kEps, 1}, {3, 2}}, false);
  check(Segment{{-1, 0.5}, {3, 0.5}}, true);  // crossing
  check(Segment{{0.5, 0.25}, {1.5, 0.75}}, true);  // inside
  check(Segment{{1, 2}, {3, 0}}, true);      // x + y = 3: through the corner (2, 1)
  check(Segment{{1 + kEps, 2}, {3 + kEps, 0}}, false);  // only the segment's normal separates
  check(Polyline{{{3, 0}, {2, 0.5}, {3, 1}}}, true);
  check(Polyline{{{3, 0}, {2 + kEps, 0.5}, {3, 1}}}, false);
  check(Polyline{{{-1, -1}, {3, -1}, {3, 2}, {-1, 2}, {-1, -1}}}, false);  // a loop around the box
  check(square({2, 1}, {3, 2}), true);  // corner to corner
  check(square({2, 1 + kEps}, {3, 2}), false);
  check(square({0.5, 0.25}, {1, 0.5}), true);
  check(Polygon{{{1, 2}, {3, 0}, {3, 2}}}, true);  // hypotenuse x + y = 3 through the corner (2, 1)
  check(Polygon{{{1, 2}, {3, 0}, {3, 2}}}, false, {kEps, 0});
  check(Polygon{{{1, 2}, {3, 2}, {3, 0}}}, false, {kEps, 0});  // clockwise
  check(square({0, 0}, {1, 1}), true, {1, 0});  // placed by position: sharing the right half
}

TEST(OverlapBox, DegenerateAndEmptyBoxes) {
  const Box line{{0, 0}, {2, 0}};  // zero height: a segment
  EXPECT_TRUE(rattle::overlapsBox(Segment{{1, -1}, {1, 1}}, {}, line));
  EXPECT_TRUE(rattle::overlapsBox(Segment{{2, 0}, {3, 0}}, {}, line));  // collinear, end to end
  EXPECT_FALSE(rattle::overlapsBox(Segment{{2 + kEps, 0}, {3, 0}}, {}, line));
  EXPECT_FALSE(rattle::overlapsBox(Segment{{0, kEps}, {2, kEps}}, {}, line));
  EXPECT_TRUE(rattle::overlapsBox(Circle{{1, 1}, 1}, {}, line));
  EXPECT_TRUE(rattle::overlapsBox(square({-1, -1}, {1, 1}), {}, line));
  const Box dot{{1, 1}, {1, 1}};  // a point
  EXPECT_TRUE(rattle::overlapsBox(Segment{{0, 0}, {2, 2}}, {}, dot));
  EXPECT_FALSE(rattle::overlapsBox(Segment{{0, kEps}, {2, 2 + kEps}}, {}, dot));
  EXPECT_TRUE(rattle::overlapsBox(Point{{1, 1}}, {}, dot));
  EXPECT_TRUE(rattle::overlapsBox(Polygon{{{0, 0}, {2, 0}, {0, 2}}}, {}, dot));  // on the hypotenuse
  EXPECT_FALSE(rattle::overlapsBox(Polygon{{{0, 0}, {2, 0}, {0, 2}}}, {-kEps, 0}, dot));
  const Box empty{{1, 1}, {0, 0}};
  EXPECT_FALSE(rattle::overlapsBox(Circle{{0.5, 0.5}, 10}, {}, empty));
  EXPECT_FALSE(rattle::overlapsBox(Point{{0.5, 0.5}}, {}, empty));
  EXPECT_FALSE(rattle::overlapsBox(square({-5, -5}, {5, 5}), {}, empty));
}

// The box test agrees with overlaps() against the box as a polygon, for random geometries and boxes.
TEST(OverlapBox, AgreesWithTheBoxAsAPolygon) {
  Random r(7);
  int yes = 0, no = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto type = static_cast<GeometryType>(r.integer(1, 4));  // points never meet exactly
    const Geometry g = randomGeometry(r, type);
    const Vec2 position = r.vec(-2, 2);
    const Vec2 a = r.vec(-2, 2), b = a + r.vec(0.1, 2);
    const Box box{a, b};
    const RefShape gs = refShapeOf(g, position);
    const RefShape bs = refShapeOf(square(a, b), {});
    const Closest c = refCoreDistance(gs, bs);
    const double gap = c.distance - gs.radius;
    if (c.distance != 0 && std::fabs(gap) < 1e-9) continue;
    const bool expected = c.distance == 0 || gap <= 0;
    EXPECT_EQ(rattle::overlapsBox(g, position, box), expected) << describe(g, position);
    (expected ? yes : no)++;
  }
  EXPECT_GT(yes, 500);
  EXPECT_GT(no, 500);
}

// ---------------------------------------------------------------------------------------------------------
// overlaps(): random pairs against the brute-force distance

TEST(OverlapRandom, EveryPairAgreesWithTheReferenceDistance) {
  Random r(2024);
  std::array<std::array<int, 5>, 5> yes{}, no{};
  int skipped = 0, judged = 0;
  for (int i = 0; i < 15000; ++i) {
    const int ta = r.integer(0, 4), tb = r.integer(0, 4);
    const Geometry a = randomGeometry(r, static_cast<GeometryType>(ta));
    const Geometry b = randomGeometry(r, static_cast<GeometryType>(tb));
    const Vec2 pa = r.vec(-1.5, 1.5), pb = r.vec(-1.5, 1.5);
    const RefShape sa = refShapeOf(a, pa), sb = refShapeOf(b, pb);
    const Closest c = refCoreDistance(sa, sb);
    const double gap = c.distance - sa.radius - sb.radius;
    if (c.distance != 0 && std::fabs(gap) < 1e-9) {
      ++skipped;
      continue;
    }
    const bool expected = c.distance == 0 || gap <= 0;
    ++judged;
    (expected ? yes : no)[std::min(ta, tb)][std::max(ta, tb)]++;
    ASSERT_EQ(rattle::overlaps(a, pa, b, pb), expected)
        << describe(a, pa) << "  vs  " << describe(b, pb) << "  gap " << gap;
    ASSERT_EQ(rattle::overlaps(b, pb, a, pa), expected);
  }
  EXPECT_LT(skipped, judged / 100);
  // Both answers occur for every pair in which something has an area or both are curves (a random point
  // never lies exactly on a point, segment or polyline).
  for (int ta = 0; ta < 5; ++ta)
    for (int tb = ta; tb < 5; ++tb) {
      const bool pointOnCurve = ta == 0 && (tb == 0 || tb == 2 || tb == 3);
      if (!pointOnCurve) {
        EXPECT_GT(yes[ta][tb], 20) << ta << " " << tb;
        EXPECT_GT(no[ta][tb], 20) << ta << " " << tb;
      }
    }
}

// Random pairs moved along their closest-point direction to within +-1e-9 of touching: every pair of
// types must then be decided to the last few digits.
TEST(OverlapRandom, NearTouchingPairsAreDecidedExactly) {
  Random r(99);
  int yes = 0, no = 0, judged = 0;
  for (int i = 0; i < 8000; ++i) {
    const int ta = r.integer(0, 4), tb = r.integer(0, 4);
    const Geometry a = randomGeometry(r, static_cast<GeometryType>(ta));
    const Geometry b = randomGeometry(r, static_cast<GeometryType>(tb));
    const Vec2 pa = r.vec(-1.5, 1.5);
    Vec2 pb = r.vec(-1.5, 1.5);
    const RefShape sa = refShapeOf(a, pa), sb0 = refShapeOf(b, pb);
    const Closest c = refCoreDistance(sa, sb0);
    const double gap = c.distance - sa.radius - sb0.radius;
    if (!(gap > 1e-3)) continue;
    const Vec2 u = (1.0 / rattle::length(c.onA - c.onB)) * (c.onA - c.onB);  // from B toward A
    const double target = r.chance(0.5) ? 1e-9 : -1e-9;
    pb = pb + (gap - target) * u;
    const RefShape sb = refShapeOf(b, pb);
    const Closest c2 = refCoreDistance(sa, sb);
    const double gap2 = c2.distance - sa.radius - sb.radius;
    if (c2.distance != 0 && std::fabs(gap2) < 2e-10) continue;  // e.g. a point passing through a segment
    const bool expected = c2.distance == 0 || gap2 <= 0;
    ++judged;
    (expected ? yes : no)++;
    ASSERT_EQ(rattle::overlaps(a, pa, b, pb), expected)
        << describe(a, pa) << "  vs  " << describe(b, pb) << "  gap " << gap2;
    ASSERT_EQ(rattle::overlaps(b, pb, a, pa), expected);
  }
  EXPECT_GT(judged, 6000);
  EXPECT_GT(yes, 1500);
  EXPECT_GT(no, 1500);
}

// ---------------------------------------------------------------------------------------------------------
// rayCast(): hand-made cases

void expectHit(const std::optional<RayCastHit>& hit, double fraction, Vec2 normal, double tol = 1e-15) {
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->fraction, fraction, tol);
  EXPECT_NEAR(hit->normal.x, normal.x, 1e-15);
  EXPECT_NEAR(hit->normal.y, normal.y, 1e-15);
}

TEST(OverlapRayCast, Point) {
  const Geometry p = Point{{2, 1}};
  expectHit(rattle::rayCast(p, {}, {0, 0}, {4, 2}), 0.5, {-2 / std::sqrt(5.0), -1 / std::sqrt(5.0)});
  expectHit(rattle::rayCast(p, {}, {0, 0}, {2, 1}), 1.0, {-2 / std::sqrt(5.0), -1 / std::sqrt(5.0)});  // at the end
  expectHit(rattle::rayCast(p, {}, {2, 1}, {1, 0}), 0.0, {-1, 0});  // from the point itself
  EXPECT_FALSE(rattle::rayCast(Point{{2, 1 + kEps}}, {}, {0, 0}, {4, 2}));
  EXPECT_FALSE(rattle::rayCast(p, {}, {0, 0}, {1, 0.5}));  // stops short
  EXPECT_FALSE(rattle::rayCast(p, {}, {4, 2}, {2, 1}));    // behind
  expectHit(rattle::rayCast(Point{{0, 0}}, {2, 1}, {0, 0}, {4, 2}), 0.5, {-2 / std::sqrt(5.0), -1 / std::sqrt(5.0)});
  // Zero translation: only on the point.
  EXPECT_TRUE(rattle::rayCast(p, {}, {2, 1}, {0, 0}));
  EXPECT_FALSE(rattle::rayCast(p, {}, {2, 1 + kEps}, {0, 0}));
  // A circle of radius 0 is a point.
  expectHit(rattle::rayCast(Circle{{2, 1}, 0}, {}, {0, 0}, {4, 2}), 0.5, {-2 / std::sqrt(5.0), -1 / std::sqrt(5.0)});
  EXPECT_FALSE(rattle::rayCast(Circle{{2, 1 + kEps}, 0}, {}, {0, 0}, {4, 2}));
}

TEST(OverlapRayCast, Circle) {
  const Geometry c = Circle{{0, 0}, 1};
  expectHit(rattle::rayCast(c, {}, {-3, 0}, {4, 0}), 0.5, {-1, 0});
  expectHit(rattle::rayCast(c, {}, {0, 3}, {0, -2}), 1.0, {0, 1});  // reaches it at its end
  EXPECT_FALSE(rattle::rayCast(c, {}, {0, 3}, {0, -2 + kEps}));
  expectHit(rattle::rayCast(c, {}, {-3, 1}, {6, 0}), 0.5, {0, 1});  // tangent graze: closed set
  EXPECT_FALSE(rattle::rayCast(c, {}, {-3, 1 + kEps}, {6, 0}));
  EXPECT_FALSE(rattle::rayCast(c, {}, {3, 0}, {4, 0}));  // pointing away
  // Starting inside: fraction 0, normal against the direction.
  expectHit(rattle::rayCast(c, {}, {0.5, 0.25}, {0, 3}), 0.0, {0, -1});
  // Starting on the circle: moving in hits now with the surface normal; moving out is on it all the same.
  expectHit(rattle::rayCast(c, {}, {1, 0}, {-1, 1}), 0.0, {1, 0});
  expectHit(rattle::rayCast(c, {}, {1, 0}, {1, 0}), 0.0, {-1, 0});
  // Placed by position, and a slanted ray: 3-4-5.
  expectHit(rattle::rayCast(Circle{{0, 0}, 5}, {10, 10}, {10 - 6, 10 - 8}, {6, 8}), 0.5, {-0.6, -0.8});
  // Zero translation.
  EXPECT_TRUE(rattle::rayCast(c, {}, {0.5, 0.5}, {0, 0}));
  EXPECT_FALSE(rattle::rayCast(c, {}, {1 + kEps, 0}, {0, 0}));
  // From a point just outside, the near root is tiny and comes out without cancellation.
  // |m|^2 - r^2 is computed without cancellation too: the fraction is right to a few ulps.
  for (double x : {-1 - 1e-12, -1 - 3e-15, -1.0000001}) {
    const auto near = rattle::rayCast(c, {}, {x, 0}, {2, 0});
    ASSERT_TRUE(near);
    const double expected = (-x - 1) / 2;  // -x - 1 is exact (Sterbenz)
    EXPECT_NEAR(near->fraction, expected, 4 * std::fabs(expected) * 0x1p-52) << x;
  }
  // Slanted: the origin (-3, -4) (1 + 2^-40) is exactly 5 * 2^-40 outside the circle of radius 5, straight
  // towards its centre, so the ray (3, 4) (length 5) hits at exactly 2^-40.
  const double s = 1 + 0x1p-40;
  const auto slanted = rattle::rayCast(Circle{{0, 0}, 5}, {}, {-3 * s, -4 * s}, {3, 4});
  ASSERT_TRUE(slanted);
  EXPECT_NEAR(slanted->fraction, 0x1p-40, 4 * 0x1p-40 * 0x1p-52);
}

TEST(OverlapRayCast, Segment) {
  const Geometry s = Segment{{0, -1}, {0, 1}};
  expectHit(rattle::rayCast(s, {}, {-2, 0}, {4, 0}), 0.5, {-1, 0});  // from the left
  expectHit(rattle::rayCast(s, {}, {2, 0}, {-4, 0}), 0.5, {1, 0});   // from the right: both sides
  expectHit(rattle::rayCast(s, {}, {-2, 1}, {4, 0}), 0.5, {-1, 0});  // through an end: ends count
  EXPECT_FALSE(rattle::rayCast(s, {}, {-2, 1 + kEps}, {4, 0}));
  EXPECT_FALSE(rattle::rayCast(s, {}, {-2, 0}, {2 - kEps, 0}));  // stops short
  expectHit(rattle::rayCast(s, {}, {-2, 0}, {2, 0}), 1.0, {-1, 0});
  // Slanted, both sides: the normal faces the ray.
  const Geometry d = Segment{{0, 0}, {2, 2}};
  const double h = 1 / std::sqrt(2.0);
  expectHit(rattle::rayCast(d, {}, {0, 2}, {2, -2}), 0.5, {-h, h});
  expectHit(rattle::rayCast(d, {}, {2, 0}, {-2, 2}), 0.5, {h, -h});
  // Along the segment's line: meets the nearer end, end-on; from on the segment: at 0.
  expectHit(rattle::rayCast(s, {}, {0, -3}, {0, 4}), 0.5, {0, -1});
  expectHit(rattle::rayCast(s, {}, {0, 3}, {0, -4}), 0.5, {0, 1});
  expectHit(rattle::rayCast(s, {}, {0, 0.5}, {0, 4}), 0.0, {0, -1});
  EXPECT_FALSE(rattle::rayCast(s, {}, {0, -3}, {0, 2 - kEps}));
  EXPECT_FALSE(rattle::rayCast(s, {}, {kEps, -3}, {0, 4}));
  // Starting on the segment, crossing it: at 0, normal facing where it came from.
  expectHit(rattle::rayCast(s, {}, {0, 0.5}, {1, 0}), 0.0, {-1, 0});
  // Zero translation.
  EXPECT_TRUE(rattle::rayCast(s, {}, {0, 1}, {0, 0}));
  EXPECT_FALSE(rattle::rayCast(s, {}, {0, 1 + kEps}, {0, 0}));
  // Placed by position.
  expectHit(rattle::rayCast(s, {5, 5}, {3, 5}, {4, 0}), 0.5, {-1, 0});
}

TEST(OverlapRayCast, Polyline) {
  const Geometry l = Polyline{{{0, 0}, {2, 0}, {2, 2}, {4, 2}}};
  expectHit(rattle::rayCast(l, {}, {1, 3}, {0, -4}), 0.75, {0, 1});  // only segment 0 is in the way
  expectHit(rattle::rayCast(l, {}, {5, 1}, {-8, 0}), 0.375, {1, 0});  // the nearest of the segments
  // The corner (2, 0) ends segments 0 and 1 at the same fraction: the lower index, segment 0, wins.
  expectHit(rattle::rayCast(l, {}, {3, -1}, {-2, 2}), 0.5, {0, -1});
  EXPECT_FALSE(rattle::rayCast(l, {}, {1, 1}, {0.5, 0.5}));  // in the bend
  expectHit(rattle::rayCast(l, {}, {6, 2}, {-4, 0}), 0.5, {1, 0});  // along the last segment: end-on
}

TEST(OverlapRayCast, Polygon) {
  for (const Polygon& g : {square({0, 0}, {2, 2}), clockwise(square({0, 0}, {2, 2}))}) {
    expectHit(rattle::rayCast(g, {}, {-2, 1}, {4, 0}), 0.5, {-1, 0});
    expectHit(rattle::rayCast(g, {}, {1, 4}, {0, -4}), 0.5, {0, 1});
    expectHit(rattle::rayCast(g, {}, {1, 1}, {4, 0}), 0.0, {-1, 0});  // from inside
    expectHit(rattle::rayCast(g, {}, {-2, 2}, {4, 0}), 0.5, {-1, 0});  // along the top edge: grazes it
    EXPECT_FALSE(rattle::rayCast(g, {}, {-2, 2 + kEps}, {4, 0}));
    // Into the corner (0, 2), entering the top and left edges at once: the lower edge index, the top.
    expectHit(rattle::rayCast(g, {}, {-1, 3}, {2, -2}), 0.5, {0, 1});
    // Grazing the corner (0, 2) from the left and leaving upward: enters the left edge's half-plane as it
    // leaves the top edge's, and touches; 1e-9 higher it misses.
    expectHit(rattle::rayCast(g, {}, {-1, 1}, {2, 2}), 0.5, {-1, 0});
    EXPECT_FALSE(rattle::rayCast(g, {}, {-1, 1 + kEps}, {2, 2}));
    EXPECT_FALSE(rattle::rayCast(g, {}, {-2, 1}, {2 - kEps, 0}));  // stops short
    expectHit(rattle::rayCast(g, {}, {-2, 1}, {2, 0}), 1.0, {-1, 0});
    EXPECT_FALSE(rattle::rayCast(g, {}, {3, 1}, {4, 0}));  // pointing away
    expectHit(rattle::rayCast(g, {}, {0, 1}, {1, 0}), 0.0, {-1, 0});  // on an edge moving in: the edge normal
    expectHit(rattle::rayCast(g, {}, {2, 1}, {1, 0}), 0.0, {-1, 0});  // on an edge moving out: on it anyway
    EXPECT_TRUE(rattle::rayCast(g, {}, {2, 2}, {0, 0}));
    EXPECT_FALSE(rattle::rayCast(g, {}, {2, 2 + kEps}, {0, 0}));
    expectHit(rattle::rayCast(g, {10, 0}, {6, 1}, {8, 0}), 0.5, {-1, 0});
  }
  // A slanted edge: triangle (0,0), (4,0), (0,4); the hypotenuse's outward normal is (1, 1)/sqrt(2).
  const double h = 1 / std::sqrt(2.0);
  expectHit(rattle::rayCast(Polygon{{{0, 0}, {4, 0}, {0, 4}}}, {}, {4, 4}, {-4, -4}), 0.5, {h, h});
}

TEST(OverlapRayCast, HugeAndTinyTranslations) {
  // Scaled by powers of two inside, so |translation|^2 neither overflows nor underflows.
  expectHit(rattle::rayCast(Circle{{0, 0}, 1}, {}, {-3, 0}, {4e200, 0}), 2.0 / 4e200, {-1, 0}, 1e-214);
  expectHit(rattle::rayCast(Point{{1e-200, 0}}, {}, {0, 0}, {4e-200, 0}), 0.25, {-1, 0});
  expectHit(rattle::rayCast(Segment{{1, -1}, {1, 1}}, {}, {0, 0}, {1e300, 1e300}), 1e-300, {-1, 0}, 1e-314);
  expectHit(rattle::rayCast(square({1, -1}, {3, 1}), {}, {0, 0}, {1e300, 0}), 1e-300, {-1, 0}, 1e-314);
}

// ---------------------------------------------------------------------------------------------------------
// rayCast(): random rays against sphere tracing

struct TraceResult {
  enum Kind { Hit, Miss, Undecided } kind;
  double fraction = 0;
};

// Sphere tracing: from t, the ball of radius dist(x(t)) holds nothing of the shape, so the ray may advance
// by that distance and never pass the first contact.
TraceResult sphereTrace(const RefShape& s, Vec2 origin, Vec2 translation) {
  const double len = rattle::length(translation);
  double t = 0;
  for (int i = 0; i < 20000; ++i) {
    const double d = refDistance(s, origin + t * translation);
    if (d <= 1e-13) return {t > 1 - 1e-9 || (t > 0 && t < 1e-9) ? TraceResult::Undecided : TraceResult::Hit, t};
    const double next = t + d / len;
    if (next > 1) {
      // Nothing within d of x(t), which covers the rest of the ray; a near miss at the end is not judged.
      return {d < 1e-7 ? TraceResult::Undecided : TraceResult::Miss, 1};
    }
    t = next;
  }
  return {TraceResult::Undecided, t};
}

TEST(OverlapRayCast, RandomRaysAgreeWithSphereTracing) {
  Random r(31337);
  std::array<int, 5> hits{}, misses{}, inside{};
  int undecided = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto type = static_cast<GeometryType>(r.integer(1, 4));  // points are hit only exactly
    const Geometry g = randomGeometry(r, type);
    const Vec2 position = r.vec(-1, 1);
    const RefShape s = refShapeOf(g, position);
    const Vec2 origin = r.vec(-4, 4);
    // Aim near the shape half of the time.
    const Vec2 target = r.chance(0.5) ? s.points[0] + r.vec(-1, 1) : r.vec(-4, 4);
    const Vec2 translation = r.uniform(0.5, 2.0) * (target - origin);
    const TraceResult ref = sphereTrace(s, origin, translation);
    if (ref.kind == TraceResult::Undecided) {
      ++undecided;
      continue;
    }
    const auto hit = rattle::rayCast(g, position, origin, translation);
    SCOPED_TRACE(describe(g, position) + "  ray " + rattle::detail::str(origin) + " + t " +
                 rattle::detail::str(translation));
    const int k = static_cast<int>(type);
    if (ref.kind == TraceResult::Miss) {
      ASSERT_FALSE(hit.has_value()) << "fraction " << hit->fraction;
      ++misses[k];
      continue;
    }
    ASSERT_TRUE(hit.has_value()) << "reference fraction " << ref.fraction;
    EXPECT_NEAR(hit->fraction, ref.fraction, 1e-9);
    EXPECT_NEAR(rattle::length(hit->normal), 1.0, 1e-15);
    EXPECT_LE(rattle::dot(hit->normal, translation), 0.0);
    const Vec2 expectedPoint = origin + hit->fraction * translation;
    EXPECT_EQ(hit->point, expectedPoint);
    EXPECT_LT(refDistance(s, hit->point), 1e-12);
    if (ref.fraction == 0) {
      // From inside: against the direction.
      const Vec2 against = (-1.0 / rattle::length(translation)) * translation;
      EXPECT_NEAR(hit->normal.x, against.x, 1e-15);
      EXPECT_NEAR(hit->normal.y, against.y, 1e-15);
      ++inside[k];
    } else {
      // From outside: a step back along the normal leaves the shape, and for a circle it is radial.
      EXPECT_GT(refDistance(s, hit->point + 1e-6 * hit->normal), 0.5e-6);
      if (auto* c = std::get_if<Circle>(&g)) {
        const Vec2 radial = (1.0 / c->radius) * (hit->point - (c->center + position));
        EXPECT_NEAR(hit->normal.x, radial.x, 1e-9);
        EXPECT_NEAR(hit->normal.y, radial.y, 1e-9);
      }
      ++hits[k];
    }
  }
  EXPECT_LT(undecided, 200);
  for (int k = 1; k <= 4; ++k) {
    EXPECT_GT(hits[k], 500) << k;
    EXPECT_GT(misses[k], 1000) << k;
  }
  EXPECT_GT(inside[1], 30);
  EXPECT_GT(inside[4], 50);
}

// ---------------------------------------------------------------------------------------------------------
// World queries

using rattle::BodyId;
using rattle::BodyType;
using rattle::FixtureDef;
using rattle::FixtureId;
using rattle::QueryFilter;
using rattle::RayHit;
using rattle::World;

BodyId makeBody(World& w, BodyType type, Vec2 position) {
  rattle::BodyDef d;
  d.type = type;
  d.position = position;
  return w.createBody(d);
}

FixtureId addFixture(World& w, BodyId body, const Geometry& g, bool sensor = false, uint32_t category = 1,
                     uint32_t mask = 0xFFFFFFFF) {
  FixtureDef d;
  d.geometry = g;
  d.sensor = sensor;
  d.filter.categoryBits = category;
  d.filter.maskBits = mask;
  return w.createFixture(body, d);
}

QueryFilter queryFilter(uint32_t category = 1, uint32_t mask = 0xFFFFFFFF, bool includeSensors = false) {
  QueryFilter q;
  q.categoryBits = category;
  q.maskBits = mask;
  q.includeSensors = includeSensors;
  return q;
}

struct Scene {
  World world;
  std::vector<FixtureId> fixtures;  // every fixture ever made, live or not
};

void buildRandomScene(Scene& s, Random& r) {
  World& w = s.world;
  auto filterBits = [&](FixtureDef& d) {
    d.filter.categoryBits = 1u << r.integer(0, 3);
    d.filter.maskBits = r.chance(0.5) ? 0xFFFFFFFFu : static_cast<uint32_t>(r.integer(0, 15));
    d.sensor = r.chance(0.15);
  };
  std::vector<BodyId> bodies;
  for (int i = 0; i < 40; ++i) {
    const BodyType type = i % 4 == 0 ? BodyType::Dynamic : (i % 9 == 0 ? BodyType::Kinematic : BodyType::Static);
    const BodyId b = makeBody(w, type, r.vec(-10, 10));
    bodies.push_back(b);
    const int n = r.integer(1, 3);
    for (int k = 0; k < n; ++k) {
      FixtureDef d;
      filterBits(d);
      if (type == BodyType::Dynamic) {
        d.geometry = r.chance(0.2) ? Geometry(Point{{0, 0}}) : Geometry(Circle{{0, 0}, r.uniform(0.1, 1.5)});
      } else {
        d.geometry = randomGeometry(r, static_cast<GeometryType>(r.integer(0, 4)), 2.0);
      }
      s.fixtures.push_back(w.createFixture(b, d));
    }
  }
  // Dead slots and reused ones: fixture indices no longer follow creation order.
  w.destroyFixture(s.fixtures[3]);
  w.destroyFixture(s.fixtures[10]);
  w.destroyBody(bodies[5]);
  for (int i = 0; i < 4; ++i) {
    FixtureDef d;
    filterBits(d);
    d.geometry = randomGeometry(r, GeometryType::Polygon, 2.0);
    s.fixtures.push_back(w.createFixture(bodies[2 + 4 * i + 1], d));
  }
  // Move some bodies after their fixtures were made: queries see where bodies are now.
  for (int i = 0; i < 40; i += 3)
    if (w.isValid(bodies[i])) w.setPosition(bodies[i], r.vec(-10, 10));
}

bool seenByFilter(const World& w, FixtureId f, const QueryFilter& q) {
  const rattle::Filter fl = w.filter(f);
  if (w.isSensor(f) && !q.includeSensors) return false;
  return (fl.categoryBits & q.maskBits) != 0 && (q.categoryBits & fl.maskBits) != 0;
}

QueryFilter randomQueryFilter(Random& r) {
  if (r.chance(0.3)) return queryFilter(1, 0xFFFFFFFF, r.chance(0.5));
  return queryFilter(1u << r.integer(0, 3), static_cast<uint32_t>(r.integer(0, 15)), r.chance(0.5));
}

// The live fixtures sorted by index, from the scene's own list.
std::vector<FixtureId> liveFixtures(const Scene& s) {
  std::vector<FixtureId> live;
  for (FixtureId f : s.fixtures)
    if (s.world.isValid(f)) live.push_back(f);
  std::sort(live.begin(), live.end(), [](FixtureId a, FixtureId b) { return a.index < b.index; });
  return live;
}

TEST(QueryWorld, RandomRayCastsMatchBruteForce) {
  Random r(5);
  Scene s;
  buildRandomScene(s, r);
  const std::vector<FixtureId> live = liveFixtures(s);
  const World& w = s.world;
  int total = 0, multi = 0;
  for (int q = 0; q < 400; ++q) {
    const QueryFilter filter = randomQueryFilter(r);
    const Vec2 origin = r.vec(-12, 12);
    // Aim at a fixture's body now and then, or a zero translation.
    Vec2 translation = r.chance(0.5) ? 2.0 * (w.position(w.body(live[r.integer(0, static_cast<int>(live.size()) - 1)])) - origin)
                                     : r.vec(-20, 20);
    if (q % 50 == 0) translation = {};
    std::vector<RayHit> expected;
    for (FixtureId f : live) {
      if (!seenByFilter(w, f, filter)) continue;
      const BodyId b = w.body(f);
      if (auto hit = rattle::rayCast(w.geometry(f), w.position(b), origin, translation))
        expected.push_back(RayHit{f, b, hit->point, hit->normal, hit->fraction});
    }
    std::sort(expected.begin(), expected.end(), [](const RayHit& x, const RayHit& y) {
      return x.fraction != y.fraction ? x.fraction < y.fraction : x.fixture.index < y.fixture.index;
    });
    const std::vector<RayHit> all = w.rayCastAll(origin, translation, filter);
    ASSERT_EQ(all.size(), expected.size()) << "query " << q;
    for (size_t i = 0; i < all.size(); ++i) {
      EXPECT_EQ(all[i].fixture, expected[i].fixture);
      EXPECT_EQ(all[i].body, expected[i].body);
      EXPECT_EQ(all[i].fraction, expected[i].fraction);
      EXPECT_EQ(all[i].point, expected[i].point);
      EXPECT_EQ(all[i].normal, expected[i].normal);
    }
    const std::optional<RayHit> first = w.rayCastFirst(origin, translation, filter);
    ASSERT_EQ(first.has_value(), !expected.empty());
    if (first) {
      EXPECT_EQ(first->fixture, expected[0].fixture);
      EXPECT_EQ(first->fraction, expected[0].fraction);
      EXPECT_EQ(first->point, expected[0].point);
    }
    total += static_cast<int>(all.size());
    multi += all.size() >= 2;
  }
  EXPECT_GT(total, 300);
  EXPECT_GT(multi, 50);
}

TEST(QueryWorld, RandomOverlapsMatchBruteForce) {
  Random r(6);
  Scene s;
  buildRandomScene(s, r);
  const std::vector<FixtureId> live = liveFixtures(s);
  const World& w = s.world;
  auto expectSame = [](const std::vector<FixtureId>& got, const std::vector<FixtureId>& expected, int q) {
    ASSERT_EQ(got.size(), expected.size()) << "query " << q;
    for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], expected[i]) << "query " << q;
  };
  int boxes = 0, circles = 0, points = 0;
  for (int q = 0; q < 300; ++q) {
    const QueryFilter filter = randomQueryFilter(r);
    // Box.
    const Vec2 a = r.vec(-12, 12);
    const Box box{a, a + (q % 25 == 0 ? Vec2{r.uniform(0, 4), 0} : r.vec(0, 6))};
    std::vector<FixtureId> expected;
    for (FixtureId f : live)
      if (seenByFilter(w, f, filter) && rattle::overlapsBox(w.geometry(f), w.position(w.body(f)), box))
        expected.push_back(f);
    expectSame(w.overlapBox(box, filter), expected, q);
    boxes += static_cast<int>(expected.size());
    // Circle.
    const Vec2 c = r.vec(-12, 12);
    const double radius = q % 30 == 0 ? 0.0 : r.uniform(0, 4);
    expected.clear();
    for (FixtureId f : live)
      if (seenByFilter(w, f, filter) && rattle::overlaps(Circle{c, radius}, {}, w.geometry(f), w.position(w.body(f))))
        expected.push_back(f);
    expectSame(w.overlapCircle(c, radius, filter), expected, q);
    circles += static_cast<int>(expected.size());
    // Point: anywhere, or exactly on a Point fixture or a body's position.
    Vec2 p = r.vec(-12, 12);
    const FixtureId pick = live[r.integer(0, static_cast<int>(live.size()) - 1)];
    if (r.chance(0.5)) {
      p = w.position(w.body(pick));
      if (auto* pt = std::get_if<Point>(&w.geometry(pick))) p = pt->position + p;
    }
    expected.clear();
    for (FixtureId f : live)
      if (seenByFilter(w, f, filter) && rattle::overlaps(Point{p}, {}, w.geometry(f), w.position(w.body(f))))
        expected.push_back(f);
    expectSame(w.overlapPoint(p, filter), expected, q);
    points += static_cast<int>(expected.size());
  }
  EXPECT_GT(boxes, 200);
  EXPECT_GT(circles, 200);
  EXPECT_GT(points, 50);
}

TEST(QueryWorld, FiltersAndSensors) {
  World w;
  const BodyId b = makeBody(w, BodyType::Static, {0, 0});
  const FixtureId plain = addFixture(w, b, Circle{{0, 0}, 1});
  const FixtureId sensor = addFixture(w, b, Circle{{0, 0}, 1}, true);
  const FixtureId cat2 = addFixture(w, b, Circle{{0, 0}, 1}, false, 2);
  const FixtureId masksOut1 = addFixture(w, b, Circle{{0, 0}, 1}, false, 1, ~1u);
  auto ids = [](const std::vector<FixtureId>& v) {
    std::vector<uint32_t> out;
    for (FixtureId f : v) out.push_back(f.index);
    return out;
  };
  using V = std::vector<uint32_t>;
  EXPECT_EQ(ids(w.overlapPoint({0, 0})), (V{plain.index, cat2.index}));
  EXPECT_EQ(ids(w.overlapPoint({0, 0}, queryFilter(1, 0xFFFFFFFF, true))), (V{plain.index, sensor.index, cat2.index}));
  EXPECT_EQ(ids(w.overlapPoint({0, 0}, queryFilter(1, 2))), (V{cat2.index}));  // only category 2 wanted
  // A query of category 2 is seen by the fixture that masks out category 1.
  EXPECT_EQ(ids(w.overlapPoint({0, 0}, queryFilter(2, 0xFFFFFFFF))), (V{plain.index, cat2.index, masksOut1.index}));
  EXPECT_TRUE(w.overlapPoint({0, 0}, queryFilter(1, 0)).empty());
  EXPECT_EQ(w.rayCastAll({-5, 0}, {10, 0}).size(), 2u);
  EXPECT_EQ(w.rayCastAll({-5, 0}, {10, 0}, queryFilter(1, 0xFFFFFFFF, true)).size(), 3u);
  EXPECT_EQ(ids(w.overlapBox({{0.5, 0.5}, {3, 3}})), (V{plain.index, cat2.index}));
  EXPECT_EQ(ids(w.overlapCircle({2, 0}, 1)), (V{plain.index, cat2.index}));  // touching
  EXPECT_TRUE(w.overlapCircle({2 + kEps, 0}, 1).empty());
}

TEST(QueryWorld, RayResultsAreSortedByFractionThenIndex) {
  World w;
  const BodyId a = makeBody(w, BodyType::Static, {0, 0});
  const FixtureId far = addFixture(w, a, Segment{{6, -1}, {6, 1}});
  const FixtureId doomed = addFixture(w, a, Segment{{9, -1}, {9, 1}});
  const FixtureId near = addFixture(w, a, Segment{{3, -1}, {3, 1}});
  w.destroyFixture(doomed);
  // Reuses the freed slot: created last, lowest index but one; it ties with `far`.
  const BodyId b = makeBody(w, BodyType::Static, {6, 0});
  const FixtureId twin = addFixture(w, b, Segment{{0, -1}, {0, 1}});
  ASSERT_EQ(twin.index, doomed.index);
  const BodyId disk = makeBody(w, BodyType::Dynamic, {8, 0});
  const FixtureId round = addFixture(w, disk, Circle{{0, 0}, 1});
  const std::vector<RayHit> all = w.rayCastAll({0, 0}, {10, 0});
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[0].fixture, near);
  EXPECT_DOUBLE_EQ(all[0].fraction, 0.3);
  EXPECT_EQ(all[1].fixture, far);  // index 0
  EXPECT_EQ(all[2].fixture, twin);  // index 1, same fraction
  EXPECT_EQ(all[1].fraction, all[2].fraction);
  EXPECT_EQ(all[2].body, b);
  EXPECT_EQ(all[3].fixture, round);
  EXPECT_EQ(all[3].body, disk);
  EXPECT_NEAR(all[3].point.x, 7, 1e-14);
  EXPECT_EQ(all[3].point.y, 0);
  EXPECT_EQ(all[3].normal, (Vec2{-1, 0}));
  const auto first = w.rayCastFirst({4, 0}, {10, 0});
  ASSERT_TRUE(first);
  EXPECT_EQ(first->fixture, far);  // the tie goes to the lower index
  // A dynamic body moved with setPosition is found where it is now.
  w.setPosition(disk, {0, 5});
  EXPECT_TRUE(w.rayCastAll({0, 0}, {10, 0}).size() == 3u);
  const auto down = w.rayCastFirst({0, 10}, {0, -10});
  ASSERT_TRUE(down);
  EXPECT_EQ(down->fixture, round);
  EXPECT_DOUBLE_EQ(down->fraction, 0.4);
  EXPECT_EQ(w.overlapPoint({0, 5}), std::vector<FixtureId>{round});
  // Empty world parts: a ray that meets nothing.
  EXPECT_FALSE(w.rayCastFirst({0, -5}, {10, 0}));
  EXPECT_TRUE(w.rayCastAll({0, -5}, {10, 0}).empty());
}

// Runs `call` and expects a rattle::Error whose message contains every one of `words`.
template <class Call>
void expectError(Call&& call, std::vector<std::string> words) {
  try {
    call();
    ADD_FAILURE() << "no rattle::Error thrown; expected one mentioning " << words[0];
  } catch (const rattle::Error& e) {
    const std::string message = e.what();
    for (const std::string& word : words) EXPECT_NE(message.find(word), std::string::npos) << message;
  }
}

TEST(QueryWorld, InvalidArgumentsAreRejected) {
  World w;
  const BodyId b = makeBody(w, BodyType::Static, {0, 0});
  addFixture(w, b, Circle{{0, 0}, 1});
  using rattle::detail::str;
  expectError([&] { w.rayCastFirst({kNaN, 0}, {1, 0}); }, {"origin", str(kNaN)});
  expectError([&] { w.rayCastAll({0, 0}, {kInf, 0}); }, {"translation", str(kInf)});
  expectError([&] { w.rayCastAll({0, -kInf}, {1, 0}); }, {"origin", str(-kInf)});
  expectError([&] { w.rayCastFirst({1e308, 0}, {1e308, 0}); }, {"translation", "overflows", str(1e308)});
  expectError([&] { w.overlapBox({{kNaN, 0}, {1, 1}}); }, {"box.min", str(kNaN)});
  expectError([&] { w.overlapBox({{0, 0}, {1, kInf}}); }, {"box.max", str(kInf)});
  expectError([&] { w.overlapBox({{2, 0}, {1, 1}}); }, {"box.min", "box.max", str(2.0), "min"});
  expectError([&] { w.overlapBox({{0, 3}, {1, 1}}); }, {"box.min", str(3.0)});
  expectError([&] { w.overlapCircle({0, kNaN}, 1); }, {"center", str(kNaN)});
  expectError([&] { w.overlapCircle({0, 0}, -1); }, {"radius", str(-1.0)});
  expectError([&] { w.overlapCircle({0, 0}, kNaN); }, {"radius", str(kNaN)});
  expectError([&] { w.overlapCircle({0, 0}, kInf); }, {"radius", str(kInf)});
  expectError([&] { w.overlapPoint({kInf, 0}); }, {"point", str(kInf)});
  // Boundary values are fine: a zero translation, a zero radius, a box of zero size.
  EXPECT_TRUE(w.rayCastFirst({0.5, 0}, {0, 0}));
  EXPECT_FALSE(w.rayCastFirst({1.5, 0}, {0, 0}));
  EXPECT_EQ(w.overlapCircle({1, 0}, 0).size(), 1u);
  EXPECT_EQ(w.overlapBox({{1, 0}, {1, 0}}).size(), 1u);
  EXPECT_TRUE(w.overlapBox({{1 + kEps, 0}, {1 + kEps, 0}}).empty());
}

}  // namespace
