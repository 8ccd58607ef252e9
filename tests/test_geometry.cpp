// Tests for the geometry layer (rattle/geometry.h): boxes, areas, distances, normalisation and validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "rattle/geometry.h"

namespace {

using rattle::Box;
using rattle::Circle;
using rattle::Geometry;
using rattle::Point;
using rattle::Polygon;
using rattle::Polyline;
using rattle::Segment;
using rattle::Vec2;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void expectBox(const Box& box, Vec2 min, Vec2 max) {
  EXPECT_EQ(box.min.x, min.x);
  EXPECT_EQ(box.min.y, min.y);
  EXPECT_EQ(box.max.x, max.x);
  EXPECT_EQ(box.max.y, max.y);
}

double signedArea(const std::vector<Vec2>& p) {
  double twice = 0.0;
  for (size_t i = 0; i < p.size(); ++i) twice += rattle::cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * twice;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The validation message for an invalid geometry; fails the test when there is none.
std::string errorOf(const Geometry& g) {
  std::optional<std::string> e = rattle::validationError(g);
  EXPECT_TRUE(e.has_value()) << "expected the geometry to be rejected";
  return e.value_or("");
}

bool mentionsWord(const std::string& message, const std::string& word) {
  // `word` as a whole identifier (not inside a longer name), e.g. the field `a` of a Segment.
  return std::regex_search(message, std::regex("(^|[^A-Za-z_])" + word + "([^A-Za-z_]|$)"));
}

// ---------------------------------------------------------------------------------------------------------
// boxOf

TEST(GeometryBox, PointIsADegenerateBox) {
  expectBox(rattle::boxOf(Point{{3.0, -4.0}}), {3.0, -4.0}, {3.0, -4.0});
}

TEST(GeometryBox, CircleExtendsByTheRadius) {
  expectBox(rattle::boxOf(Circle{{1.0, 2.0}, 0.5}), {0.5, 1.5}, {1.5, 2.5});
  expectBox(rattle::boxOf(Circle{{-1.0, 0.0}, 0.0}), {-1.0, 0.0}, {-1.0, 0.0});
}

TEST(GeometryBox, SegmentSpansItsEndsInEitherOrder) {
  expectBox(rattle::boxOf(Segment{{3.0, -1.0}, {-2.0, 4.0}}), {-2.0, -1.0}, {3.0, 4.0});
  expectBox(rattle::boxOf(Segment{{-2.0, 4.0}, {3.0, -1.0}}), {-2.0, -1.0}, {3.0, 4.0});
}

TEST(GeometryBox, PolylineAndPolygonSpanAllPoints) {
  expectBox(rattle::boxOf(Polyline{{{0.0, 0.0}, {5.0, 1.0}, {2.0, -3.0}, {-1.0, 2.0}}}), {-1.0, -3.0},
            {5.0, 2.0});
  expectBox(rattle::boxOf(Polygon{{{1.0, 1.0}, {4.0, 2.0}, {2.0, 6.0}}}), {1.0, 1.0}, {4.0, 6.0});
}

TEST(GeometryBox, UnionOverlapsContains) {
  const Box a{{0.0, 0.0}, {1.0, 1.0}};
  const Box b{{2.0, -1.0}, {3.0, 0.5}};
  expectBox(rattle::unionOf(a, b), {0.0, -1.0}, {3.0, 1.0});
  EXPECT_FALSE(a.overlaps(b));
  EXPECT_TRUE(rattle::unionOf(a, b).contains(a));
  EXPECT_TRUE(rattle::unionOf(a, b).contains(b));
  // Touching boxes overlap (closed boxes).
  EXPECT_TRUE(a.overlaps(Box{{1.0, 1.0}, {2.0, 2.0}}));
}

// ---------------------------------------------------------------------------------------------------------
// areaOf

TEST(GeometryArea, CircleIsPiRSquared) {
  EXPECT_NEAR(rattle::areaOf(Circle{{5.0, 5.0}, 2.0}), 4.0 * std::numbers::pi, 1e-12);
  EXPECT_EQ(rattle::areaOf(Circle{{0.0, 0.0}, 0.0}), 0.0);
}

TEST(GeometryArea, PolygonEnclosedAreaInEitherWinding) {
  const std::vector<Vec2> triangleCcw{{0.0, 0.0}, {4.0, 0.0}, {0.0, 3.0}};  // 4 * 3 / 2 = 6
  const std::vector<Vec2> triangleCw{{0.0, 0.0}, {0.0, 3.0}, {4.0, 0.0}};
  EXPECT_NEAR(rattle::areaOf(Polygon{triangleCcw}), 6.0, 1e-12);
  EXPECT_NEAR(rattle::areaOf(Polygon{triangleCw}), 6.0, 1e-12);
  // A 2 x 2 square away from the origin.
  EXPECT_NEAR(rattle::areaOf(Polygon{{{9.0, 9.0}, {11.0, 9.0}, {11.0, 11.0}, {9.0, 11.0}}}), 4.0, 1e-12);
}

TEST(GeometryArea, PointsSegmentsPolylinesHaveNone) {
  EXPECT_EQ(rattle::areaOf(Point{{1.0, 2.0}}), 0.0);
  EXPECT_EQ(rattle::areaOf(Segment{{0.0, 0.0}, {3.0, 4.0}}), 0.0);
  EXPECT_EQ(rattle::areaOf(Polyline{{{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 0.0}}}), 0.0);
}

// ---------------------------------------------------------------------------------------------------------
// distanceTo

TEST(GeometryDistance, Point) {
  EXPECT_NEAR(rattle::distanceTo(Point{{1.0, 1.0}}, {4.0, 5.0}), 5.0, 1e-12);  // 3-4-5
  EXPECT_EQ(rattle::distanceTo(Point{{1.0, 1.0}}, {1.0, 1.0}), 0.0);
}

TEST(GeometryDistance, CircleOutsideAndInside) {
  const Circle c{{1.0, 1.0}, 2.0};
  EXPECT_NEAR(rattle::distanceTo(c, {4.0, 5.0}), 3.0, 1e-12);  // 5 from the centre, minus 2
  EXPECT_EQ(rattle::distanceTo(c, {1.5, 1.0}), 0.0);            // inside
  EXPECT_EQ(rattle::distanceTo(c, {1.0, 1.0}), 0.0);            // the centre
}

TEST(GeometryDistance, SegmentInsideAndBeyondItsEnds) {
  const Segment s{{-2.0, 0.0}, {2.0, 0.0}};
  EXPECT_NEAR(rattle::distanceTo(s, {0.5, 3.0}), 3.0, 1e-12);   // above the inside
  EXPECT_NEAR(rattle::distanceTo(s, {0.5, -1.5}), 1.5, 1e-12);  // below the inside
  EXPECT_NEAR(rattle::distanceTo(s, {5.0, 4.0}), 5.0, 1e-12);   // beyond b: (3, 4) from b
  EXPECT_NEAR(rattle::distanceTo(s, {-5.0, 0.0}), 3.0, 1e-12);  // on the line, beyond a
  EXPECT_EQ(rattle::distanceTo(s, {1.0, 0.0}), 0.0);
  // A diagonal segment: (0,4) is 4/sqrt(2) from the line y = x, and its foot (2,2) is inside.
  EXPECT_NEAR(rattle::distanceTo(Segment{{0.0, 0.0}, {4.0, 4.0}}, {0.0, 4.0}), 2.0 * std::numbers::sqrt2,
              1e-12);
}

TEST(GeometryDistance, PolylineNearestSegmentOrCorner) {
  const Polyline p{{{0.0, 0.0}, {4.0, 0.0}, {4.0, 4.0}}};
  EXPECT_NEAR(rattle::distanceTo(p, {2.0, 1.0}), 1.0, 1e-12);  // segment 0 is 1 away, segment 1 is 2
  EXPECT_NEAR(rattle::distanceTo(p, {7.0, -4.0}), 5.0, 1e-12);  // nearest is the corner (4,0)
  EXPECT_NEAR(rattle::distanceTo(p, {4.0, 6.0}), 2.0, 1e-12);  // beyond the last point
  EXPECT_EQ(rattle::distanceTo(p, {4.0, 1.0}), 0.0);
}

TEST(GeometryDistance, PolygonIsZeroInsideEdgeOrCornerOutside) {
  const std::vector<Vec2> ccw{{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}};
  const std::vector<Vec2> cw{{-1.0, -1.0}, {-1.0, 1.0}, {1.0, 1.0}, {1.0, -1.0}};
  for (const auto& pts : {ccw, cw}) {
    const Polygon square{pts};
    EXPECT_EQ(rattle::distanceTo(square, {0.0, 0.0}), 0.0);
    EXPECT_EQ(rattle::distanceTo(square, {0.9, -0.5}), 0.0);
    EXPECT_EQ(rattle::distanceTo(square, {1.0, 0.0}), 0.0);       // on an edge
    EXPECT_NEAR(rattle::distanceTo(square, {0.5, 3.5}), 2.5, 1e-12);  // above the top edge
    EXPECT_NEAR(rattle::distanceTo(square, {4.0, 5.0}), 5.0, 1e-12);  // (3,4) from the corner (1,1)
    EXPECT_NEAR(rattle::distanceTo(square, {-4.0, 0.25}), 3.0, 1e-12);
  }
}

// ---------------------------------------------------------------------------------------------------------
// normalized

TEST(GeometryNormalized, ClockwisePolygonComesBackCounterClockwiseSamePoints) {
  const std::vector<Vec2> cw{{0.0, 0.0}, {0.0, 3.0}, {2.0, 4.0}, {5.0, 1.0}, {4.0, -1.0}};
  ASSERT_LT(signedArea(cw), 0.0);
  ASSERT_FALSE(rattle::validationError(Polygon{cw}).has_value());
  const Geometry g = rattle::normalized(Polygon{cw});
  ASSERT_EQ(rattle::typeOf(g), rattle::GeometryType::Polygon);
  const std::vector<Vec2>& out = std::get<Polygon>(g).points;
  ASSERT_EQ(out.size(), cw.size());
  EXPECT_GT(signedArea(out), 0.0);
  EXPECT_NEAR(signedArea(out), -signedArea(cw), 1e-12);
  // Same point set.
  for (Vec2 p : cw) EXPECT_NE(std::find(out.begin(), out.end(), p), out.end()) << p.x << "," << p.y;
  // And the boundary is the same cycle, walked the other way: each point's neighbours are unchanged.
  for (size_t i = 0; i < out.size(); ++i) {
    const size_t j = static_cast<size_t>(std::find(cw.begin(), cw.end(), out[i]) - cw.begin());
    const Vec2 next = out[(i + 1) % out.size()];
    EXPECT_EQ(next, cw[(j + cw.size() - 1) % cw.size()]) << "point " << i;
  }
  EXPECT_FALSE(rattle::validationError(g).has_value());
}

TEST(GeometryNormalized, CounterClockwisePolygonAndOtherShapesUnchanged) {
  const std::vector<Vec2> ccw{{0.0, 0.0}, {4.0, 0.0}, {4.0, 3.0}};
  EXPECT_EQ(std::get<Polygon>(rattle::normalized(Polygon{ccw})).points, ccw);

  const Geometry c = rattle::normalized(Circle{{1.0, 2.0}, 3.0});
  ASSERT_EQ(rattle::typeOf(c), rattle::GeometryType::Circle);
  EXPECT_EQ(std::get<Circle>(c).center, (Vec2{1.0, 2.0}));
  EXPECT_EQ(std::get<Circle>(c).radius, 3.0);

  // A polyline keeps its order whatever its turning direction.
  const std::vector<Vec2> line{{0.0, 0.0}, {0.0, 3.0}, {2.0, 4.0}};
  EXPECT_EQ(std::get<Polyline>(rattle::normalized(Polyline{line})).points, line);

  const Geometry s = rattle::normalized(Segment{{5.0, 1.0}, {-1.0, 2.0}});
  EXPECT_EQ(std::get<Segment>(s).a, (Vec2{5.0, 1.0}));
  EXPECT_EQ(std::get<Segment>(s).b, (Vec2{-1.0, 2.0}));
}

TEST(GeometryNames, EveryTypeHasAName) {
  for (int t = 0; t < rattle::kGeometryTypeCount; ++t) {
    const char* name = rattle::nameOf(static_cast<rattle::GeometryType>(t));
    ASSERT_NE(name, nullptr);
    EXPECT_GT(std::string(name).size(), 0u);
  }
  EXPECT_EQ(lower(rattle::nameOf(rattle::GeometryType::Polygon)), "polygon");
}

// ---------------------------------------------------------------------------------------------------------
// validationError: valid shapes

TEST(GeometryValidation, ValidShapesHaveNoError) {
  const std::vector<Geometry> valid{
      Point{{0.0, 0.0}},
      Point{{-1e300, 1e300}},
      Circle{{1.0, 2.0}, 0.5},
      Circle{{1.0, 2.0}, 0.0},  // radius 0 is allowed
      Segment{{0.0, 0.0}, {1.0, 0.0}},
      Segment{{1e-9, 0.0}, {0.0, 0.0}},
      Polyline{{{0.0, 0.0}, {1.0, 0.0}}},
      Polyline{{{0.0, 0.0}, {1.0, 0.0}, {2.0, 0.0}}},              // collinear polylines are fine
      Polyline{{{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 0.0}}},  // closed loop: only neighbours must differ
      Polyline{{{0.0, 0.0}, {1.0, 0.0}, {0.0, 0.0}}},              // doubling back
      Polygon{{{0.0, 0.0}, {4.0, 0.0}, {0.0, 3.0}}},               // ccw triangle
      Polygon{{{0.0, 0.0}, {0.0, 3.0}, {4.0, 0.0}}},               // cw triangle
      Polygon{{{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}},
      Polygon{{{0.0, 10.0}, {-9.5, 3.1}, {-5.9, -8.1}, {5.9, -8.1}, {9.5, 3.1}}},  // regular-ish pentagon
  };
  for (size_t i = 0; i < valid.size(); ++i) {
    const std::optional<std::string> e = rattle::validationError(valid[i]);
    EXPECT_FALSE(e.has_value()) << "case " << i << ": " << e.value_or("");
  }
}

// ---------------------------------------------------------------------------------------------------------
// validationError: invalid shapes. Each message must name the field and its value.

TEST(GeometryValidation, NonFiniteNumbersAnywhere) {
  {
    const std::string m = errorOf(Circle{{kNaN, 0.0}, 1.0});
    EXPECT_NE(m.find("center"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("nan"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Circle{{0.0, -kInf}, 1.0});
    EXPECT_NE(m.find("center"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("inf"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Circle{{0.0, 0.0}, kInf});
    EXPECT_NE(m.find("radius"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("inf"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Circle{{0.0, 0.0}, kNaN});
    EXPECT_NE(m.find("radius"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("nan"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Point{{kInf, 0.0}});
    EXPECT_NE(m.find("position"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("inf"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Segment{{0.0, kNaN}, {1.0, 0.0}});
    EXPECT_TRUE(mentionsWord(m, "a")) << m;
    EXPECT_NE(lower(m).find("nan"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Segment{{0.0, 0.0}, {kInf, 0.0}});
    EXPECT_TRUE(mentionsWord(m, "b")) << m;
    EXPECT_NE(lower(m).find("inf"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Polyline{{{0.0, 0.0}, {1.0, 0.0}, {2.0, kNaN}}});
    EXPECT_NE(m.find("points"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("nan"), std::string::npos) << m;
  }
  {
    const std::string m = errorOf(Polygon{{{0.0, 0.0}, {4.0, 0.0}, {-kInf, 3.0}}});
    EXPECT_NE(m.find("points"), std::string::npos) << m;
    EXPECT_NE(lower(m).find("inf"), std::string::npos) << m;
  }
}

TEST(GeometryValidation, NegativeRadius) {
  const std::string m = errorOf(Circle{{0.0, 0.0}, -1.0});
  EXPECT_NE(m.find("radius"), std::string::npos) << m;
  EXPECT_NE(m.find("-1"), std::string::npos) << m;
  const std::string tiny = errorOf(Circle{{0.0, 0.0}, -1e-300});
  EXPECT_NE(tiny.find("radius"), std::string::npos) << tiny;
}

TEST(GeometryValidation, ZeroLengthSegment) {
  const std::string m = errorOf(Segment{{1.5, -2.5}, {1.5, -2.5}});
  EXPECT_NE(m.find("1.5"), std::string::npos) << m;
  EXPECT_NE(m.find("-2.5"), std::string::npos) << m;
  EXPECT_TRUE(mentionsWord(m, "a") || mentionsWord(m, "b")) << m;
}

TEST(GeometryValidation, PolylineWithTooFewPoints) {
  for (const auto& pts : {std::vector<Vec2>{}, std::vector<Vec2>{{1.0, 2.0}}}) {
    const std::string m = errorOf(Polyline{pts});
    EXPECT_NE(m.find("points"), std::string::npos) << m;
    EXPECT_NE(m.find(std::to_string(pts.size())), std::string::npos) << m;  // the count
  }
}

TEST(GeometryValidation, PolylinePointRepeatingThePreviousOne) {
  const std::string m = errorOf(Polyline{{{0.0, 0.0}, {3.25, 7.0}, {3.25, 7.0}, {5.0, 5.0}}});
  EXPECT_NE(m.find("points"), std::string::npos) << m;
  EXPECT_NE(m.find("3.25"), std::string::npos) << m;
}

TEST(GeometryValidation, PolygonWithTooFewPoints) {
  for (const auto& pts : {std::vector<Vec2>{}, std::vector<Vec2>{{0.0, 0.0}, {1.0, 0.0}}}) {
    const std::string m = errorOf(Polygon{pts});
    EXPECT_NE(m.find("points"), std::string::npos) << m;
    EXPECT_NE(m.find(std::to_string(pts.size())), std::string::npos) << m;
  }
}

TEST(GeometryValidation, NonConvexPolygon) {
  // An arrow: (2,1) is a reflex corner.
  const std::string m = errorOf(Polygon{{{0.0, 0.0}, {4.0, 0.0}, {4.0, 4.0}, {2.0, 1.0}, {0.0, 4.0}}});
  EXPECT_NE(m.find("points"), std::string::npos) << m;
}

TEST(GeometryValidation, SelfIntersectingStar) {
  // The corners of a regular pentagon visited in pentagram order 0, 2, 4, 1, 3: every turn has the same
  // sign, yet the boundary winds twice round the centre and crosses itself.
  std::vector<Vec2> pentagon;
  for (int i = 0; i < 5; ++i) {
    const double angle = std::numbers::pi / 2 + 2.0 * std::numbers::pi * i / 5.0;
    pentagon.push_back({10.0 * std::cos(angle), 10.0 * std::sin(angle)});
  }
  ASSERT_FALSE(rattle::validationError(Polygon{pentagon}).has_value());
  const std::vector<Vec2> star{pentagon[0], pentagon[2], pentagon[4], pentagon[1], pentagon[3]};
  for (size_t i = 0; i < star.size(); ++i) {  // all left turns
    const Vec2 a = star[i], b = star[(i + 1) % 5], c = star[(i + 2) % 5];
    ASSERT_GT(rattle::cross(b - a, c - b), 0.0);
  }
  const std::string m = errorOf(Polygon{star});
  EXPECT_NE(m.find("points"), std::string::npos) << m;
  // Clockwise star too.
  const std::vector<Vec2> starCw{star.rbegin(), star.rend()};
  errorOf(Polygon{starCw});
}

TEST(GeometryValidation, CollinearPolygonPoints) {
  {
    const std::string m = errorOf(Polygon{{{0.0, 0.0}, {1.0, 0.0}, {2.0, 0.0}, {1.0, 1.0}}});
    EXPECT_NE(m.find("points"), std::string::npos) << m;
  }
  // The three collinear points straddle the wrap-around (last, first, second).
  errorOf(Polygon{{{1.0, 0.0}, {2.0, 0.0}, {1.0, 1.0}, {0.0, 0.0}}});
}

TEST(GeometryValidation, FlatTriangle) {
  // All three points on one line: the message still names the field (points) and a value.
  const std::string m = errorOf(Polygon{{{0.0, 0.0}, {1.0, 1.0}, {2.0, 2.0}}});
  EXPECT_NE(m.find("points"), std::string::npos) << m;
}

TEST(GeometryValidation, RepeatedPolygonPoint) {
  {
    const std::string m = errorOf(Polygon{{{0.0, 0.0}, {4.0, 0.0}, {4.0, 0.0}, {0.0, 3.0}}});
    EXPECT_NE(m.find("points"), std::string::npos) << m;
  }
  // The last point repeats the first.
  errorOf(Polygon{{{0.0, 0.0}, {4.0, 0.0}, {0.0, 3.0}, {0.0, 0.0}}});
}

}  // namespace
