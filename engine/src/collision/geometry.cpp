// The geometry layer: boxes, areas, distances and validation of each shape.
#include "rattle/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/format.h"

namespace rattle {

using detail::str;

namespace {

template <class... Fs>
struct Overloaded : Fs... {
  using Fs::operator()...;
};
template <class... Fs>
Overloaded(Fs...) -> Overloaded<Fs...>;

Box boxOfPoints(const std::vector<Vec2>& points) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Box box{{inf, inf}, {-inf, -inf}};
  for (Vec2 p : points) {
    box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y)};
    box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y)};
  }
  return box;
}

// Twice the signed area (shoelace formula); positive for counter-clockwise winding.
double twiceSignedArea(const std::vector<Vec2>& points) {
  double sum = 0.0;
  for (size_t i = 0, n = points.size(); i < n; ++i) sum += cross(points[i], points[(i + 1) % n]);
  return sum;
}

double distanceToSegment(Vec2 a, Vec2 b, Vec2 p) {
  Vec2 d = b - a;
  double t = std::clamp(dot(p - a, d) / dot(d, d), 0.0, 1.0);
  return length(p - (a + t * d));
}

std::optional<std::string> pointsError(const char* shape, const std::vector<Vec2>& points) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!isFinite(points[i])) {
      return std::string(shape) + ".points[" + std::to_string(i) + "] = " + str(points[i]) + ": must be finite";
    }
  }
  return std::nullopt;
}

}  // namespace

const char* nameOf(GeometryType type) {
  switch (type) {
    case GeometryType::Point:
      return "Point";
    case GeometryType::Circle:
      return "Circle";
    case GeometryType::Segment:
      return "Segment";
    case GeometryType::Polyline:
      return "Polyline";
    case GeometryType::Polygon:
      return "Polygon";
  }
  return "?";
}

Box boxOf(const Geometry& g) {
  return std::visit(Overloaded{
                        [](const Point& s) {
                          return Box{s.position, s.position};
                        },
                        [](const Circle& s) {
                          Vec2 r{s.radius, s.radius};
                          return Box{s.center - r, s.center + r};
                        },
                        [](const Segment& s) {
                          return boxOfPoints({s.a, s.b});
                        },
                        [](const Polyline& s) { return boxOfPoints(s.points); },
                        [](const Polygon& s) { return boxOfPoints(s.points); },
                    },
                    g);
}

double areaOf(const Geometry& g) {
  if (const auto* c = std::get_if<Circle>(&g)) return M_PI * c->radius * c->radius;
  if (const auto* p = std::get_if<Polygon>(&g)) return 0.5 * std::fabs(twiceSignedArea(p->points));
  return 0.0;
}

double distanceTo(const Geometry& g, Vec2 p) {
  return std::visit(Overloaded{
                        [&](const Point& s) { return length(p - s.position); },
                        [&](const Circle& s) { return std::max(0.0, length(p - s.center) - s.radius); },
                        [&](const Segment& s) { return distanceToSegment(s.a, s.b, p); },
                        [&](const Polyline& s) {
                          double best = std::numeric_limits<double>::infinity();
                          for (size_t i = 0; i + 1 < s.points.size(); ++i)
                            best = std::min(best, distanceToSegment(s.points[i], s.points[i + 1], p));
                          return best;
                        },
                        [&](const Polygon& s) {
                          const size_t n = s.points.size();
                          double best = std::numeric_limits<double>::infinity();
                          bool inside = true;
                          const double orientation = twiceSignedArea(s.points) >= 0 ? 1.0 : -1.0;
                          for (size_t i = 0; i < n; ++i) {
                            Vec2 a = s.points[i], b = s.points[(i + 1) % n];
                            if (orientation * cross(b - a, p - a) < 0) inside = false;
                            best = std::min(best, distanceToSegment(a, b, p));
                          }
                          return inside ? 0.0 : best;
                        },
                    },
                    g);
}

std::optional<std::string> validationError(const Geometry& g) {
  return std::visit(Overloaded{
                        [](const Point& s) -> std::optional<std::string> {
                          if (!isFinite(s.position)) return "Point.position = " + str(s.position) + ": must be finite";
                          return std::nullopt;
                        },
                        [](const Circle& s) -> std::optional<std::string> {
                          if (!isFinite(s.center)) return "Circle.center = " + str(s.center) + ": must be finite";
                          if (!std::isfinite(s.radius) || s.radius < 0)
                            return "Circle.radius = " + str(s.radius) + ": must be finite and >= 0";
                          return std::nullopt;
                        },
                        [](const Segment& s) -> std::optional<std::string> {
                          if (!isFinite(s.a)) return "Segment.a = " + str(s.a) + ": must be finite";
                          if (!isFinite(s.b)) return "Segment.b = " + str(s.b) + ": must be finite";
                          if (s.a == s.b) return "Segment: zero length, a = b = " + str(s.a);
                          if (!std::isfinite(length(s.b - s.a)))
                            return "Segment: length overflows, a = " + str(s.a) + ", b = " + str(s.b);
                          return std::nullopt;
                        },
                        [](const Polyline& s) -> std::optional<std::string> {
                          if (s.points.size() < 2)
                            return "Polyline.points: needs at least 2 points, got " + std::to_string(s.points.size());
                          if (auto e = pointsError("Polyline", s.points)) return e;
                          for (size_t i = 1; i < s.points.size(); ++i) {
                            if (s.points[i] == s.points[i - 1])
                              return "Polyline.points[" + std::to_string(i) + "] = " + str(s.points[i]) +
                                     " repeats the point before it";
                          }
                          return std::nullopt;
                        },
                        [](const Polygon& s) -> std::optional<std::string> {
                          const size_t n = s.points.size();
                          if (n < 3) return "Polygon.points: needs at least 3 points, got " + std::to_string(n);
                          if (auto e = pointsError("Polygon", s.points)) return e;
                          for (size_t i = 0; i < n; ++i) {
                            for (size_t j = i + 1; j < n; ++j) {
                              if (s.points[i] == s.points[j])
                                return "Polygon.points[" + std::to_string(j) + "] = " + str(s.points[j]) +
                                       " repeats points[" + std::to_string(i) + "]";
                            }
                          }
                          const double area2 = twiceSignedArea(s.points);
                          if (!(std::fabs(area2) > 0) || !std::isfinite(area2))
                            return "Polygon.points: degenerate, the " + std::to_string(n) +
                                   " points enclose an area of " + str(0.5 * area2);
                          // Strictly convex and simple: every other point lies strictly on the inner side of every
                          // edge. O(n^2), which is nothing for the handful of points a convex piece has, and it also
                          // rejects self-intersecting orders (a pentagram turns left at every corner).
                          const double orientation = area2 > 0 ? 1.0 : -1.0;
                          for (size_t i = 0; i < n; ++i) {
                            Vec2 a = s.points[i], b = s.points[(i + 1) % n];
                            for (size_t k = 0; k < n; ++k) {
                              if (k == i || k == (i + 1) % n) continue;
                              const double side = orientation * cross(b - a, s.points[k] - a);
                              if (side <= 0) {
                                return "Polygon.points[" + std::to_string(k) + "] = " + str(s.points[k]) +
                                       (side == 0 ? " lies on the line of edge " : " lies outside edge ") +
                                       std::to_string(i) + ": the polygon must be strictly convex";
                              }
                            }
                          }
                          return std::nullopt;
                        },
                    },
                    g);
}

Geometry normalized(const Geometry& g) {
  if (const auto* p = std::get_if<Polygon>(&g)) {
    if (twiceSignedArea(p->points) < 0) {
      Polygon ccw{{p->points.rbegin(), p->points.rend()}};
      return ccw;
    }
  }
  return g;
}

}  // namespace rattle
