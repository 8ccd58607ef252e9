// When two moving geometries start or stop overlapping: the sensor's counterpart of time of impact.
//
// The overlap of two placed geometries can change only at an instant where their boundaries touch. For a
// circle (radius r) against anything that is when its centre is at distance r from a corner or end point
// (|c(t) - p|^2 = r^2: degree 2 on a straight path, 4 on a parabola) or from an edge's line
// (n.(c(t) - a) = +-r: degree 1 or 2); for two straight-edged shapes, when a corner of one crosses the line
// of an edge of the other (degree 1: such pairs never fall). Collecting every such root in [0, maxTime]
// gives a set of instants between which the overlap cannot change; the overlap test at the midpoint of
// each piece then tells exactly which instants are transitions. A root where nothing changes (a tangent
// touch) is skipped by the same test, so a body grazing a sensor begins and ends nothing.
#include <algorithm>
#include <cmath>
#include <vector>

#include "collision/closest_point.h"
#include "collision/polynomial.h"
#include "rattle/time_of_impact.h"

namespace rattle {
namespace {

using detail::Polynomial;

// Corners and edges of a geometry, in its own coordinates.
void cornersOf(const Geometry& g, std::vector<Vec2>& corners) {
  if (const auto* s = std::get_if<Point>(&g)) corners.push_back(s->position);
  if (const auto* s = std::get_if<Segment>(&g)) corners.insert(corners.end(), {s->a, s->b});
  if (const auto* s = std::get_if<Polyline>(&g)) corners.insert(corners.end(), s->points.begin(), s->points.end());
  if (const auto* s = std::get_if<Polygon>(&g)) corners.insert(corners.end(), s->points.begin(), s->points.end());
}

void edgesOf(const Geometry& g, std::vector<std::pair<Vec2, Vec2>>& edges) {
  if (const auto* s = std::get_if<Segment>(&g)) edges.push_back({s->a, s->b});
  if (const auto* s = std::get_if<Polyline>(&g)) {
    for (size_t i = 0; i + 1 < s->points.size(); ++i) edges.push_back({s->points[i], s->points[i + 1]});
  }
  if (const auto* s = std::get_if<Polygon>(&g)) {
    for (size_t i = 0; i < s->points.size(); ++i)
      edges.push_back({s->points[i], s->points[(i + 1) % s->points.size()]});
  }
}

bool circleLike(const Geometry& g) { return std::holds_alternative<Circle>(g) || std::holds_alternative<Point>(g); }

Circle asCircle(const Geometry& g) {
  if (const auto* c = std::get_if<Circle>(&g)) return *c;
  return Circle{std::get<Point>(g).position, 0.0};
}

void addRoots(const Polynomial& p, double maxTime, std::vector<double>& times) {
  std::array<double, 4> roots{};
  const int n = detail::rootsIn(p, 0, maxTime, roots);
  times.insert(times.end(), roots.begin(), roots.begin() + n);
}

// Instants at which a circle centred at c + v t + a t^2/2 (radius r) can start or stop touching b.
void circleBoundaryTimes(const Circle& circle, const Motion& m, const Geometry& b, double maxTime,
                         std::vector<double>& times) {
  const Vec2 v = m.velocity, acc = m.acceleration;
  thread_local std::vector<Vec2> corners;  // kept from call to call, as timeOfOverlapChange's times
  corners.clear();
  if (const auto* s = std::get_if<Circle>(&b)) {
    corners.push_back(s->center);
  } else {
    cornersOf(b, corners);
  }
  const double reach = circle.radius + (std::holds_alternative<Circle>(b) ? std::get<Circle>(b).radius : 0.0);
  for (Vec2 p : corners) {
    const Vec2 r = circle.center - p;
    Polynomial f;
    f.degree = 4;
    f.c = {dot(r, r) - reach * reach, 2 * dot(r, v), dot(v, v) + dot(r, acc), dot(v, acc), 0.25 * dot(acc, acc)};
    addRoots(f, maxTime, times);
  }
  thread_local std::vector<std::pair<Vec2, Vec2>> edges;
  edges.clear();
  edgesOf(b, edges);
  for (auto [a, e] : edges) {
    const Vec2 d = e - a;
    const Vec2 n = perpendicular(d) * (1.0 / length(d));
    for (double side : {circle.radius, -circle.radius}) {
      Polynomial f;
      f.degree = 2;
      f.c = {dot(n, circle.center - a) - side, dot(n, v), 0.5 * dot(n, acc)};
      addRoots(f, maxTime, times);
    }
  }
}

// Instants at which a corner of one straight-edged shape crosses the line of an edge of the other, the
// first moving with velocity v relative to the second.
void cornerEdgeTimes(const Geometry& moving, Vec2 offset, const Geometry& resting, Vec2 v, double maxTime,
                     std::vector<double>& times) {
  thread_local std::vector<Vec2> corners;
  thread_local std::vector<std::pair<Vec2, Vec2>> edges;
  corners.clear();
  edges.clear();
  cornersOf(moving, corners);
  edgesOf(resting, edges);
  for (Vec2 p : corners) {
    for (auto [a, e] : edges) {
      const Vec2 n = perpendicular(e - a);
      Polynomial f;
      f.degree = 1;
      f.c = {dot(n, p + offset - a), dot(n, v), 0, 0, 0};
      addRoots(f, maxTime, times);
    }
  }
}

}  // namespace

std::optional<double> timeOfOverlapChange(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                          const Motion& m, double maxTime, bool overlappingNow) {
  // Kept from call to call (one list per thread): a step asks this of every sensor pair along every
  // piece of its paths, and growing a fresh list each time was most of a sensed step's allocations.
  thread_local std::vector<double> times;
  times.clear();
  const Vec2 offset = positionA - positionB;  // A in B's frame at time 0
  if (circleLike(a)) {
    Circle c = asCircle(a);
    c.center += offset;
    circleBoundaryTimes(c, m, b, maxTime, times);
  } else if (circleLike(b)) {
    Circle c = asCircle(b);
    c.center -= offset;  // B in A's frame, moving the other way
    circleBoundaryTimes(c, Motion{-m.velocity, -m.acceleration}, a, maxTime, times);
  } else {
    cornerEdgeTimes(a, offset, b, m.velocity, maxTime, times);
    cornerEdgeTimes(b, -offset, a, -m.velocity, maxTime, times);
  }
  times.push_back(0);
  times.push_back(maxTime);
  std::sort(times.begin(), times.end());
  // Roots closer together than round-off (an edge's line and its end circle at the same instant, or the
  // very transition just handled when predicting again from it) would leave pieces too short for their
  // midpoint to mean anything, and the overlap would flicker. Keep one instant of each such cluster.
  // How close is "closer than round-off": the time the motion takes to cover the round-off of the
  // coordinates involved, and never less than 1e-12 of the interval.
  const double speed = length(m.velocity) + length(m.acceleration) * maxTime;
  const double scale = std::fabs(positionA.x) + std::fabs(positionA.y) + std::fabs(positionB.x) +
                       std::fabs(positionB.y) + length(boxOf(a).max - boxOf(a).min) +
                       length(boxOf(b).max - boxOf(b).min);
  const double merge =
      std::max(1e-12 * maxTime, speed > 0 ? detail::kRoundOffUlps * scale / speed : 0.0);
  size_t kept = 0;
  for (size_t i = 0; i < times.size(); ++i) {
    if (kept == 0 || times[i] - times[kept - 1] > merge) times[kept++] = times[i];
  }
  times.resize(kept);
  if (times.back() < maxTime) times.push_back(maxTime);

  auto overlapAt = [&](double t) {
    const Vec2 travel = m.velocity * t + m.acceleration * (0.5 * t * t);
    return overlaps(a, positionA + travel, b, positionB);
  };
  bool state = overlappingNow;
  for (size_t i = 0; i + 1 < times.size(); ++i) {
    const double mid = times[i] + 0.5 * (times[i + 1] - times[i]);
    if (mid <= times[i] || mid >= times[i + 1]) continue;
    const bool inside = overlapAt(mid);
    if (inside != state) return times[i];
    state = inside;
  }
  // Ending exactly at maxTime: compare with the state there.
  if (overlapAt(maxTime) != state && maxTime > 0) return maxTime;
  if (maxTime == 0 && overlapAt(0) != overlappingNow) return 0.0;
  return std::nullopt;
}

}  // namespace rattle
