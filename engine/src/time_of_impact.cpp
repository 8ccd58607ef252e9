// Exact times of impact for a circle in linear motion against each geometry, and the dispatch table.
//
// All functions work in B's frame (B at rest) and follow the rules in time_of_impact.h. Two kernels do
// the work: a circle against a circle (a quadratic in t) and a circle against one edge line (linear in
// t); segments, polylines and polygons are made of those, taking the earliest impact and, on equal
// times, the lowest feature index, so ties resolve the same way on every run.
#include "rattle/time_of_impact.h"

#include <cmath>

namespace rattle {
namespace {

// b^2 - a*c as Kahan's compensated 2x2 determinant: with w = a*c rounded, e = w - a*c is exact (one
// fma), so b^2 - a*c = (b^2 - w) + (w - a*c) loses nothing to cancellation. Error <= 1.5 ulp for exact
// inputs (Jeannerod, Louvet, Muller, Math. Comp. 82, 2013). std::fma is correctly rounded by IEEE 754,
// so this is the same on every build, with or without hardware FMA.
double discriminant(double b, double a, double c) {
  const double w = a * c;
  const double e = std::fma(-a, c, w);
  const double f = std::fma(b, b, -w);
  return f + e;
}

// First time the distance between two centres, r + v t, closes to `reach` while approaching.
// f(t) = |r + v t|^2 - reach^2 = A t^2 + 2 b t + c with A = v.v, b = r.v, c = r.r - reach^2.
std::optional<double> timeToReach(Vec2 r, Vec2 v, double reach, double maxTime) {
  const double c = dot(r, r) - reach * reach;
  const double b = dot(r, v);
  if (c <= 0) {
    // Touching or overlapping (by round-off, or because bodies were placed so): the sign of f'(0) = 2b
    // decides. Approaching collides now; separating or sliding gets no event (Bannerman et al. 2014).
    if (b < 0) return 0.0;
    return std::nullopt;
  }
  if (b >= 0) return std::nullopt;
  const double disc = discriminant(b, dot(v, v), c);
  // disc == 0 is a tangent touch, a double root: not an event.
  if (!(disc > 0)) return std::nullopt;
  // The smaller root (-b - sqrt(disc)) / A cancels when c -> 0; its conjugate form has a sum of two
  // positive terms below: t = c / (-b + sqrt(disc)).
  const double t = c / (-b + std::sqrt(disc));
  if (!(t <= maxTime)) return std::nullopt;
  return t;
}

Impact pointImpact(Vec2 center, Vec2 velocity, Vec2 target, double targetRadius, double t, int feature) {
  Vec2 r = center + velocity * t - target;
  double len = length(r);
  // Coincident centres happen only for two points; push back along the motion then.
  Vec2 n = len > 0 ? r * (1.0 / len) : (length(velocity) > 0 ? -velocity * (1.0 / length(velocity)) : Vec2{1, 0});
  return Impact{t, target + n * targetRadius, n, feature};
}

struct Edge {
  Vec2 a;
  Vec2 u;  // unit direction from a along the edge
  Vec2 n;  // unit normal on the side that collides
  double length;
};

Edge edgeOf(Vec2 a, Vec2 b) {
  Vec2 d = b - a;
  double len = length(d);
  Vec2 u = d * (1.0 / len);
  // Outward normal of a counter-clockwise polygon's edge: the edge direction turned clockwise.
  return Edge{a, u, Vec2{u.y, -u.x}, len};
}

// The circle against the inside of one edge, from the side `edge.n` points to. Linear: the signed
// distance s(t) = n.(c - a) + (n.v) t reaches r at t = (s0 - r) / -(n.v). The impact counts only if the
// contact point then lies on the edge (0 <= tau <= length): an edge's ends are not corners.
std::optional<Impact> edgeImpact(const Circle& circle, Vec2 v, const Edge& edge, double maxTime, int feature) {
  const Vec2 rel = circle.center - edge.a;
  const double s0 = dot(edge.n, rel);
  const double vn = dot(edge.n, v);
  if (!(vn < 0)) return std::nullopt;  // moving away from the line or along it
  const double gap = s0 - circle.radius;
  double t;
  if (gap >= 0) {
    t = gap / -vn;
    if (!(t <= maxTime)) return std::nullopt;
  } else if (s0 > -circle.radius) {
    t = 0.0;  // overlapping the edge and approaching: collide now
  } else {
    return std::nullopt;  // the centre is a full radius behind the line: nothing to meet
  }
  const double tau = dot(edge.u, rel) + dot(edge.u, v) * t;
  if (tau < 0 || tau > edge.length) return std::nullopt;
  return Impact{t, edge.a + edge.u * tau, edge.n, feature};
}

void keepEarlier(std::optional<Impact>& best, const std::optional<Impact>& candidate) {
  if (candidate && (!best || candidate->time < best->time)) best = candidate;
}

// A segment collides on both sides: face the side the centre is on. A centre exactly on the line is
// moving along or away from it in the sense of f = s^2 - r^2 (f'(0) = 0): no event.
std::optional<Impact> segmentImpact(const Circle& a, Vec2 v, Vec2 p0, Vec2 p1, double maxTime, int feature) {
  Edge edge = edgeOf(p0, p1);
  const double s0 = dot(edge.n, a.center - edge.a);
  if (s0 == 0) return std::nullopt;
  if (s0 < 0) edge.n = -edge.n;
  return edgeImpact(a, v, edge, maxTime, feature);
}

}  // namespace

std::optional<Impact> timeOfImpactCircleCircle(const Circle& a, Vec2 velocity, const Circle& b, double maxTime,
                                               int excludedFeature) {
  if (excludedFeature == 0) return std::nullopt;
  auto t = timeToReach(a.center - b.center, velocity, a.radius + b.radius, maxTime);
  if (!t) return std::nullopt;
  return pointImpact(a.center, velocity, b.center, b.radius, *t, 0);
}

std::optional<Impact> timeOfImpactCirclePoint(const Circle& a, Vec2 velocity, const Point& b, double maxTime,
                                              int excludedFeature) {
  if (excludedFeature == 0) return std::nullopt;
  auto t = timeToReach(a.center - b.position, velocity, a.radius, maxTime);
  if (!t) return std::nullopt;
  return pointImpact(a.center, velocity, b.position, 0.0, *t, 0);
}

std::optional<Impact> timeOfImpactCircleSegment(const Circle& a, Vec2 velocity, const Segment& b, double maxTime,
                                                int excludedFeature) {
  if (excludedFeature == 0) return std::nullopt;
  return segmentImpact(a, velocity, b.a, b.b, maxTime, 0);
}

std::optional<Impact> timeOfImpactCirclePolyline(const Circle& a, Vec2 velocity, const Polyline& b, double maxTime,
                                                 int excludedFeature) {
  const int n = static_cast<int>(b.points.size());
  std::optional<Impact> best;
  for (int i = 0; i + 1 < n; ++i) {
    if (i == excludedFeature) continue;
    keepEarlier(best, segmentImpact(a, velocity, b.points[i], b.points[i + 1], maxTime, i));
  }
  for (int k = 0; k < n; ++k) {
    const int feature = n - 1 + k;
    if (feature == excludedFeature) continue;
    if (auto t = timeToReach(a.center - b.points[k], velocity, a.radius, maxTime))
      keepEarlier(best, pointImpact(a.center, velocity, b.points[k], 0.0, *t, feature));
  }
  return best;
}

std::optional<Impact> timeOfImpactCirclePolygon(const Circle& a, Vec2 velocity, const Polygon& b, double maxTime,
                                                int excludedFeature) {
  const int n = static_cast<int>(b.points.size());
  std::optional<Impact> best;
  for (int i = 0; i < n; ++i) {
    if (i == excludedFeature) continue;
    keepEarlier(best, edgeImpact(a, velocity, edgeOf(b.points[i], b.points[(i + 1) % n]), maxTime, i));
  }
  for (int k = 0; k < n; ++k) {
    const int feature = n + k;
    if (feature == excludedFeature) continue;
    if (auto t = timeToReach(a.center - b.points[k], velocity, a.radius, maxTime))
      keepEarlier(best, pointImpact(a.center, velocity, b.points[k], 0.0, *t, feature));
  }
  return best;
}

// ---- Dispatch ----------------------------------------------------------------------------------------

namespace {

using PairFunction = std::optional<Impact> (*)(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                               Vec2 relativeVelocity, double maxTime, int excludedFeature);

// A circle-like geometry as a circle in world coordinates.
Circle asCircle(const Geometry& g, Vec2 position) {
  if (const auto* c = std::get_if<Circle>(&g)) return Circle{c->center + position, c->radius};
  return Circle{std::get<Point>(g).position + position, 0.0};
}

// Circle (or point) A against geometry B of type Shape: the circle goes into B's frame, the answer back.
template <class Shape, std::optional<Impact> (*Fn)(const Circle&, Vec2, const Shape&, double, int)>
std::optional<Impact> circleVs(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB, Vec2 v,
                               double maxTime, int excludedFeature) {
  Circle circle = asCircle(a, positionA);
  circle.center -= positionB;
  auto impact = Fn(circle, v, std::get<Shape>(b), maxTime, excludedFeature);
  if (impact) impact->point += positionB;
  return impact;
}

std::optional<Impact> circleVsPointShape(const Circle& a, Vec2 v, const Point& b, double maxTime, int excluded) {
  return timeOfImpactCirclePoint(a, v, b, maxTime, excluded);
}

// The other order: B is the circle. Solve with the roles swapped and the motion reversed, then turn
// the answer back: the normal is negated, and the contact point, found in the frame where A rests,
// moves by A's travel v t into the frame where B rests.
template <PairFunction Fn>
std::optional<Impact> swapped(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB, Vec2 v,
                              double maxTime, int excludedFeature) {
  auto impact = Fn(b, positionB, a, positionA, -v, maxTime, excludedFeature);
  if (impact) {
    impact->normal = -impact->normal;
    impact->point += v * impact->time;
  }
  return impact;
}

std::optional<Impact> noImpact(const Geometry&, Vec2, const Geometry&, Vec2, Vec2, double, int) { return std::nullopt; }

constexpr PairFunction kCircleCircle = circleVs<Circle, timeOfImpactCircleCircle>;
constexpr PairFunction kCirclePoint = circleVs<Point, circleVsPointShape>;
constexpr PairFunction kCircleSegment = circleVs<Segment, timeOfImpactCircleSegment>;
constexpr PairFunction kCirclePolyline = circleVs<Polyline, timeOfImpactCirclePolyline>;
constexpr PairFunction kCirclePolygon = circleVs<Polygon, timeOfImpactCirclePolygon>;

// A point on the moving side is a circle of radius 0, so "point vs X" reuses the circle functions
// (asCircle handles both); a point on the resting side uses circle-point.
constexpr PairFunction kTable[kGeometryTypeCount][kGeometryTypeCount] = {
    //             Point                     Circle                     Segment          Polyline          Polygon
    /* Point    */ {kCirclePoint, kCircleCircle, kCircleSegment, kCirclePolyline, kCirclePolygon},
    /* Circle   */ {kCirclePoint, kCircleCircle, kCircleSegment, kCirclePolyline, kCirclePolygon},
    /* Segment  */ {swapped<kCircleSegment>, swapped<kCircleSegment>, noImpact, noImpact, noImpact},
    /* Polyline */ {swapped<kCirclePolyline>, swapped<kCirclePolyline>, noImpact, noImpact, noImpact},
    /* Polygon  */ {swapped<kCirclePolygon>, swapped<kCirclePolygon>, noImpact, noImpact, noImpact},
};

}  // namespace

std::optional<Impact> timeOfImpact(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                   Vec2 relativeVelocity, double maxTime, int excludedFeature) {
  return kTable[a.index()][b.index()](a, positionA, b, positionB, relativeVelocity, maxTime, excludedFeature);
}

}  // namespace rattle
