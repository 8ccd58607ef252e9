// Tests for rattle/time_of_impact.h: hand-made cases whose answers are derived by hand (each derivation is
// in the comment next to it), then a randomized comparison against an independent brute-force reference.
//
// Conventions used throughout (from the header): A is a circle moving relative to B, which is at rest, along
// c + v t + a t^2 / 2 (a rattle::Motion; a plain Vec2 converts to a Motion with no acceleration); `normal`
// is a unit vector from B toward A; `point` is on B's surface at the time of impact; a polyline with n
// points numbers segment i as i and corner k as n-1+k; a polygon with n points numbers edge i (point i to
// i+1) as i and corner k as n+k; impacts count in [0, maxTime], both ends included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "rattle/geometry.h"
#include "rattle/time_of_impact.h"

namespace {

using rattle::Circle;
using rattle::Geometry;
using rattle::Impact;
using rattle::Point;
using rattle::Polygon;
using rattle::Polyline;
using rattle::Segment;
using rattle::Vec2;

constexpr double kRel = 1e-12;  // relative tolerance for analytic answers
const double kSqrt2 = std::numbers::sqrt2;
const double kSqrt3 = std::numbers::sqrt3;

double tol(double expected, double rel = kRel) { return rel * std::max(1.0, std::abs(expected)); }

::testing::AssertionResult nearVec(Vec2 got, Vec2 want, double rel = kRel) {
  const double t = rel * std::max({1.0, std::abs(want.x), std::abs(want.y)});
  if (std::abs(got.x - want.x) <= t && std::abs(got.y - want.y) <= t) return ::testing::AssertionSuccess();
  char buf[200];
  std::snprintf(buf, sizeof buf, "got (%.17g, %.17g), want (%.17g, %.17g), tolerance %.3g", got.x, got.y,
                want.x, want.y, t);
  return ::testing::AssertionFailure() << buf;
}

// Checks every field of an impact. `rel` is the relative tolerance on time, point and normal.
void expectImpact(const std::optional<Impact>& got, double time, Vec2 point, Vec2 normal, int feature,
                  double rel = kRel) {
  ASSERT_TRUE(got.has_value()) << "expected an impact at t = " << time;
  EXPECT_NEAR(got->time, time, tol(time, rel));
  EXPECT_TRUE(nearVec(got->point, point, rel)) << "point";
  EXPECT_TRUE(nearVec(got->normal, normal, rel)) << "normal";
  EXPECT_NEAR(rattle::length(got->normal), 1.0, 1e-14) << "normal must be unit";
  EXPECT_EQ(got->feature, feature);
}

void expectNone(const std::optional<Impact>& got) {
  EXPECT_FALSE(got.has_value()) << "unexpected impact at t = " << got->time << ", point (" << got->point.x
                                << ", " << got->point.y << "), normal (" << got->normal.x << ", "
                                << got->normal.y << "), feature " << got->feature;
}

// The square [-1,1]^2, counter-clockwise. Edges: 0 bottom, 1 right, 2 top, 3 left.
// Corners: 4 = (-1,-1), 5 = (1,-1), 6 = (1,1), 7 = (-1,1).
Polygon square() { return Polygon{{{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}}; }

// =========================================================================================================
// Circle - circle

TEST(TimeOfImpactCircleCircle, HeadOn) {
  // Centres 10 apart on the x axis, radii 1 + 1: the gap of 8 closes at speed 2, so t = 4. Then A's centre
  // is at (-2,0); the contact point on B's surface is (-1,0); the normal from B toward A is (-1,0).
  // Stable form: r = (-10,0), b = r.v = -20, a = 4, c = 100 - 4 = 96, disc = 400 - 384 = 16,
  // t = 96 / (20 + 4) = 4 exactly.
  const auto hit = rattle::timeOfImpactCircleCircle({{-10.0, 0.0}, 1.0}, Vec2{2.0, 0.0}, {{0.0, 0.0}, 1.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 4.0, {-1.0, 0.0}, {-1.0, 0.0}, 0));
  EXPECT_EQ(hit->time, 4.0);
}

TEST(TimeOfImpactCircleCircle, HeadOnFarFromTheOrigin) {
  // Same relative geometry shifted by (1e6, -1e6): all coordinates stay exact, so t = 4 again.
  const Vec2 o{1e6, -1e6};
  const auto hit = rattle::timeOfImpactCircleCircle({o + Vec2{-10.0, 0.0}, 1.0}, Vec2{2.0, 0.0}, {o, 1.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 4.0, o + Vec2{-1.0, 0.0}, {-1.0, 0.0}, 0));
}

TEST(TimeOfImpactCircleCircle, UnequalRadii) {
  {
    // Vertical: gap = 5 - (0.25 + 2) = 2.75 at speed 1.5 -> t = 11/6; point (0,2) on B; normal (0,1).
    const auto hit =
        rattle::timeOfImpactCircleCircle({{0.0, 5.0}, 0.25}, Vec2{0.0, -1.5}, {{0.0, 0.0}, 2.0}, 10.0);
    ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 11.0 / 6.0, {0.0, 2.0}, {0.0, 1.0}, 0));
  }
  {
    // Along the 3-4-5 diagonal: |r| = 10, radii 1 + 4 = 5, speed |(-3,-4)| = 5 along the line of centres
    // -> t = (10 - 5) / 5 = 1; normal (0.6, 0.8); point = B.center + 4 * normal = (2.4, 3.2).
    const auto hit = rattle::timeOfImpactCircleCircle({{6.0, 8.0}, 1.0}, Vec2{-3.0, -4.0}, {{0.0, 0.0}, 4.0}, 10.0);
    ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 1.0, {2.4, 3.2}, {0.6, 0.8}, 0));
  }
}

TEST(TimeOfImpactCircleCircle, OffCentre) {
  // A at (-10,1) moving (1,0), radii 1 + 1: (t - 10)^2 + 1 = 4 -> t = 10 - sqrt(3). Then A's centre is
  // (-sqrt3, 1), at distance 2 from B's centre; normal = (-sqrt3, 1) / 2; point = B.center + 1 * normal.
  const auto hit = rattle::timeOfImpactCircleCircle({{-10.0, 1.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 1.0}, 100.0);
  const Vec2 n{-kSqrt3 / 2.0, 0.5};
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 10.0 - kSqrt3, n, n, 0));
}

TEST(TimeOfImpactCircleCircle, GrazingAtExactlyTheSumOfRadiiIsNotAnImpact) {
  // Centre (-10,1) moving (1,0) past (0,0), radii 0.5 + 0.5: the closest distance is exactly 1 = the sum of
  // radii, reached at t = 10: a double root (disc = a d^2 - (r x v)^2 = 1 - 1 = 0), a tangent touch.
  expectNone(rattle::timeOfImpactCircleCircle({{-10.0, 1.0}, 0.5}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 0.5}, 100.0));
  // Same pass at speed 3, below, and far from the origin (differences stay exact).
  expectNone(rattle::timeOfImpactCircleCircle({{-10.0, -1.0}, 0.5}, Vec2{3.0, 0.0}, {{0.0, 0.0}, 0.5}, 100.0));
  expectNone(rattle::timeOfImpactCircleCircle({{990.0, 2001.0}, 0.25}, Vec2{1.0, 0.0}, {{1000.0, 2000.0}, 0.75},
                                              100.0));
  // Vertical pass.
  expectNone(rattle::timeOfImpactCircleCircle({{2.0, 10.0}, 1.5}, Vec2{0.0, -1.0}, {{0.0, 0.0}, 0.5}, 100.0));
}

TEST(TimeOfImpactCircleCircle, TinyGapKeepsFullRelativeAccuracy) {
  // Gap eps = 2^-33 (exactly representable next to 2) closed at speed 1: t = eps, to high relative
  // accuracy. (c = |r|^2 - d^2 = 4 eps + eps^2 loses its eps^2 to rounding, a relative 2.9e-11 of t; the
  // form (|r| - d)(|r| + d) would keep it. Either is far inside the 1e-9 asked here.)
  const double eps = std::ldexp(1.0, -33);
  const auto hit = rattle::timeOfImpactCircleCircle({{-2.0 - eps, 0.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 1.0}, 1.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->time, eps, eps * 1e-9);
  // The same gap against a point: radius 1 at (-1 - eps, 0) onto (0,0).
  const auto point = rattle::timeOfImpactCirclePoint({{-1.0 - eps, 0.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 1.0);
  ASSERT_TRUE(point.has_value());
  EXPECT_NEAR(point->time, eps, eps * 1e-9);
}

TEST(TimeOfImpactCircleCircle, NearGrazingPassDoesHit) {
  // Centre (-10, 0.999), radii 0.5 + 0.5: (t - 10)^2 + 0.999^2 = 1 -> t = 10 - sqrt(1 - 0.999^2).
  const long double y = 0.999L;
  const double expected = static_cast<double>(10.0L - std::sqrt(1.0L - y * y));
  const auto hit = rattle::timeOfImpactCircleCircle({{-10.0, 0.999}, 0.5}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 0.5}, 100.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->time, expected, tol(expected, 1e-12));
  const Vec2 c{-10.0 + expected, 0.999};
  EXPECT_TRUE(nearVec(hit->normal, (1.0 / rattle::length(c)) * c, 1e-10));
}

TEST(TimeOfImpactCircleCircle, TouchingAndApproachingIsImmediate) {
  // |r| = 2 = sum of radii exactly (c = 0) and r.v = -2 < 0: impact now, exactly t = 0.
  const auto hit = rattle::timeOfImpactCircleCircle({{-2.0, 0.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 1.0}, 5.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 0.0, {-1.0, 0.0}, {-1.0, 0.0}, 0));
  EXPECT_EQ(hit->time, 0.0);
  // Touching up to round-off on a diagonal (1.2^2 + 1.6^2 = 4 in reals, not exactly in doubles): the
  // answer is t = 0, or a round-off-sized time.
  const auto diag = rattle::timeOfImpactCircleCircle({{1.2, 1.6}, 1.0}, Vec2{-0.6, -0.8}, {{0.0, 0.0}, 1.0}, 5.0);
  ASSERT_TRUE(diag.has_value());
  EXPECT_GE(diag->time, 0.0);
  EXPECT_LE(diag->time, 1e-14);
  EXPECT_TRUE(nearVec(diag->normal, {0.6, 0.8}, 1e-12));
  EXPECT_TRUE(nearVec(diag->point, {0.6, 0.8}, 1e-12));
}

TEST(TimeOfImpactCircleCircle, ImpactExactlyAtMaxTimeZero) {
  // Touching and approaching with maxTime = 0: the impact at t = 0 is inside [0, 0].
  const auto hit = rattle::timeOfImpactCircleCircle({{-2.0, 0.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 1.0}, 0.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time, 0.0);
}

TEST(TimeOfImpactCircleCircle, OverlappingByATinyAmountAndApproachingIsImmediate) {
  // Centres 2 - 1e-12 apart with radii 1 + 1: overlapped (round-off) and approaching -> t = 0 exactly.
  const auto hit =
      rattle::timeOfImpactCircleCircle({{-2.0 + 1e-12, 0.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 1.0}, 5.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 0.0, {-1.0, 0.0}, {-1.0, 0.0}, 0, 1e-11));
  EXPECT_EQ(hit->time, 0.0);
  // Approaching obliquely: r.v = (-2)(1) + 0 * 5 = -2 < 0.
  const auto oblique =
      rattle::timeOfImpactCircleCircle({{-2.0 + 1e-9, 0.0}, 1.0}, Vec2{1.0, 5.0}, {{0.0, 0.0}, 1.0}, 5.0);
  ASSERT_TRUE(oblique.has_value());
  EXPECT_EQ(oblique->time, 0.0);
  EXPECT_TRUE(nearVec(oblique->normal, {-1.0, 0.0}, 1e-12));
}

TEST(TimeOfImpactCircleCircle, OverlappingAndSeparatingIsNone) {
  expectNone(rattle::timeOfImpactCircleCircle({{-2.0 + 1e-12, 0.0}, 1.0}, Vec2{-1.0, 0.0}, {{0.0, 0.0}, 1.0}, 5.0));
  expectNone(rattle::timeOfImpactCircleCircle({{-2.0 + 1e-12, 0.0}, 1.0}, Vec2{-1.0, 3.0}, {{0.0, 0.0}, 1.0}, 5.0));
  // A deep overlap that is separating: still no event (f' >= 0 and never turns negative).
  expectNone(rattle::timeOfImpactCircleCircle({{-1.5, 0.0}, 1.0}, Vec2{-1.0, 0.0}, {{0.0, 0.0}, 1.0}, 5.0));
}

TEST(TimeOfImpactCircleCircle, TouchingAndMovingTangentiallyIsNone) {
  // f(t) = |(-2, t)|^2 - 4 = t^2 >= 0: a double root at 0, not an event.
  expectNone(rattle::timeOfImpactCircleCircle({{-2.0, 0.0}, 1.0}, Vec2{0.0, 1.0}, {{0.0, 0.0}, 1.0}, 5.0));
  // Overlapping by round-off and moving tangentially: f'(0) = 0 and f' >= 0 afterwards -> none.
  expectNone(rattle::timeOfImpactCircleCircle({{-2.0 + 1e-12, 0.0}, 1.0}, Vec2{0.0, -1.0}, {{0.0, 0.0}, 1.0}, 5.0));
}

TEST(TimeOfImpactCircleCircle, MovingApartOrAtRestIsNone) {
  expectNone(rattle::timeOfImpactCircleCircle({{-5.0, 0.0}, 1.0}, Vec2{-1.0, 0.0}, {{0.0, 0.0}, 1.0}, 100.0));
  expectNone(rattle::timeOfImpactCircleCircle({{-5.0, 0.0}, 1.0}, Vec2{-1.0, 7.0}, {{0.0, 0.0}, 1.0}, 100.0));
  expectNone(rattle::timeOfImpactCircleCircle({{-5.0, 0.0}, 1.0}, Vec2{0.0, 0.0}, {{0.0, 0.0}, 1.0}, 100.0));
  expectNone(rattle::timeOfImpactCircleCircle({{-2.0, 0.0}, 1.0}, Vec2{0.0, 0.0}, {{0.0, 0.0}, 1.0}, 100.0));
}

TEST(TimeOfImpactCircleCircle, AfterMaxTimeIsNoneAndExactlyAtMaxTimeIsAnImpact) {
  // The head-on case hits at exactly t = 4 (see HeadOn).
  const Circle a{{-10.0, 0.0}, 1.0};
  const Circle b{{0.0, 0.0}, 1.0};
  expectNone(rattle::timeOfImpactCircleCircle(a, Vec2{2.0, 0.0}, b, 3.999));
  expectNone(rattle::timeOfImpactCircleCircle(a, Vec2{2.0, 0.0}, b, std::nextafter(4.0, 0.0)));
  const auto hit = rattle::timeOfImpactCircleCircle(a, Vec2{2.0, 0.0}, b, 4.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time, 4.0);
}

TEST(TimeOfImpactCircleCircle, ZeroRadiusMoverActsAsAPoint) {
  // A point at (-10,0) moving (2,0) reaches B's surface x = -1 at t = 9/2.
  const auto hit = rattle::timeOfImpactCircleCircle({{-10.0, 0.0}, 0.0}, Vec2{2.0, 0.0}, {{0.0, 0.0}, 1.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 4.5, {-1.0, 0.0}, {-1.0, 0.0}, 0));
}

TEST(TimeOfImpactCircleCircle, ExcludedFeatureIsIgnored) {
  // The touching-and-approaching case with feature 0 (the circle) excluded: nothing is left to hit.
  expectNone(rattle::timeOfImpactCircleCircle({{-2.0, 0.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}, 1.0}, 5.0, 0));
  // Excluding a feature the circle does not have changes nothing.
  const auto hit = rattle::timeOfImpactCircleCircle({{-10.0, 0.0}, 1.0}, Vec2{2.0, 0.0}, {{0.0, 0.0}, 1.0}, 10.0, 3);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 4.0, {-1.0, 0.0}, {-1.0, 0.0}, 0));
}

// =========================================================================================================
// Circle - point

TEST(TimeOfImpactCirclePoint, HeadOn) {
  // Centre (-10,0), radius 1, speed 2 toward (0,0): the gap of 9 closes at t = 4.5.
  const auto hit = rattle::timeOfImpactCirclePoint({{-10.0, 0.0}, 1.0}, Vec2{2.0, 0.0}, {{0.0, 0.0}}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 4.5, {0.0, 0.0}, {-1.0, 0.0}, 0));
}

TEST(TimeOfImpactCirclePoint, Oblique) {
  // Centre (-10,3), radius 5, velocity (1,0): (t - 10)^2 + 9 = 25 -> t - 10 = -4 -> t = 6. The centre is
  // then (-4,3): normal (-4,3)/5 = (-0.8, 0.6); point = the point itself. Exact: c = 84, b = -10, a = 1,
  // disc = 16, t = 84 / 14 = 6.
  const auto hit = rattle::timeOfImpactCirclePoint({{-10.0, 3.0}, 5.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 6.0, {0.0, 0.0}, {-0.8, 0.6}, 0));
  // Shifted point and centre by (7,-2): same answer, shifted point.
  const auto shifted = rattle::timeOfImpactCirclePoint({{-3.0, 1.0}, 5.0}, Vec2{1.0, 0.0}, {{7.0, -2.0}}, 10.0);
  expectImpact(shifted, 6.0, {7.0, -2.0}, {-0.8, 0.6}, 0);
}

TEST(TimeOfImpactCirclePoint, GrazingIsNone) {
  // Closest approach exactly equals the radius (1 = 1 and 5 = 5): tangent touches.
  expectNone(rattle::timeOfImpactCirclePoint({{-10.0, 1.0}, 1.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 100.0));
  expectNone(rattle::timeOfImpactCirclePoint({{-10.0, -5.0}, 5.0}, Vec2{2.0, 0.0}, {{0.0, 0.0}}, 100.0));
}

TEST(TimeOfImpactCirclePoint, TouchingCases) {
  const Circle a{{-4.0, 3.0}, 5.0};  // exactly touching (0,0): 16 + 9 = 25
  // Approaching: r.v = -4 < 0 -> t = 0, normal (-0.8, 0.6).
  const auto hit = rattle::timeOfImpactCirclePoint(a, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 0.0, {0.0, 0.0}, {-0.8, 0.6}, 0));
  EXPECT_EQ(hit->time, 0.0);
  // Separating.
  expectNone(rattle::timeOfImpactCirclePoint(a, Vec2{-1.0, 0.0}, {{0.0, 0.0}}, 10.0));
  // Tangential: v = (3,4) is perpendicular to r = (-4,3): r.v = 0.
  expectNone(rattle::timeOfImpactCirclePoint(a, Vec2{3.0, 4.0}, {{0.0, 0.0}}, 10.0));
  // Overlapping by round-off: approaching -> 0, separating -> none.
  const Circle over{{-4.0, 3.0}, 5.0 + 1e-12};
  const auto overHit = rattle::timeOfImpactCirclePoint(over, Vec2{0.5, -1.0}, {{0.0, 0.0}}, 10.0);
  ASSERT_TRUE(overHit.has_value());
  EXPECT_EQ(overHit->time, 0.0);
  expectNone(rattle::timeOfImpactCirclePoint(over, Vec2{-0.5, 1.0}, {{0.0, 0.0}}, 10.0));
}

TEST(TimeOfImpactCirclePoint, MovingApartAndMaxTime) {
  expectNone(rattle::timeOfImpactCirclePoint({{-10.0, 3.0}, 5.0}, Vec2{-1.0, 0.0}, {{0.0, 0.0}}, 100.0));
  // The oblique case hits at exactly t = 6.
  expectNone(rattle::timeOfImpactCirclePoint({{-10.0, 3.0}, 5.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 5.99));
  const auto hit = rattle::timeOfImpactCirclePoint({{-10.0, 3.0}, 5.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 6.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time, 6.0);
}

TEST(TimeOfImpactCirclePoint, ExcludedFeatureIsIgnored) {
  expectNone(rattle::timeOfImpactCirclePoint({{-4.0, 3.0}, 5.0}, Vec2{1.0, 0.0}, {{0.0, 0.0}}, 10.0, 0));
}

// =========================================================================================================
// Circle - segment

const Segment kFloor{{-2.0, 0.0}, {2.0, 0.0}};

TEST(TimeOfImpactCircleSegment, FromEitherSideTheNormalFlips) {
  // From above: centre y = 3 reaches y = r = 0.5 at t = 2.5; point (0.5, 0); normal (0, 1).
  expectImpact(rattle::timeOfImpactCircleSegment({{0.5, 3.0}, 0.5}, Vec2{0.0, -1.0}, kFloor, 10.0), 2.5,
               {0.5, 0.0}, {0.0, 1.0}, 0);
  // From below: centre y = -3 reaches y = -0.5 at t = 2.5; normal (0, -1).
  expectImpact(rattle::timeOfImpactCircleSegment({{0.5, -3.0}, 0.5}, Vec2{0.0, 1.0}, kFloor, 10.0), 2.5,
               {0.5, 0.0}, {0.0, -1.0}, 0);
  // The segment's direction (a -> b or b -> a) does not matter.
  const Segment reversed{kFloor.b, kFloor.a};
  expectImpact(rattle::timeOfImpactCircleSegment({{0.5, 3.0}, 0.5}, Vec2{0.0, -1.0}, reversed, 10.0), 2.5,
               {0.5, 0.0}, {0.0, 1.0}, 0);
  expectImpact(rattle::timeOfImpactCircleSegment({{0.5, -3.0}, 0.5}, Vec2{0.0, 1.0}, reversed, 10.0), 2.5,
               {0.5, 0.0}, {0.0, -1.0}, 0);
}

TEST(TimeOfImpactCircleSegment, Oblique) {
  // Centre (-3,4), radius 1, velocity (3,-3): y = 4 - 3t reaches 1 at t = 1, when the centre is at (0,1).
  expectImpact(rattle::timeOfImpactCircleSegment({{-3.0, 4.0}, 1.0}, Vec2{3.0, -3.0}, kFloor, 10.0), 1.0,
               {0.0, 0.0}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactCircleSegment, DiagonalSegment) {
  // Segment (0,0)-(4,4) on the line y = x. Centre (0,4), radius 1, velocity (1,-1): the centre stays on the
  // line x + y = 4, so the foot of the perpendicular is always (2,2), inside. Distance to the line is
  // |x - y| / sqrt2 = |2t - 4| / sqrt2 = 1 -> t = 2 - 1/sqrt2. Normal (-1,1)/sqrt2.
  expectImpact(rattle::timeOfImpactCircleSegment({{0.0, 4.0}, 1.0}, Vec2{1.0, -1.0}, {{0.0, 0.0}, {4.0, 4.0}}, 10.0),
               2.0 - 1.0 / kSqrt2, {2.0, 2.0}, {-1.0 / kSqrt2, 1.0 / kSqrt2}, 0);
}

TEST(TimeOfImpactCircleSegment, ZeroRadiusCrossesTheSegment) {
  // A point at (0.5, 3) moving down reaches y = 0 at t = 3.
  expectImpact(rattle::timeOfImpactCircleSegment({{0.5, 3.0}, 0.0}, Vec2{0.0, -1.0}, kFloor, 10.0), 3.0,
               {0.5, 0.0}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactCircleSegment, ParallelMotionIsNone) {
  expectNone(rattle::timeOfImpactCircleSegment({{-5.0, 3.0}, 0.5}, Vec2{1.0, 0.0}, kFloor, 100.0));
  expectNone(rattle::timeOfImpactCircleSegment({{-5.0, -3.0}, 0.5}, Vec2{-2.0, 0.0}, kFloor, 100.0));
  // Touching the segment and sliding along it.
  expectNone(rattle::timeOfImpactCircleSegment({{0.0, 0.5}, 0.5}, Vec2{1.0, 0.0}, kFloor, 100.0));
  expectNone(rattle::timeOfImpactCircleSegment({{0.0, -0.5}, 0.5}, Vec2{-1.0, 0.0}, kFloor, 100.0));
}

TEST(TimeOfImpactCircleSegment, EndOnAlongItsOwnLineIsNone) {
  // The segment's ends are not corners: a disk moving along the segment's line toward an end passes.
  expectNone(rattle::timeOfImpactCircleSegment({{-5.0, 0.0}, 0.5}, Vec2{1.0, 0.0}, kFloor, 100.0));
  expectNone(rattle::timeOfImpactCircleSegment({{5.0, 0.0}, 0.5}, Vec2{-1.0, 0.0}, kFloor, 100.0));
  expectNone(rattle::timeOfImpactCircleSegment({{-5.0, 0.0}, 0.0}, Vec2{1.0, 0.0}, kFloor, 100.0));
  // Diagonal segment, disk coming along its line from beyond b.
  expectNone(rattle::timeOfImpactCircleSegment({{10.0, 10.0}, 1.0}, Vec2{-1.0, -1.0}, {{0.0, 0.0}, {4.0, 4.0}},
                                               100.0));
}

TEST(TimeOfImpactCircleSegment, TouchingCases) {
  // Touching at (1,0) from above (centre y = 0.5 = r, exactly).
  const auto hit = rattle::timeOfImpactCircleSegment({{1.0, 0.5}, 0.5}, Vec2{0.0, -1.0}, kFloor, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 0.0, {1.0, 0.0}, {0.0, 1.0}, 0));
  EXPECT_EQ(hit->time, 0.0);
  // Overlapping by round-off and approaching obliquely -> t = 0.
  const auto over = rattle::timeOfImpactCircleSegment({{1.0, 0.5 - 1e-12}, 0.5}, Vec2{0.3, -1.0}, kFloor, 10.0);
  ASSERT_TRUE(over.has_value());
  EXPECT_EQ(over->time, 0.0);
  EXPECT_TRUE(nearVec(over->normal, {0.0, 1.0}));
  EXPECT_TRUE(nearVec(over->point, {1.0, 0.0}));
  // Overlapping by round-off from below and approaching: normal (0,-1).
  const auto below = rattle::timeOfImpactCircleSegment({{-1.0, -0.5 + 1e-12}, 0.5}, Vec2{0.0, 2.0}, kFloor, 10.0);
  ASSERT_TRUE(below.has_value());
  EXPECT_EQ(below->time, 0.0);
  EXPECT_TRUE(nearVec(below->normal, {0.0, -1.0}));
  // Overlapping and separating.
  expectNone(rattle::timeOfImpactCircleSegment({{1.0, 0.5 - 1e-12}, 0.5}, Vec2{0.0, 1.0}, kFloor, 10.0));
  expectNone(rattle::timeOfImpactCircleSegment({{1.0, 0.5 - 1e-12}, 0.5}, Vec2{-3.0, 1.0}, kFloor, 10.0));
  // Touching and separating.
  expectNone(rattle::timeOfImpactCircleSegment({{1.0, 0.5}, 0.5}, Vec2{0.0, 1.0}, kFloor, 10.0));
}

TEST(TimeOfImpactCircleSegment, MovingApartOrAfterMaxTimeIsNone) {
  expectNone(rattle::timeOfImpactCircleSegment({{0.0, 3.0}, 0.5}, Vec2{0.0, 1.0}, kFloor, 100.0));
  expectNone(rattle::timeOfImpactCircleSegment({{0.0, -3.0}, 0.5}, Vec2{0.3, -1.0}, kFloor, 100.0));
  // From above, impact at t = 2.5 (see FromEitherSideTheNormalFlips).
  expectNone(rattle::timeOfImpactCircleSegment({{0.5, 3.0}, 0.5}, Vec2{0.0, -1.0}, kFloor, 2.4));
}

TEST(TimeOfImpactCircleSegment, ImpactExactlyAtMaxTime) {
  // Gap 3 - 0.5 = 2.5 closed at speed 1: t = 2.5 exactly, inside [0, 2.5].
  const auto hit = rattle::timeOfImpactCircleSegment({{0.5, 3.0}, 0.5}, Vec2{0.0, -1.0}, kFloor, 2.5);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time, 2.5);
}

TEST(TimeOfImpactCircleSegment, ExcludedFeatureIsIgnored) {
  expectNone(rattle::timeOfImpactCircleSegment({{1.0, 0.5}, 0.5}, Vec2{0.0, -1.0}, kFloor, 10.0, 0));
}

// =========================================================================================================
// Circle - polyline

TEST(TimeOfImpactCirclePolyline, EndPointsCollide) {
  // Two points: segment 0 is feature 0, point 0 is corner 1, point 1 is corner 2.
  const Polyline line{{{-2.0, 0.0}, {2.0, 0.0}}};
  // Along the line from the left: centre x = -5 + t reaches -2.5 at t = 2.5; point (-2,0); normal (-1,0).
  expectImpact(rattle::timeOfImpactCirclePolyline({{-5.0, 0.0}, 0.5}, Vec2{1.0, 0.0}, line, 10.0), 2.5,
               {-2.0, 0.0}, {-1.0, 0.0}, 1);
  // From the right: hits point 1 = feature 2.
  expectImpact(rattle::timeOfImpactCirclePolyline({{5.0, 0.0}, 0.5}, Vec2{-1.0, 0.0}, line, 10.0), 2.5,
               {2.0, 0.0}, {1.0, 0.0}, 2);
  // Parallel at height 0.3: (x + 2)^2 + 0.09 = 0.25 -> x + 2 = -0.4 -> x = -2.4 at t = 2.6;
  // normal (-0.4, 0.3) / 0.5 = (-0.8, 0.6).
  expectImpact(rattle::timeOfImpactCirclePolyline({{-5.0, 0.3}, 0.5}, Vec2{1.0, 0.0}, line, 10.0), 2.6,
               {-2.0, 0.0}, {-0.8, 0.6}, 1);
  // The inside still collides: from above at x = 0.5.
  expectImpact(rattle::timeOfImpactCirclePolyline({{0.5, 3.0}, 0.5}, Vec2{0.0, -1.0}, line, 10.0), 2.5,
               {0.5, 0.0}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactCirclePolyline, CornerAlongASegmentsLine) {
  // Points (2,2), (0,0), (2,0): segment 0 is the diagonal (2,2)-(0,0), segment 1 is (0,0)-(2,0); corners
  // are features 2, 3, 4, and the corner (0,0) is point 1 -> feature 3.
  // A disk moving along segment 1's line (y = 0) from the left: the corner is hit when the centre reaches
  // (-0.5, 0): t = 4.5. (Segment 0's line y = x is reached earlier, at x = -sqrt2/2, but its foot
  // (-sqrt2/4, -sqrt2/4) is outside segment 0.)
  const Polyline corner{{{2.0, 2.0}, {0.0, 0.0}, {2.0, 0.0}}};
  expectImpact(rattle::timeOfImpactCirclePolyline({{-5.0, 0.0}, 0.5}, Vec2{1.0, 0.0}, corner, 10.0), 4.5,
               {0.0, 0.0}, {-1.0, 0.0}, 3);
  // The same motion against the lone Segment (0,0)-(2,0) passes its end.
  expectNone(rattle::timeOfImpactCircleSegment({{-5.0, 0.0}, 0.5}, Vec2{1.0, 0.0}, {{0.0, 0.0}, {2.0, 0.0}}, 10.0));
}

TEST(TimeOfImpactCirclePolyline, CornerOfAVFromOutside) {
  // V with corner (0,0): segment 0 (-2,2)-(0,0), segment 1 (0,0)-(2,2). From below the centre (0, y) is in
  // the corner's region; it reaches y = -0.5 at t = 2.5. Corner (0,0) is point 1 -> feature 2 + 1 = 3.
  const Polyline v{{{-2.0, 2.0}, {0.0, 0.0}, {2.0, 2.0}}};
  expectImpact(rattle::timeOfImpactCirclePolyline({{0.0, -3.0}, 0.5}, Vec2{0.0, 1.0}, v, 10.0), 2.5, {0.0, 0.0},
               {0.0, -1.0}, 3);
}

TEST(TimeOfImpactCirclePolyline, InsideAVBothArmsAtOnce) {
  // Inside the V, moving straight down: the disk touches both arms together when its centre (0, y) is
  // y / sqrt2 = 0.5 from each line -> y = sqrt2 / 2, t = 3 - sqrt2 / 2. Either arm may be reported; the
  // normal must match it: arm 0 (on y = -x) pushes along (1,1)/sqrt2, arm 1 (on y = x) along (-1,1)/sqrt2.
  const Polyline v{{{-2.0, 2.0}, {0.0, 0.0}, {2.0, 2.0}}};
  const auto hit = rattle::timeOfImpactCirclePolyline({{0.0, 3.0}, 0.5}, Vec2{0.0, -1.0}, v, 10.0);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->time, 3.0 - kSqrt2 / 2.0, tol(3.0));
  ASSERT_TRUE(hit->feature == 0 || hit->feature == 1) << hit->feature;
  if (hit->feature == 0) {
    EXPECT_TRUE(nearVec(hit->normal, {1.0 / kSqrt2, 1.0 / kSqrt2}));
    EXPECT_TRUE(nearVec(hit->point, {-0.25 * kSqrt2, 0.25 * kSqrt2}));
  } else {
    EXPECT_TRUE(nearVec(hit->normal, {-1.0 / kSqrt2, 1.0 / kSqrt2}));
    EXPECT_TRUE(nearVec(hit->point, {0.25 * kSqrt2, 0.25 * kSqrt2}));
  }
}

TEST(TimeOfImpactCirclePolyline, SegmentHitFromEitherSide) {
  // L shape: segment 0 (-20,0)-(0,0), segment 1 (0,0)-(0,20).
  const Polyline l{{{-20.0, 0.0}, {0.0, 0.0}, {0.0, 20.0}}};
  // Segment 0 from above (inside the L) and from below.
  expectImpact(rattle::timeOfImpactCirclePolyline({{-10.0, 4.0}, 1.0}, Vec2{0.0, -1.0}, l, 10.0), 3.0,
               {-10.0, 0.0}, {0.0, 1.0}, 0);
  expectImpact(rattle::timeOfImpactCirclePolyline({{-10.0, -4.0}, 1.0}, Vec2{0.0, 1.0}, l, 10.0), 3.0,
               {-10.0, 0.0}, {0.0, -1.0}, 0);
  // Segment 1 from the right (outside) and from the left (inside).
  expectImpact(rattle::timeOfImpactCirclePolyline({{6.0, 7.0}, 1.0}, Vec2{-2.0, 0.0}, l, 10.0), 2.5, {0.0, 7.0},
               {1.0, 0.0}, 1);
  expectImpact(rattle::timeOfImpactCirclePolyline({{-6.0, 7.0}, 1.0}, Vec2{2.0, 0.0}, l, 10.0), 2.5, {0.0, 7.0},
               {-1.0, 0.0}, 1);
}

TEST(TimeOfImpactCirclePolyline, ExcludedSegmentLeavesTheNextSegment) {
  // L shape as above; corners are features 2, 3, 4 (the corner (0,0) is 3). Disk radius 5 at (-10,5)
  // touches segment 0 exactly (foot (-10,0)) and moves (2,-1), toward it: impact now, feature 0.
  const Polyline l{{{-20.0, 0.0}, {0.0, 0.0}, {0.0, 20.0}}};
  const Circle a{{-10.0, 5.0}, 5.0};
  const auto first = rattle::timeOfImpactCirclePolyline(a, Vec2{2.0, -1.0}, l, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(first, 0.0, {-10.0, 0.0}, {0.0, 1.0}, 0));
  EXPECT_EQ(first->time, 0.0);
  // With segment 0 excluded the disk reaches segment 1 (x = 0) when its centre x = -10 + 2t = -5: t = 2.5,
  // centre (-5, 2.5), foot (0, 2.5) inside. The corner (0,0) would only be reached later:
  // (2t - 10)^2 + (5 - t)^2 = 25 -> (t - 5)^2 = 5 -> t = 5 - sqrt5 = 2.76.
  expectImpact(rattle::timeOfImpactCirclePolyline(a, Vec2{2.0, -1.0}, l, 10.0, 0), 2.5, {0.0, 2.5}, {-1.0, 0.0}, 1);
  // Excluding an unrelated feature changes nothing.
  expectImpact(rattle::timeOfImpactCirclePolyline(a, Vec2{2.0, -1.0}, l, 10.0, 4), 0.0, {-10.0, 0.0}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactCirclePolyline, ExcludedCornerLeavesTheOtherSegment) {
  // Points (10,2), (0,0), (10,-2), (10,-30), (-30,-30): a narrow V with its tip at (0,0), then a wall x = 10
  // and a floor y = -30. Segments 0..3; corners 4..8; the tip is point 1 -> feature 5; the floor is
  // segment 3.
  const Polyline p{{{10.0, 2.0}, {0.0, 0.0}, {10.0, -2.0}, {10.0, -30.0}, {-30.0, -30.0}}};
  // Disk radius 5 at (-3,4) touches the tip exactly (9 + 16 = 25), in the tip's region (the arms run to
  // the right), and moves (-1,-3): r.v = (-3)(-1) + 4(-3) = -9 < 0, approaching -> t = 0; normal (-0.6, 0.8).
  const Circle a{{-3.0, 4.0}, 5.0};
  const Vec2 v{-1.0, -3.0};
  const auto first = rattle::timeOfImpactCirclePolyline(a, v, p, 20.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(first, 0.0, {0.0, 0.0}, {-0.6, 0.8}, 5));
  EXPECT_EQ(first->time, 0.0);
  // With the tip excluded: x = -3 - t only decreases, so the arms (x >= 0) are never reached; the floor
  // y = -30 is reached when 4 - 3t = -25: t = 29/3, centre x = -3 - 29/3 = -38/3 (inside [-30, 10]).
  expectImpact(rattle::timeOfImpactCirclePolyline(a, v, p, 20.0, 5), 29.0 / 3.0, {-38.0 / 3.0, -30.0},
               {0.0, 1.0}, 3);
}

TEST(TimeOfImpactCirclePolyline, TouchingSeparatingTangentialAndMaxTime) {
  const Polyline line{{{-2.0, 0.0}, {2.0, 0.0}}};
  // Touching the end (-2,0) from the left and leaving: none.
  expectNone(rattle::timeOfImpactCirclePolyline({{-2.5, 0.0}, 0.5}, Vec2{-1.0, 0.0}, line, 10.0));
  // Touching the inside and sliding along it, then past the end (a tangent touch at the end corner too:
  // (x - 2)^2 + 0.25 = 0.25 only at x = 2): none.
  expectNone(rattle::timeOfImpactCirclePolyline({{0.0, 0.5}, 0.5}, Vec2{1.0, 0.0}, line, 10.0));
  // Moving apart.
  expectNone(rattle::timeOfImpactCirclePolyline({{0.0, 3.0}, 0.5}, Vec2{0.0, 1.0}, line, 10.0));
  // The end is hit at t = 2.5 exactly.
  expectNone(rattle::timeOfImpactCirclePolyline({{-5.0, 0.0}, 0.5}, Vec2{1.0, 0.0}, line, 2.49));
  const auto hit = rattle::timeOfImpactCirclePolyline({{-5.0, 0.0}, 0.5}, Vec2{1.0, 0.0}, line, 2.5);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time, 2.5);
}

// =========================================================================================================
// Circle - polygon

TEST(TimeOfImpactCirclePolygon, Edges) {
  // Top edge (2): centre y = 5 - 2t reaches 1 + 1 = 2 at t = 1.5; point (0.5, 1); normal (0, 1).
  expectImpact(rattle::timeOfImpactCirclePolygon({{0.5, 5.0}, 1.0}, Vec2{0.0, -2.0}, square(), 10.0), 1.5,
               {0.5, 1.0}, {0.0, 1.0}, 2);
  // Right edge (1): x = 5 - t reaches 2 at t = 3.
  expectImpact(rattle::timeOfImpactCirclePolygon({{5.0, 0.25}, 1.0}, Vec2{-1.0, 0.0}, square(), 10.0), 3.0,
               {1.0, 0.25}, {1.0, 0.0}, 1);
  // Left edge (3).
  expectImpact(rattle::timeOfImpactCirclePolygon({{-5.0, -0.25}, 1.0}, Vec2{1.0, 0.0}, square(), 10.0), 3.0,
               {-1.0, -0.25}, {-1.0, 0.0}, 3);
  // Bottom edge (0): y = -4 + 0.5t reaches -1.5 at t = 5.
  expectImpact(rattle::timeOfImpactCirclePolygon({{0.3, -4.0}, 0.5}, Vec2{0.0, 0.5}, square(), 10.0), 5.0,
               {0.3, -1.0}, {0.0, -1.0}, 0);
}

TEST(TimeOfImpactCirclePolygon, SlantedEdge) {
  // Triangle (0,0), (4,0), (0,3), counter-clockwise. Edge 1 runs (4,0) -> (0,3) on 3x + 4y = 12, outward
  // normal (0.6, 0.8). Start 6 along the normal from the edge's midpoint (2, 1.5): (5.6, 6.3); radius 1,
  // speed 2 straight back: the gap of 5 closes at t = 2.5; point (2, 1.5).
  const Polygon tri{{{0.0, 0.0}, {4.0, 0.0}, {0.0, 3.0}}};
  expectImpact(rattle::timeOfImpactCirclePolygon({{5.6, 6.3}, 1.0}, Vec2{-1.2, -1.6}, tri, 10.0), 2.5, {2.0, 1.5},
               {0.6, 0.8}, 1);
}

TEST(TimeOfImpactCirclePolygon, Corners) {
  // Straight at corner (1,1) (point 2 -> feature 4 + 2 = 6) along the diagonal from (5,5): the distance 4
  // sqrt2 less the radius 1, at speed sqrt2 -> t = 4 - 1/sqrt2. Stable form: r = (4,4), c = 31, b = -8,
  // a = 2, disc = 2, t = 31 / (8 + sqrt2) = (8 - sqrt2) / 2.
  expectImpact(rattle::timeOfImpactCirclePolygon({{5.0, 5.0}, 1.0}, Vec2{-1.0, -1.0}, square(), 10.0),
               4.0 - 1.0 / kSqrt2, {1.0, 1.0}, {1.0 / kSqrt2, 1.0 / kSqrt2}, 6);
  // Horizontally at height -1.8 toward corner (1,-1) (point 1 -> feature 5): the right edge's span y in
  // [-1,1] is never reached; the corner is at distance 1 when the centre is (1 + 0.6, -1.8): x = 6 - t =
  // 1.6 -> t = 4.4; normal (0.6, -0.8).
  expectImpact(rattle::timeOfImpactCirclePolygon({{6.0, -1.8}, 1.0}, Vec2{-1.0, 0.0}, square(), 10.0), 4.4,
               {1.0, -1.0}, {0.6, -0.8}, 5);
}

TEST(TimeOfImpactCirclePolygon, ClockwiseInputAfterNormalized) {
  // The same top-edge hit on a clockwise square passed through normalized(): the feature is the index of
  // the edge (1,1) -> (-1,1) in the normalized point list.
  const Polygon cw{{{-1.0, -1.0}, {-1.0, 1.0}, {1.0, 1.0}, {1.0, -1.0}}};
  const Polygon ccw = std::get<Polygon>(rattle::normalized(cw));
  ASSERT_EQ(ccw.points.size(), 4u);
  int top = -1;
  for (int i = 0; i < 4; ++i)
    if (ccw.points[i] == Vec2{1.0, 1.0} && ccw.points[(i + 1) % 4] == Vec2{-1.0, 1.0}) top = i;
  ASSERT_GE(top, 0) << "normalized() did not wind the square counter-clockwise";
  expectImpact(rattle::timeOfImpactCirclePolygon({{0.5, 5.0}, 1.0}, Vec2{0.0, -2.0}, ccw, 10.0), 1.5, {0.5, 1.0},
               {0.0, 1.0}, top);
}

TEST(TimeOfImpactCirclePolygon, CentreDeepInsideIsNone) {
  // Centre (0,0), radius 0.5: 1 behind every edge, more than its radius.
  for (Vec2 v : {Vec2{1.0, 0.0}, Vec2{0.0, -3.0}, Vec2{7.0, 7.0}, Vec2{-0.1, 0.2}})
    expectNone(rattle::timeOfImpactCirclePolygon({{0.0, 0.0}, 0.5}, v, square(), 10.0));
  expectNone(rattle::timeOfImpactCirclePolygon({{0.2, -0.3}, 0.0}, Vec2{5.0, 1.0}, square(), 10.0));
}

TEST(TimeOfImpactCirclePolygon, TouchingCases) {
  // Touching the right edge at (1,0) (centre x = 1.5 = 1 + r exactly) and approaching: t = 0, feature 1.
  const auto hit = rattle::timeOfImpactCirclePolygon({{1.5, 0.0}, 0.5}, Vec2{-1.0, 0.0}, square(), 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 0.0, {1.0, 0.0}, {1.0, 0.0}, 1));
  EXPECT_EQ(hit->time, 0.0);
  // Overlapping by round-off and approaching obliquely: t = 0, feature 1.
  const auto over = rattle::timeOfImpactCirclePolygon({{1.5 - 1e-12, 0.2}, 0.5}, Vec2{-1.0, 0.5}, square(), 10.0);
  ASSERT_TRUE(over.has_value());
  EXPECT_EQ(over->time, 0.0);
  EXPECT_EQ(over->feature, 1);
  EXPECT_TRUE(nearVec(over->normal, {1.0, 0.0}));
  // Overlapping and separating.
  expectNone(rattle::timeOfImpactCirclePolygon({{1.5 - 1e-12, 0.0}, 0.5}, Vec2{1.0, 0.0}, square(), 10.0));
  expectNone(rattle::timeOfImpactCirclePolygon({{1.5 - 1e-12, 0.0}, 0.5}, Vec2{1.0, -4.0}, square(), 10.0));
  // Touching and sliding along the edge, past the corner (1,1): for that corner r = (0.5, -1), v = (0,1),
  // b = -1, a = 1, c = 1.25 - 0.25 = 1, disc = b^2 - ac = 0: a tangent touch, not an impact.
  expectNone(rattle::timeOfImpactCirclePolygon({{1.5, 0.0}, 0.5}, Vec2{0.0, 1.0}, square(), 10.0));
  // Touching a corner exactly (3-4-5 at corner (1,1), radius 5) and approaching it: t = 0, feature 6.
  const auto corner = rattle::timeOfImpactCirclePolygon({{4.0, 5.0}, 5.0}, Vec2{-1.0, -1.0}, square(), 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(corner, 0.0, {1.0, 1.0}, {0.6, 0.8}, 6));
}

// A circle wider than a thin polygon, its centre outside it (above the top edge): the bottom edge's line is
// less than a radius below the centre, but the centre is on the top edge's side, and only the edges it is
// in front of hold it. The slab [-1,1] x [-0.25,0.25] (edges: 0 bottom, 1 right, 2 top, 3 left), circle
// of radius 5 centred at (0, 4.1): it overlaps the top edge by 0.65 and reaches 4.35 below the slab's bottom
// line. Moving down: the top edge at once (normal +y, point (0, 0.25)). Moving up, away from the top edge:
// nothing (the bottom edge, met as if from below, bounced it back into the top one).
TEST(TimeOfImpactCirclePolygon, AWideCircleOverAThinPolygonMeetsOnlyTheNearEdges) {
  const Polygon slab{{{-1.0, -0.25}, {1.0, -0.25}, {1.0, 0.25}, {-1.0, 0.25}}};
  ASSERT_NO_FATAL_FAILURE(expectImpact(rattle::timeOfImpactCirclePolygon({{0.0, 4.1}, 5.0}, Vec2{0.0, -3.0}, slab, 1.0),
                                       0.0, {0.0, 0.25}, {0.0, 1.0}, 2));
  expectNone(rattle::timeOfImpactCirclePolygon({{0.0, 4.1}, 5.0}, Vec2{0.0, 3.0}, slab, 1.0));
  expectNone(rattle::timeOfImpactCirclePolygon({{0.0, 4.1}, 5.0}, Vec2{-2.0, 3.0}, slab, 1.0));
  // A centre inside keeps the overlap rules of every edge it is within a radius of: (0, 0.1), radius 0.5,
  // moving down, 0.15 behind the top edge's line, goes deeper behind it, and the top edge meets it at once
  // (the modes let a disk made so pass through, by the pair's made-overlapping exemption, not here).
  const auto inside = rattle::timeOfImpactCirclePolygon({{0.0, 0.1}, 0.5}, Vec2{0.0, -1.0}, slab, 1.0);
  ASSERT_TRUE(inside.has_value());
  EXPECT_EQ(inside->time, 0.0);
  EXPECT_EQ(inside->feature, 2);
}

// A corner is the contact only where it is the polygon's nearest point: a circle over the bottom edge of the
// square, overlapping it by 0.05 near corner (-1,-1) (centre (-0.8, -1.45), radius 0.5, 0.492 from the
// corner), sliding along the edge toward the corner and past it, meets nothing: its centre is over the edge,
// whose face it moves along, until it is past the corner's perpendicular, and from there it moves away from
// the corner. (Taken as met at once by the corner, normal (0.41, -0.91), a speck of radius 1e-12 lying so
// over a polygon's corner was pushed into a disk pressing it back, at one instant, without end.)
TEST(TimeOfImpactCirclePolygon, ACornerIsNotMetOverAnEdge) {
  expectNone(rattle::timeOfImpactCirclePolygon({{-0.8, -1.45}, 0.5}, Vec2{-1.0, 0.0}, square(), 10.0));
  // From the corner's own region (left of x = -1, below y = -1) and approaching it, the corner is met.
  const auto corner = rattle::timeOfImpactCirclePolygon({{-1.3, -1.4}, 0.5}, Vec2{1.0, 1.0}, square(), 10.0);
  ASSERT_TRUE(corner.has_value());
  EXPECT_EQ(corner->time, 0.0);
  EXPECT_EQ(corner->feature, 4);
  EXPECT_TRUE(nearVec(corner->normal, Vec2{-0.6, -0.8}));
}

TEST(TimeOfImpactCirclePolygon, ImpactExactlyAtMaxTime) {
  // The top-edge hit (see Edges) is at t = (5 - 1 - 1) / 2 = 1.5 exactly.
  const auto hit = rattle::timeOfImpactCirclePolygon({{0.5, 5.0}, 1.0}, Vec2{0.0, -2.0}, square(), 1.5);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->time, 1.5);
  // A corner hit exactly at maxTime: corner (1,-1) reached at t = 4.4 (see Corners); 4.4 is not exact, so
  // take maxTime from the unbounded answer.
  const auto corner = rattle::timeOfImpactCirclePolygon({{6.0, -1.8}, 1.0}, Vec2{-1.0, 0.0}, square(), 10.0);
  ASSERT_TRUE(corner.has_value());
  const auto again = rattle::timeOfImpactCirclePolygon({{6.0, -1.8}, 1.0}, Vec2{-1.0, 0.0}, square(), corner->time);
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->time, corner->time);
}

TEST(TimeOfImpactCirclePolygon, MovingApartOrAfterMaxTimeIsNone) {
  expectNone(rattle::timeOfImpactCirclePolygon({{0.5, 5.0}, 1.0}, Vec2{0.0, 2.0}, square(), 10.0));
  expectNone(rattle::timeOfImpactCirclePolygon({{0.5, 5.0}, 1.0}, Vec2{3.0, 0.0}, square(), 10.0));
  // The top-edge hit is at t = 1.5 exactly.
  expectNone(rattle::timeOfImpactCirclePolygon({{0.5, 5.0}, 1.0}, Vec2{0.0, -2.0}, square(), 1.49));
  // A miss: passes to the right of the square (distance 2 > 1 from the corner (1,1) at closest approach).
  expectNone(rattle::timeOfImpactCirclePolygon({{3.0, 5.0}, 1.0}, Vec2{0.0, -1.0}, square(), 100.0));
}

TEST(TimeOfImpactCirclePolygon, ExcludedEdgeIsIgnored) {
  // Touching the right edge and approaching, edge 1 excluded: moving left through the square the disk never
  // comes within 0.5 of the corners (1,+-1) (their distance is at least 1) and meets the other edges only from
  // behind, so nothing is left.
  expectNone(rattle::timeOfImpactCirclePolygon({{1.5, 0.0}, 0.5}, Vec2{-1.0, 0.0}, square(), 10.0, 1));
  // Excluding another feature leaves the edge.
  const auto hit = rattle::timeOfImpactCirclePolygon({{1.5, 0.0}, 0.5}, Vec2{-1.0, 0.0}, square(), 10.0, 6);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->feature, 1);
  EXPECT_EQ(hit->time, 0.0);
}

// A face or corner the circle cannot reach within maxTime is skipped without solving for it (its centre
// moves at most |v| T + |a| T^2 / 2): at the edge of that reach the answer must still be the analytic one.
TEST(TimeOfImpactReach, AFaceOrCornerJustWithinReachIsMetAndJustBeyondIsNot) {
  // Falling onto the floor of a closed box: 2.5 = 4 t + 4.905 t^2 (the gap from y 3 - 0.5 to the floor).
  const Polyline box{{{-5.0, 0.0}, {5.0, 0.0}, {5.0, 10.0}, {-5.0, 10.0}, {-5.0, 0.0}}};
  const rattle::Circle disk{{1.0, 3.0}, 0.5};
  const rattle::Motion fall{{0.0, -4.0}, {0.0, -9.81}};
  const double fallTime = (-4.0 + std::sqrt(16.0 + 4 * 4.905 * 2.5)) / (2 * 4.905);
  // Toward the corner (1, 1) of the square from (3, 3): the distance 2 sqrt 2 closes to 0.5 at speed 2.
  const rattle::Circle outside{{3.0, 3.0}, 0.5};
  const Vec2 diagonal{-std::sqrt(2.0), -std::sqrt(2.0)};
  const double cornerTime = (2 * std::sqrt(2.0) - 0.5) / 2;
  // Along an open Polyline's line into its end (1, 1) from (3, 1): 1.5 at speed 3.
  const Polyline open{{{-1.0, 1.0}, {1.0, 1.0}}};
  const rattle::Circle beside{{3.0, 1.0}, 0.5};
  const double endTime = 0.5;
  // The same diagonal into the joint (1, 1) of a bent Polyline whose third segment lies far off: the
  // joint is met, though one segment beyond it is out of reach.
  const Polyline bend{{{-3.0, 1.0}, {1.0, 1.0}, {1.0, -3.0}, {100.0, -3.0}}};
  for (const double share : {1 - 1e-3, 1 - 1e-9, 1 + 1e-9, 1 + 1e-3}) {
    SCOPED_TRACE(share);
    const auto floor = rattle::timeOfImpactCirclePolyline(disk, fall, box, fallTime * share);
    const auto corner = rattle::timeOfImpactCirclePolygon(outside, diagonal, square(), cornerTime * share);
    const auto end = rattle::timeOfImpactCirclePolyline(beside, Vec2{-3.0, 0.0}, open, endTime * share);
    const auto joint = rattle::timeOfImpactCirclePolyline(outside, diagonal, bend, cornerTime * share);
    if (share < 1) {
      expectNone(floor);
      expectNone(corner);
      expectNone(end);
      expectNone(joint);
      continue;
    }
    ASSERT_TRUE(floor && corner && end && joint);
    EXPECT_NEAR(joint->time, cornerTime, 1e-14);
    EXPECT_EQ(joint->feature, 3 + 1);  // the Polyline's corner 1
    EXPECT_NEAR(floor->time, fallTime, 1e-14);
    EXPECT_EQ(floor->feature, 0);
    EXPECT_NEAR(corner->time, cornerTime, 1e-14);
    EXPECT_EQ(corner->feature, 4 + 2);  // corner 2 of square(): (1, 1)
    EXPECT_NEAR(end->time, endTime, 1e-14);
    EXPECT_EQ(end->feature, 1 + 1);  // the Polyline's corner 1, its end
  }
}

// =========================================================================================================
// A point (radius 0) on a line: round-off decides nothing

TEST(TimeOfImpactPointOnALine, AlongABottomEdgeIntoTheNextEdgeAtItsEnd) {
  // A point runs left along the line y = -1 of the square's bottom edge, an ulp below it (where round-off
  // puts a point sliding on the seam between this square and a floor that shares the line), and meets
  // the right edge x = 1 at its end: at t = (3 - 1) / 2 = 1, pushed back along +x. Without slack the right
  // edge's tau is an ulp outside, the corner (reach 0) is missed off the exact line, and the point passed
  // under the square.
  const double below = std::nextafter(-1.0, -2.0);
  expectImpact(rattle::timeOfImpactCirclePolygon({{3.0, below}, 0.0}, Vec2{-2.0, 0.0}, square(), 10.0), 1.0,
               {1.0, -1.0}, {1.0, 0.0}, 1);
}

TEST(TimeOfImpactPointOnALine, AnUlpBelowABoxsFloorIntoAWallThatIsABareSegment) {
  // A box of four bare segments: its right wall x = 1 runs up from the corner (1, -1), where the floor
  // y = -1 ends. A point sliding right an ulp below the floor's line (where round-off leaves it) crosses
  // the wall's line an ulp beyond the wall's end, at t = (1 - -3) / 4 = 1: that ulp is round-off, so it
  // meets the wall's face there, pushed back along -x. Without it the point left the box through its
  // corner. A point passing a bare segment's end by more than round-off still meets nothing.
  const double below = std::nextafter(-1.0, -2.0);
  const rattle::Segment wall{{1.0, -1.0}, {1.0, 1.0}};
  expectImpact(rattle::timeOfImpactCircleSegment({{-3.0, below}, 0.0}, Vec2{4.0, 0.0}, wall, 10.0), 1.0,
               {1.0, -1.0}, {-1.0, 0.0}, 0);
  expectNone(rattle::timeOfImpactCircleSegment({{-3.0, -1.0 - 1e-9}, 0.0}, Vec2{4.0, 0.0}, wall, 10.0));
}

TEST(TimeOfImpactPointOnALine, AnUlpInsideAPolygonFaceAndPressedIntoItIsAContactNow) {
  // At rest an ulp inside the top face y = 1 (s0 = -ulp), gravity pressing it in: touching and
  // approaching, so now, with the face's normal. A circle of radius 0 has no overlap to tell it is still
  // in front, and used to be taken for one deep inside (no impact: it fell through).
  const double inside = std::nextafter(1.0, 0.0);
  expectImpact(rattle::timeOfImpactCirclePolygon({{0.25, inside}, 0.0}, rattle::Motion{{0.0, 0.0}, {0.0, -9.81}},
                                                 square(), 1.0),
               0.0, {0.25, 1.0}, {0.0, 1.0}, 2, 1e-15);
}

TEST(TimeOfImpactPointOnALine, LeavingAFloorItWasJustResolvedAgainstComesBack) {
  // On the floor y = 0 of a polyline, just bounced off it (feature 0 resolved at this instant) at 0.5
  // upward under gravity 10: back at t = 2 v / g = 0.1, from above.
  const Polyline floor{{{-5.0, 0.0}, {5.0, 0.0}}};
  const rattle::Motion up{{1.0, 0.5}, {0.0, -10.0}};
  expectImpact(rattle::timeOfImpactCirclePolyline({{0.0, 0.0}, 0.0}, up, floor, 1.0, 0), 0.1, {0.1, 0.0},
               {0.0, 1.0}, 0);
  // Not just resolved there, the same point has arrived at the line from below: a contact now.
  expectImpact(rattle::timeOfImpactCirclePolyline({{0.0, 0.0}, 0.0}, up, floor, 1.0), 0.0, {0.0, 0.0},
               {0.0, -1.0}, 0);
}

TEST(TimeOfImpactPointOnALine, SlidingAlongAFloorIntoAWallAtTheCorner) {
  // A box's floor and left wall as one polyline (corner at the origin). A point sliding left exactly
  // along the floor, pressed into it by gravity, is in contact with the floor now; with the floor's
  // contact resolved, it meets the wall at its end at t = 2 / 4 = 0.5, pushed back along +x.
  const Polyline corner{{{0.0, 5.0}, {0.0, 0.0}, {5.0, 0.0}}};
  const rattle::Motion sliding{{-4.0, 0.0}, {0.0, -9.81}};
  expectImpact(rattle::timeOfImpactCirclePolyline({{2.0, 0.0}, 0.0}, sliding, corner, 1.0), 0.0, {2.0, 0.0},
               {0.0, 1.0}, 1);
  const rattle::Motion along{Vec2{-4.0, 0.0}};
  expectImpact(rattle::timeOfImpactCirclePolyline({{2.0, 0.0}, 0.0}, along, corner, 1.0, 1), 0.5, {0.0, 0.0},
               {1.0, 0.0}, 0);
}

TEST(TimeOfImpactPointOnALine, MovingAlongASlopedPolygonEdgeMeetsItAtNoTimeAndSoDoesADisk) {
  // A point on the line of a polygon's edge at angle theta (placed there in doubles, so within round-off
  // of it) moving and accelerating along the edge: its normal velocity and acceleration are round-off,
  // so it meets the edge at no time, whether or not that edge was just resolved (a slide). Read from the
  // round-off, it met the edge at once at 113 of these 359 angles, and a world dismissed and predicted it
  // again at that instant until its budget ran out. Within maxTime 0.5 it travels 2 * 0.5 + 3 * 0.5^2 / 2
  // = 1.375 of the 5 to the edge's end, so no other feature is in reach either. The same point moving
  // into the edge (an inward normal speed of 0.5) meets it now (within the round-off of its place).
  for (int degrees = 1; degrees < 360; ++degrees) {
    SCOPED_TRACE(degrees);
    const double theta = degrees * std::numbers::pi / 180;
    const Vec2 u{std::cos(theta), std::sin(theta)}, inward{-u.y, u.x};
    const Polygon quad{{{0.0, 0.0}, u * 10.0, u * 10.0 + inward * 2.0, inward * 2.0}};
    const Circle point{u * 5.0, 0.0};
    const rattle::Motion along{u * 2.0, u * 3.0};
    expectNone(rattle::timeOfImpactCirclePolygon(point, along, quad, 0.5));
    expectNone(rattle::timeOfImpactCirclePolygon(point, along, quad, 0.5, 0));
    // So too a disk of radius 0.5 touching the edge (its centre 0.5 out of it, in doubles), sliding.
    const Circle disk{u * 5.0 - inward * 0.5, 0.5};
    expectNone(rattle::timeOfImpactCirclePolygon(disk, along, quad, 0.5));
    expectNone(rattle::timeOfImpactCirclePolygon(disk, along, quad, 0.5, 0));
    const auto into = rattle::timeOfImpactCirclePolygon(point, rattle::Motion{u * 2.0 + inward * 0.5, u * 3.0}, quad, 0.5);
    ASSERT_TRUE(into.has_value());
    EXPECT_NEAR(into->time, 0.0, 1e-14);  // the point may lie an ulp off the line
    EXPECT_EQ(into->feature, 0);
  }
}

// =========================================================================================================
// The dispatcher

TEST(TimeOfImpactDispatch, CircleCircleWithPositions) {
  // World centres (90,50) and (100,50), radii 1 + 1, relative velocity (2,0): t = 4 (see HeadOn); the point
  // is on B's surface in world coordinates: (99, 50).
  const auto hit = rattle::timeOfImpact(Circle{{1.0, 0.0}, 1.0}, {89.0, 50.0}, Circle{{-1.0, 0.0}, 1.0},
                                        {101.0, 50.0}, Vec2{2.0, 0.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 4.0, {99.0, 50.0}, {-1.0, 0.0}, 0));
}

TEST(TimeOfImpactDispatch, CircleAgainstEachOtherType) {
  const Circle disk{{0.0, 0.0}, 0.5};
  // Segment at (10,10): from (-2,0)-(2,0) to (8,10)-(12,10). Disk at (10.5, 13) moving (0,-1): t = 2.5.
  expectImpact(rattle::timeOfImpact(disk, {10.5, 13.0}, Segment{{-2.0, 0.0}, {2.0, 0.0}}, {10.0, 10.0},
                                    Vec2{0.0, -1.0}, 10.0),
               2.5, {10.5, 10.0}, {0.0, 1.0}, 0);
  // Point at (3,-1) (geometry (1,0) at position (2,-1)); disk radius 5 at (-7, 2) moving (1,0): relative to
  // the point this is CirclePoint.Oblique -> t = 6, normal (-0.8, 0.6).
  expectImpact(rattle::timeOfImpact(Circle{{0.0, 0.0}, 5.0}, {-7.0, 2.0}, Point{{1.0, 0.0}}, {2.0, -1.0},
                                    Vec2{1.0, 0.0}, 10.0),
               6.0, {3.0, -1.0}, {-0.8, 0.6}, 0);
  // Polyline end (see CirclePolyline.EndPointsCollide), shifted by (100, 0).
  expectImpact(rattle::timeOfImpact(disk, {95.0, 0.0}, Polyline{{{-2.0, 0.0}, {2.0, 0.0}}}, {100.0, 0.0},
                                    Vec2{1.0, 0.0}, 10.0),
               2.5, {98.0, 0.0}, {-1.0, 0.0}, 1);
  // Square at (0, 20): top-edge hit (see CirclePolygon.Edges) shifted by (0, 20).
  expectImpact(rattle::timeOfImpact(Circle{{0.5, 0.0}, 1.0}, {0.0, 25.0}, square(), {0.0, 20.0}, Vec2{0.0, -2.0},
                                    10.0),
               1.5, {0.5, 21.0}, {0.0, 1.0}, 2);
}

TEST(TimeOfImpactDispatch, PointMovesAsAZeroRadiusCircle) {
  // Point A at (0.5, 3) moving (0,-1) onto the segment y = 0: t = 3.
  expectImpact(rattle::timeOfImpact(Point{{0.5, 3.0}}, {0.0, 0.0}, Segment{{-2.0, 0.0}, {2.0, 0.0}}, {0.0, 0.0},
                                    Vec2{0.0, -1.0}, 10.0),
               3.0, {0.5, 0.0}, {0.0, 1.0}, 0);
  // Point A at (-10, 0) moving (2,0) onto circle B of radius 1 at the origin: t = 4.5, point (-1, 0).
  expectImpact(rattle::timeOfImpact(Point{{0.0, 0.0}}, {-10.0, 0.0}, Circle{{0.0, 0.0}, 1.0}, {0.0, 0.0},
                                    Vec2{2.0, 0.0}, 10.0),
               4.5, {-1.0, 0.0}, {-1.0, 0.0}, 0);
  // Point A into the square's right edge: x = 5 - t reaches 1 at t = 4.
  expectImpact(rattle::timeOfImpact(Point{{5.0, 0.25}}, {0.0, 0.0}, square(), {0.0, 0.0}, Vec2{-1.0, 0.0}, 10.0),
               4.0, {1.0, 0.25}, {1.0, 0.0}, 1);
}

// When only B is a circle (or point), the dispatcher swaps roles: B moves with -relativeVelocity relative
// to A, the normal still points from B toward A, and `feature` names a part of A. The point is read in the
// same frame as for the unswapped order: B stays at positionB and A moves with relativeVelocity, so the
// point is where they touch at `time` = (contact point on A at rest) + relativeVelocity * time.
// (The header only says "world coordinates"; this is the one frame that reads the same for both orders.)
TEST(TimeOfImpactDispatch, SwappedSegmentAndCircle) {
  // A = segment (8,10)-(12,10), B = disk radius 0.5 at (10.5, 13). A moves (0,1) relative to B, so B moves
  // (0,-1) relative to A: B's centre reaches y = 10.5 at t = 2.5. B is above A, so the normal from B toward
  // A is (0,-1). With B held at (10.5, 13), A has risen by 2.5: the contact is at (10.5, 12.5).
  const auto hit = rattle::timeOfImpact(Segment{{-2.0, 0.0}, {2.0, 0.0}}, {10.0, 10.0}, Circle{{0.0, 0.0}, 0.5},
                                        {10.5, 13.0}, Vec2{0.0, 1.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 2.5, {10.5, 12.5}, {0.0, -1.0}, 0));
  // Moving apart: none.
  expectNone(rattle::timeOfImpact(Segment{{-2.0, 0.0}, {2.0, 0.0}}, {10.0, 10.0}, Circle{{0.0, 0.0}, 0.5},
                                  {10.5, 13.0}, Vec2{0.0, -1.0}, 10.0));
  // Touching now (time 0: no frame ambiguity): B's centre at (10.5, 10.5), A approaching B.
  const auto now = rattle::timeOfImpact(Segment{{-2.0, 0.0}, {2.0, 0.0}}, {10.0, 10.0}, Circle{{0.0, 0.0}, 0.5},
                                        {10.5, 10.5}, Vec2{0.0, 1.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(now, 0.0, {10.5, 10.0}, {0.0, -1.0}, 0));
}

TEST(TimeOfImpactDispatch, SwappedPolygonAndCircle) {
  // A = the square at (100,-50); B = disk radius 1 at (105, -49.75). A moves (1,0) relative to B, so B moves
  // (-1,0) relative to A and meets A's right edge (feature 1) when its centre x = 102: t = 3. The normal
  // from B toward A is (-1,0); the point is (101, -49.75) on A at rest, plus A's displacement (3,0):
  // (104, -49.75), the leftmost point of B.
  const auto hit = rattle::timeOfImpact(square(), {100.0, -50.0}, Circle{{0.0, 0.0}, 1.0}, {105.0, -49.75},
                                        Vec2{1.0, 0.0}, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 3.0, {104.0, -49.75}, {-1.0, 0.0}, 1));
  // B deep inside A: none.
  expectNone(rattle::timeOfImpact(square(), {100.0, -50.0}, Circle{{0.0, 0.0}, 0.5}, {100.0, -50.0},
                                  Vec2{1.0, 0.0}, 10.0));
}

TEST(TimeOfImpactDispatch, SwappedPolylineAndCircleWithExcludedFeature) {
  // The narrow-V polyline of CirclePolyline.ExcludedCornerLeavesTheOtherSegment as A, at position (1,1);
  // the disk as B at (-3,4) + (1,1). B's velocity relative to A must be (-1,-3), so A's relative velocity
  // is (1,3).
  const Polyline p{{{10.0, 2.0}, {0.0, 0.0}, {10.0, -2.0}, {10.0, -30.0}, {-30.0, -30.0}}};
  const Vec2 pos{1.0, 1.0};
  const Circle b{{0.0, 0.0}, 5.0};
  const auto first = rattle::timeOfImpact(p, pos, b, pos + Vec2{-3.0, 4.0}, Vec2{1.0, 3.0}, 20.0);
  // Normal from B toward A: minus the pair function's (-0.6, 0.8).
  ASSERT_NO_FATAL_FAILURE(expectImpact(first, 0.0, pos, {0.6, -0.8}, 5));
  const auto second = rattle::timeOfImpact(p, pos, b, pos + Vec2{-3.0, 4.0}, Vec2{1.0, 3.0}, 20.0, 5);
  // On A at rest the contact is pos + (-38/3, -30); A has moved (1,3) * 29/3 = (29/3, 29) by then:
  // pos + (-3, -1) = (-2, 0).
  ASSERT_NO_FATAL_FAILURE(expectImpact(second, 29.0 / 3.0, {-2.0, 0.0}, {0.0, -1.0}, 3));
}

TEST(TimeOfImpactDispatch, SwappedSegmentAndPoint) {
  // A = segment y = 0, B = point (0.5, 3). A moves (0,1) relative to B: B reaches y = 0 at t = 3; B is
  // above A, so the normal from B toward A is (0,-1). The contact is the point B itself, (0.5, 3).
  expectImpact(rattle::timeOfImpact(Segment{{-2.0, 0.0}, {2.0, 0.0}}, {0.0, 0.0}, Point{{0.5, 3.0}}, {0.0, 0.0},
                                    Vec2{0.0, 1.0}, 10.0),
               3.0, {0.5, 3.0}, {0.0, -1.0}, 0);
}

TEST(TimeOfImpactDispatch, PairsWithoutACircleGiveNothing) {
  // Overlapping and approaching, but neither side is a circle or a point: no entry in the table.
  const Segment s{{-2.0, 0.0}, {2.0, 0.0}};
  expectNone(rattle::timeOfImpact(s, {0.0, 0.0}, square(), {0.0, 0.0}, Vec2{0.0, -1.0}, 10.0));
  expectNone(rattle::timeOfImpact(square(), {0.0, 0.0}, square(), {0.5, 0.0}, Vec2{1.0, 0.0}, 10.0));
  expectNone(rattle::timeOfImpact(Polyline{{{-2.0, 1.0}, {2.0, -1.0}}}, {0.0, 0.0}, s, {0.0, 0.0}, Vec2{0.0, 1.0},
                                  10.0));
  expectNone(rattle::timeOfImpact(s, {0.0, 5.0}, s, {0.0, 0.0}, Vec2{0.0, -1.0}, 10.0));
}


// =========================================================================================================
// Under a constant relative acceleration (gravity on one body only): c(t) = c + v t + a t^2 / 2.

const rattle::Motion kFall{Vec2{0.0, 0.0}, Vec2{0.0, -10.0}};

TEST(TimeOfImpactGravity, DropOntoASegment) {
  // y = 5 - 5 t^2 reaches r = 0.5 when t^2 = 0.9.
  expectImpact(rattle::timeOfImpactCircleSegment({{0.0, 5.0}, 0.5}, kFall, kFloor, 10.0), std::sqrt(0.9),
               {0.0, 0.0}, {0.0, 1.0}, 0);
  // With a horizontal drift of 1: lands at x = sqrt(0.9).
  expectImpact(rattle::timeOfImpactCircleSegment({{0.0, 5.0}, 0.5}, rattle::Motion{Vec2{1.0, 0.0}, Vec2{0.0, -10.0}},
                                                 kFloor, 10.0),
               std::sqrt(0.9), {std::sqrt(0.9), 0.0}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactGravity, ThrownUpComesBackDown) {
  // y = 2 + 5t - 5t^2 = 0.5  ->  5t^2 - 5t - 1.5 = 0  ->  t = (5 + sqrt55) / 10 (the other root is < 0).
  expectImpact(rattle::timeOfImpactCircleSegment({{0.0, 2.0}, 0.5}, rattle::Motion{Vec2{0.0, 5.0}, Vec2{0.0, -10.0}},
                                                 kFloor, 10.0),
               (5.0 + std::sqrt(55.0)) / 10.0, {0.0, 0.0}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactGravity, ApexJustTouchingFromBelowIsNone) {
  // From below, thrown up at 10 with g = 10: the disk's top y + r = -5 + 10t - 5t^2 peaks at exactly 0 at
  // t = 1. The gap is 5 (t - 1)^2: a double root, a tangent touch, not an impact.
  const rattle::Motion up{Vec2{0.0, 10.0}, Vec2{0.0, -10.0}};
  expectNone(rattle::timeOfImpactCircleSegment({{0.0, -5.5}, 0.5}, up, kFloor, 10.0));
  // Starting 0.05 higher it does hit: -5.45 + 10t - 5t^2 = -0.5 -> 5t^2 - 10t + 4.95 = 0 ->
  // t = (10 - sqrt(100 - 99)) / 10 = 0.9; from below, so the normal is (0,-1).
  expectImpact(rattle::timeOfImpactCircleSegment({{0.0, -5.45}, 0.5}, up, kFloor, 10.0), 0.9, {0.0, 0.0},
               {0.0, -1.0}, 0, 1e-11);
}

TEST(TimeOfImpactGravity, TouchingAndSeparatingThenPulledBack) {
  // Touching the floor (centre y = r) and leaving at speed 1 under g = 10: gap f = t - 5t^2. f' turns
  // negative at t = 0.1 while f > 0, and f crosses zero downward at t = 0.2.
  expectImpact(rattle::timeOfImpactCircleSegment({{0.25, 0.5}, 0.5}, rattle::Motion{Vec2{0.0, 1.0}, Vec2{0.0, -10.0}},
                                                 kFloor, 10.0),
               0.2, {0.25, 0.0}, {0.0, 1.0}, 0);
  // The same against a circle: A touching B from above, thrown up at 1: |r + v t + a t^2/2| = sum of
  // radii again when 1 + t - 5t^2 = 1, t = 0.2.
  expectImpact(rattle::timeOfImpactCircleCircle({{0.0, 1.0}, 0.5}, rattle::Motion{Vec2{0.0, 1.0}, Vec2{0.0, -10.0}},
                                                {{0.0, 0.0}, 0.5}, 10.0),
               0.2, {0.0, 0.5}, {0.0, 1.0}, 0);
}

TEST(TimeOfImpactGravity, TouchingAtRestPressedInIsImmediatePulledAwayIsNone) {
  // f(0) = 0, f'(0) = 0 and f''(0) < 0: gravity presses the disk into the floor: impact now.
  const auto hit = rattle::timeOfImpactCircleSegment({{0.25, 0.5}, 0.5}, kFall, kFloor, 10.0);
  ASSERT_NO_FATAL_FAILURE(expectImpact(hit, 0.0, {0.25, 0.0}, {0.0, 1.0}, 0));
  EXPECT_EQ(hit->time, 0.0);
  // Accelerating away from the floor: f''(0) > 0, separating: none.
  expectNone(rattle::timeOfImpactCircleSegment({{0.25, 0.5}, 0.5}, rattle::Motion{Vec2{0.0, 0.0}, Vec2{0.0, 10.0}},
                                               kFloor, 10.0));
}

TEST(TimeOfImpactGravity, DropOntoAPointIsAQuartic) {
  // Centre (0.3, 5 - 5t^2), radius 0.5, onto the point (0,0): 0.09 + y^2 = 0.25 -> y = 0.4 -> t^2 = 0.92.
  // Normal (0.3, 0.4) / 0.5 = (0.6, 0.8).
  expectImpact(rattle::timeOfImpactCirclePoint({{0.3, 5.0}, 0.5}, kFall, {{0.0, 0.0}}, 10.0), std::sqrt(0.92),
               {0.0, 0.0}, {0.6, 0.8}, 0);
  // Falling 0.6 to the side of it: misses.
  expectNone(rattle::timeOfImpactCirclePoint({{0.6, 5.0}, 0.5}, kFall, {{0.0, 0.0}}, 10.0));
}

TEST(TimeOfImpactGravity, CircleCircleQuartic) {
  // A at (3, 10 - 5t^2), radius 1, onto B of radius 4 at the origin: 9 + y^2 = 25 -> y = 4 -> t^2 = 1.2.
  // Normal (3,4)/5; point 4 * normal = (2.4, 3.2).
  expectImpact(rattle::timeOfImpactCircleCircle({{3.0, 10.0}, 1.0}, kFall, {{0.0, 0.0}, 4.0}, 10.0),
               std::sqrt(1.2), {2.4, 3.2}, {0.6, 0.8}, 0);
}

TEST(TimeOfImpactGravity, ArcOntoAPolygonTop) {
  // x = -2 + 2t, y = 1.6 + 4.9t - 5t^2, radius 0.5, onto the square: y - 1.5 = 0.1 + 4.9t - 5t^2 =
  // -5 (t - 1)(t + 0.02) >= 0 on [0, 1], so the disk stays above the top face's line until t = 1, when
  // x = 0: the top edge (feature 2), point (0, 1), normal (0, 1). It starts 0.6 from the square's top and
  // sqrt(1 + 0.36) > 0.5 from its corner (-1, 1).
  expectImpact(rattle::timeOfImpactCirclePolygon({{-2.0, 1.6}, 0.5}, rattle::Motion{Vec2{2.0, 4.9}, Vec2{0.0, -10.0}},
                                                 square(), 10.0),
               1.0, {0.0, 1.0}, {0.0, 1.0}, 2, 1e-11);
}

TEST(TimeOfImpactGravity, ImpactExactlyAtMaxTime) {
  // y = 5.5 - 5t^2 reaches r = 0.5 at exactly t = 1 (floor); y = 7 - 5t^2 reaches 1 + 1 at t = 1 (circle).
  const auto floor = rattle::timeOfImpactCircleSegment({{0.0, 5.5}, 0.5}, kFall, kFloor, 1.0);
  EXPECT_TRUE(floor.has_value());
  if (floor) {
    EXPECT_EQ(floor->time, 1.0);
  }
  expectNone(rattle::timeOfImpactCircleSegment({{0.0, 5.5}, 0.5}, kFall, kFloor, 0.999));
  const auto circle = rattle::timeOfImpactCircleCircle({{0.0, 7.0}, 1.0}, kFall, {{0.0, 0.0}, 1.0}, 1.0);
  EXPECT_TRUE(circle.has_value());
  if (circle) {
    EXPECT_EQ(circle->time, 1.0);
  }
  expectNone(rattle::timeOfImpactCircleCircle({{0.0, 7.0}, 1.0}, kFall, {{0.0, 0.0}, 1.0}, 0.999));
}

TEST(TimeOfImpactGravity, DispatcherSwapsTheAcceleration) {
  // A = the floor at the origin, B = a disk of radius 0.5 at (0,5). A accelerates up at 10 relative to B,
  // so B falls at 10 relative to A: t = sqrt(0.9). The normal from B toward A is (0,-1). With B resting at
  // (0,5), A has risen 4.5 by then: the contact is at (0, 4.5), B's lowest point.
  const auto hit = rattle::timeOfImpact(kFloor, {0.0, 0.0}, Circle{{0.0, 0.0}, 0.5}, {0.0, 5.0},
                                        rattle::Motion{Vec2{0.0, 0.0}, Vec2{0.0, 10.0}}, 10.0);
  expectImpact(hit, std::sqrt(0.9), {0.0, 4.5}, {0.0, -1.0}, 0);
  // Unswapped: the disk falls onto the floor.
  expectImpact(rattle::timeOfImpact(Circle{{0.0, 0.0}, 0.5}, {0.0, 5.0}, kFloor, {0.0, 0.0}, kFall, 10.0),
               std::sqrt(0.9), {0.0, 0.0}, {0.0, 1.0}, 0);
}

// =========================================================================================================
// Randomized comparison against an independent brute-force reference.
//
// The reference knows nothing about polynomials, features or the engine's formulas. For a circle of radius
// R whose centre follows c(t) = c0 + v t + a t^2 / 2, it evaluates the true distance D(t) from c(t) to B
// (computed directly from B's geometry: distance to a disk, to a closed segment, or to a filled convex
// polygon, all in long double). It samples D at 512 steps over the horizon, refines every sampled local
// minimum by golden-section search (this catches dips narrower than a step, and gives the closest
// approaches used to exclude near-grazing cases), and bisects the first time D drops below R. On straight
// paths D is convex (B is convex), so there is a single minimum; on parabolas there may be several.
//
// Every case starts clearly separated (D(0) > R + 1e-3). Excluded (counted as skipped, not compared):
//   - near-grazing: a local minimum of D (before the reference impact, or anywhere when there is none)
//     within 1e-6 of R (absolute; radii are >= 0.05). There "impact" vs "none" flips under round-off of
//     the inputs and the contact time is ill-conditioned. A fifth of the straight-path cases are built to
//     pass at R +- 10^(-9..-1), so the band is exercised on both sides;
//   - impacts within 1e-7 (relative) of maxTime, where "inside [0, maxTime]" flips under round-off;
//   - for segments, first contacts within 1e-6 (relative to the length) of an end, where "inside" vs
//     "end" flips.
// Compared: hit or none; time within 1e-9 relative (the engine's stable roots should be near full
// precision; the margin covers the conditioning next to the excluded band); point within 1e-7; normal
// within 1e-6; and the feature where it is unambiguous (a polygon contact more than 1e-6 from an
// edge/corner boundary). The dispatcher is checked on the same cases with the roles swapped.

using LD = long double;

struct LVec {
  LD x, y;
};

LVec lv(Vec2 v) { return {v.x, v.y}; }
LD ldot(LVec a, LVec b) { return a.x * b.x + a.y * b.y; }
LVec lsub(LVec a, LVec b) { return {a.x - b.x, a.y - b.y}; }
LD llen(LVec a) { return std::sqrt(ldot(a, a)); }

// Closest point of the closed segment [a, b] to p, and the parameter of p's projection (unclamped).
LVec closestOnSegment(LVec p, LVec a, LVec b, LD* param = nullptr) {
  const LVec ab = lsub(b, a);
  const LD s = ldot(lsub(p, a), ab) / ldot(ab, ab);
  if (param) *param = s;
  const LD u = std::clamp<LD>(s, 0.0L, 1.0L);
  return {a.x + u * ab.x, a.y + u * ab.y};
}

// Closest point of a filled convex counter-clockwise polygon to p (p itself when inside).
LVec closestOnPolygon(LVec p, const std::vector<LVec>& poly) {
  bool inside = true;
  LD best = std::numeric_limits<LD>::infinity();
  LVec bestPoint{0, 0};
  for (size_t i = 0; i < poly.size(); ++i) {
    const LVec a = poly[i], b = poly[(i + 1) % poly.size()];
    const LVec ab = lsub(b, a), ap = lsub(p, a);
    if (ab.x * ap.y - ab.y * ap.x < 0) inside = false;
    const LVec q = closestOnSegment(p, a, b);
    const LD d = llen(lsub(p, q));
    if (d < best) best = d, bestPoint = q;
  }
  return inside ? p : bestPoint;
}

// The mover's path: centre c0 + v t + acc t^2 / 2 for t in [0, maxTime].
struct Path {
  Vec2 c0, v, acc;
  double maxTime = 1.0;
  rattle::Motion motion() const { return rattle::Motion{v, acc}; }
  LVec at(LD t) const {
    return {(LD)c0.x + (LD)v.x * t + (LD)acc.x * t * t / 2, (LD)c0.y + (LD)v.y * t + (LD)acc.y * t * t / 2};
  }
  Vec2 travel(double t) const { return v * t + acc * (0.5 * t * t); }
};

struct Reference {
  bool hit = false;
  LD time = 0;
  bool grazing = false;  // a closest approach within the margin of R (before the impact, if any)
};

constexpr LD kGrazingMargin = 1e-6L;

template <class Distance>
Reference bruteForce(const Distance& distance, const Path& path, LD radius, LD horizon) {
  auto D = [&](LD t) { return distance(path.at(t)); };
  constexpr int kSteps = 512;
  auto sampleTime = [&](int k) { return horizon * k / kSteps; };
  std::vector<LD> d(kSteps + 1);
  for (int k = 0; k <= kSteps; ++k) d[k] = D(sampleTime(k));

  struct Minimum {
    LD t, d;
  };
  std::vector<Minimum> minima;
  const LD g = (std::sqrt(5.0L) - 1) / 2;
  for (int k = 0; k <= kSteps; ++k) {
    // Minima after the first sample below R matter neither for the first crossing nor for grazing.
    if (k > 0 && d[k - 1] < radius) break;
    if ((k > 0 && d[k] > d[k - 1]) || (k < kSteps && d[k] > d[k + 1])) continue;
    if (d[k] < radius - 2 * kGrazingMargin) {  // clearly inside already: no refinement needed
      minima.push_back({sampleTime(k), d[k]});
      continue;
    }
    LD lo = sampleTime(std::max(0, k - 1)), hi = sampleTime(std::min(kSteps, k + 1));
    LD m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    LD f1 = D(m1), f2 = D(m2);
    for (int i = 0; i < 64; ++i) {
      if (f1 < f2) {
        hi = m2, m2 = m1, f2 = f1, m1 = hi - g * (hi - lo), f1 = D(m1);
      } else {
        lo = m1, m1 = m2, f1 = f2, m2 = lo + g * (hi - lo), f2 = D(m2);
      }
    }
    Minimum m{(lo + hi) / 2, D((lo + hi) / 2)};
    if (d[k] < m.d) m = {sampleTime(k), d[k]};
    minima.push_back(m);
  }

  // The first bracket [a, b] with D(a) >= R > D(b): a sampled step, or a dip between samples.
  LD a = -1, b = -1;
  for (int k = 1; k <= kSteps; ++k) {
    if (d[k] < radius) {
      a = sampleTime(k - 1), b = sampleTime(k);
      break;
    }
  }
  for (const Minimum& m : minima) {
    if (m.d < radius && (b < 0 || m.t < a)) {
      b = m.t;
      a = sampleTime(static_cast<int>(std::floor(m.t / horizon * kSteps)));
      if (!(a < b)) a = sampleTime(std::max(0, static_cast<int>(std::floor(m.t / horizon * kSteps)) - 1));
      break;
    }
  }
  Reference ref;
  if (b >= 0) {
    for (int i = 0; i < 200; ++i) {
      const LD mid = (a + b) / 2;
      if (mid <= a || mid >= b) break;
      (D(mid) < radius ? b : a) = mid;
    }
    ref.hit = true;
    ref.time = b;
  }
  for (const Minimum& m : minima)
    if ((!ref.hit || m.t <= ref.time) && std::abs(m.d - radius) < kGrazingMargin) ref.grazing = true;
  return ref;
}

struct Tally {
  int cases = 0, hits = 0, nones = 0, skipped = 0, failures = 0;
  int endContacts = 0, endContactsReported = 0;  // segments
  int edgeFeatures = 0, cornerFeatures = 0;      // polygons
  double worstTimeError = 0;                     // relative, over compared impacts
};

void report(const char* name, const Tally& t) {
  std::printf("[ %s ] %d cases: %d impacts, %d none, %d skipped (near-grazing / near maxTime / near an end);"
              " worst time error %.2g",
              name, t.cases, t.hits, t.nones, t.skipped, t.worstTimeError);
  if (t.endContacts)
    std::printf("; %d first contacts at an end (the engine reported a later impact for %d)", t.endContacts,
                t.endContactsReported);
  if (t.edgeFeatures + t.cornerFeatures)
    std::printf("; features checked at %d edges, %d corners", t.edgeFeatures, t.cornerFeatures);
  std::printf("\n");
}

std::string describe(const Path& m, double radius) {
  char buf[300];
  std::snprintf(buf, sizeof buf, "c0 = (%.17g, %.17g), v = (%.17g, %.17g), a = (%.17g, %.17g), r = %.17g, maxTime = %.17g",
                m.c0.x, m.c0.y, m.v.x, m.v.y, m.acc.x, m.acc.y, radius, m.maxTime);
  return buf;
}

// Compares one engine answer with the reference. `closest(p)` is the closest point of B to p.
template <class Closest>
void compare(const char* what, int index, const std::optional<Impact>& got, const Reference& ref, const Path& m,
             double radius, const Closest& closest, Tally& tally, bool skip, int expectedFeature /* -1: unchecked */) {
  ++tally.cases;
  if (skip) {
    ++tally.skipped;
    return;
  }
  auto fail = [&](const std::string& why) {
    if (++tally.failures <= 5)
      ADD_FAILURE() << what << " case " << index << ": " << why << "\n  " << describe(m, radius)
                    << "\n  reference: " << (ref.hit ? "impact at " + std::to_string((double)ref.time) : "none")
                    << "\n  engine: "
                    << (got ? "impact at " + std::to_string(got->time) + " feature " + std::to_string(got->feature)
                            : "none");
  };
  if (!ref.hit) {
    ++tally.nones;
    if (got) fail("engine reports an impact the reference does not have");
    return;
  }
  ++tally.hits;
  if (!got) return fail("engine misses the impact");
  const double t = static_cast<double>(ref.time);
  const double timeError = std::abs(got->time - t) / std::max(1.0, t);
  tally.worstTimeError = std::max(tally.worstTimeError, timeError);
  if (!(timeError <= 1e-9)) return fail("time differs");
  if (got->time < 0.0 || got->time > m.maxTime) return fail("time outside [0, maxTime]");
  const LVec c = m.at(ref.time);
  const LVec q = closest(c);
  const Vec2 point{(double)q.x, (double)q.y};
  const LD len = llen(lsub(c, q));
  const Vec2 normal{(double)((c.x - q.x) / len), (double)((c.y - q.y) / len)};
  if (auto r = nearVec(got->point, point, 1e-7); !r) return fail(std::string("point differs: ") + r.message());
  if (auto r = nearVec(got->normal, normal, 1e-6); !r) return fail(std::string("normal differs: ") + r.message());
  if (expectedFeature >= 0 && got->feature != expectedFeature)
    return fail("feature " + std::to_string(got->feature) + ", expected " + std::to_string(expectedFeature));
}

// The dispatcher with the roles swapped (B's geometry as A, the circle as B, the motion negated) must give
// the same time and feature, the opposite normal, and the point seen from the circle's rest frame.
void compareSwapped(const char* what, int index, const std::optional<Impact>& direct, const Geometry& b,
                    const Circle& mover, const Path& m, Tally& tally) {
  const auto swapped = rattle::timeOfImpact(b, {0.0, 0.0}, Circle{{0.0, 0.0}, mover.radius}, mover.center,
                                            rattle::Motion{-m.v, -m.acc}, m.maxTime);
  if (direct.has_value() == swapped.has_value() &&
      (!direct || (direct->time == swapped->time && direct->feature == swapped->feature &&
                   nearVec(swapped->normal, -direct->normal, 1e-12) &&
                   nearVec(swapped->point, direct->point - m.travel(direct->time), 1e-12))))
    return;
  if (++tally.failures <= 5)
    ADD_FAILURE() << what << " case " << index << ": the swapped dispatcher call disagrees\n  "
                  << describe(m, mover.radius) << "\n  direct: "
                  << (direct ? "impact at " + std::to_string(direct->time) : std::string("none"))
                  << "\n  swapped: " << (swapped ? "impact at " + std::to_string(swapped->time) : std::string("none"));
}

// Whether the reference impact is too close to maxTime to compare.
bool nearMaxTime(const Reference& ref, double maxTime) {
  return ref.hit && std::abs((double)ref.time - maxTime) <= 1e-7 * std::max(1.0, maxTime);
}

// A start on a circle of radius extent + r + (0.5..8) around `centre`, and a path that would pass through
// `aim` after maxTime / (0.3..2): hits, misses and late impacts all occur. `gravity` > 0 adds an
// acceleration of that size in a random direction.
Path aimedPath(std::mt19937_64& rng, Vec2 centre, double extent, double r, Vec2 aim, double gravity) {
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Path m;
  const double th = angle(rng);
  const double d = extent + r + 0.5 + 7.5 * unit(rng);
  m.c0 = centre + Vec2{d * std::cos(th), d * std::sin(th)};
  m.maxTime = 0.2 + 2.8 * unit(rng);
  const double reachTime = m.maxTime / (0.3 + 1.7 * unit(rng));
  if (gravity > 0) {
    const double phi = angle(rng);
    m.acc = gravity * Vec2{std::cos(phi), std::sin(phi)};
  }
  m.v = (1.0 / reachTime) * (aim - m.c0 - (0.5 * reachTime * reachTime) * m.acc);
  return m;
}

// A straight pass whose closest approach to B is r + gap. The path runs along a random direction u; B's
// extent across it is support(w) = max over B of w.p with w = perp(u), so the path's offset along w is
// support(w) + r + gap. The closest approach comes at 0.3 to 0.9 of maxTime.
template <class Support>
Path grazingPath(std::mt19937_64& rng, Vec2 centre, double extent, double r, double gap, const Support& support) {
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double th = angle(rng);
  const Vec2 u{std::cos(th), std::sin(th)};
  const Vec2 w = rattle::perpendicular(u);
  const double distanceToGo = extent + r + 0.5 + 7.5 * unit(rng);
  const double along = rattle::dot(u, centre) - distanceToGo;
  Path m;
  m.c0 = along * u + (support(w) + r + gap) * w;
  m.maxTime = 0.2 + 2.8 * unit(rng);
  m.v = (distanceToGo / (m.maxTime * (0.3 + 0.6 * unit(rng)))) * u;
  return m;
}

// A gap of +-10^(-9..-1): three eighths of them inside the excluded band, the rest near-grazing but compared.
double randomGap(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> exponent(-9.0, -1.0);
  std::bernoulli_distribution sign(0.5);
  return (sign(rng) ? 1.0 : -1.0) * std::pow(10.0, exponent(rng));
}

// One case of each kind: draws B and the mover's path, runs the engine and the reference, compares.
// `mode`: 0 straight aimed path, 1 straight near-grazing pass, 2 parabola (gravity).

void circleCase(std::mt19937_64& rng, int index, int mode, Tally& tally) {
  std::uniform_real_distribution<double> radius(0.05, 3.0);
  std::uniform_real_distribution<double> coord(-5.0, 5.0);
  std::uniform_real_distribution<double> g(1.0, 20.0);
  const Circle b{{coord(rng), coord(rng)}, radius(rng)};
  const double ra = radius(rng);
  const double reach = b.radius + 1.5 * ra;
  const Vec2 aim = b.center + Vec2{reach * coord(rng) / 5.0, reach * coord(rng) / 5.0};
  const Path m = mode == 1 ? grazingPath(rng, b.center, b.radius, ra, randomGap(rng),
                                         [&](Vec2 w) { return rattle::dot(w, b.center) + b.radius; })
                           : aimedPath(rng, b.center, b.radius, ra, aim, mode == 2 ? g(rng) : 0.0);
  const LVec cb = lv(b.center);
  const LD rb = b.radius;
  auto distance = [&](LVec p) { return std::max<LD>(0, llen(lsub(p, cb)) - rb); };
  if (distance(lv(m.c0)) <= ra + 1e-3) return;  // must start clearly apart
  // Over a slightly longer horizon, so impacts just after maxTime are seen and excluded.
  const Reference full = bruteForce(distance, m, ra, m.maxTime * (1 + 1e-6));
  Reference ref = full;
  if (ref.hit && ref.time > m.maxTime) ref.hit = false;
  const bool skip = full.grazing || nearMaxTime(full, m.maxTime);
  const Circle mover{m.c0, ra};
  const auto got = rattle::timeOfImpactCircleCircle(mover, m.motion(), b, m.maxTime);
  auto closest = [&](LVec p) {
    const LVec d = lsub(p, cb);
    const LD l = llen(d);
    return LVec{cb.x + rb * d.x / l, cb.y + rb * d.y / l};
  };
  compare("circle-circle", index, got, ref, m, ra, closest, tally, skip, 0);
  compareSwapped("circle-circle", index, got, b, mover, m, tally);
}

// The reference uses the closed segment. When its first contact is inside the segment, the engine must
// agree. When it is at an end (the centre's projection falls beyond the segment), the segment's ends are
// not corners, so that contact is not an impact; what the engine does after such a pass is not pinned
// down beyond this: it may report nothing, or a later contact on the segment, never one before the
// reference's first contact (which would be impossible).
void segmentCase(std::mt19937_64& rng, int index, int mode, Tally& tally) {
  std::uniform_real_distribution<double> radius(0.05, 2.0);
  std::uniform_real_distribution<double> coord(-3.0, 3.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> g(1.0, 20.0);
  const Segment s{{coord(rng), coord(rng)}, {coord(rng), coord(rng)}};
  if (rattle::length(s.b - s.a) < 0.5) return;
  const double ra = radius(rng);
  // Aim at a random point of the segment, give or take 1.5 radii.
  const Vec2 aim = s.a + unit(rng) * (s.b - s.a) + Vec2{1.5 * ra * (2 * unit(rng) - 1), 1.5 * ra * (2 * unit(rng) - 1)};
  const Path m = aimedPath(rng, {0.0, 0.0}, 3.0 * std::numbers::sqrt2, ra, aim, mode == 2 ? g(rng) : 0.0);
  const LVec a = lv(s.a), b = lv(s.b);
  auto distance = [&](LVec p) { return llen(lsub(p, closestOnSegment(p, a, b))); };
  if (distance(lv(m.c0)) <= ra + 1e-3) return;
  const Reference full = bruteForce(distance, m, ra, m.maxTime * (1 + 1e-6));
  Reference ref = full;
  if (ref.hit && ref.time > m.maxTime) ref.hit = false;
  bool skip = full.grazing || nearMaxTime(full, m.maxTime);
  const Circle mover{m.c0, ra};
  const auto got = rattle::timeOfImpactCircleSegment(mover, m.motion(), s, m.maxTime);
  compareSwapped("circle-segment", index, got, s, mover, m, tally);
  if (ref.hit && !skip) {
    LD param = 0;
    closestOnSegment(m.at(ref.time), a, b, &param);
    if (std::abs(param) < 1e-6L || std::abs(param - 1) < 1e-6L) skip = true;  // at an end, within the margin
    if (!skip && (param <= 0 || param >= 1)) {
      ++tally.cases;
      ++tally.endContacts;
      if (got) {
        ++tally.endContactsReported;
        LD gotParam = 0;
        closestOnSegment(lv(got->point), a, b, &gotParam);
        if (!(got->time >= (double)ref.time - 1e-9 && gotParam >= -1e-9 && gotParam <= 1 + 1e-9) &&
            ++tally.failures <= 5)
          ADD_FAILURE() << "circle-segment case " << index << ": impact at " << got->time
                        << " before the first contact at an end (" << (double)ref.time << ") or off the segment\n  "
                        << describe(m, ra);
      }
      return;
    }
  }
  compare("circle-segment", index, got, ref, m, ra, [&](LVec p) { return closestOnSegment(p, a, b); }, tally,
          skip, 0);
}

void polygonCase(std::mt19937_64& rng, int index, int mode, Tally& tally) {
  std::uniform_real_distribution<double> radius(0.05, 2.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> count(3, 8);
  std::uniform_real_distribution<double> g(1.0, 20.0);
  // A convex polygon: points on an ellipse at sorted random angles at least 0.15 rad apart.
  const int n = count(rng);
  std::vector<double> angles;
  while ((int)angles.size() < n) {
    const double th = 2.0 * std::numbers::pi * unit(rng);
    bool ok = true;
    for (double o : angles) {
      const double d = std::abs(th - o);
      ok = ok && std::min(d, 2.0 * std::numbers::pi - d) > 0.15;
    }
    if (ok) angles.push_back(th);
  }
  std::sort(angles.begin(), angles.end());
  const double rx = 0.5 + 2.5 * unit(rng), ry = 0.5 + 2.5 * unit(rng);
  const Vec2 centre{4.0 * unit(rng) - 2.0, 4.0 * unit(rng) - 2.0};
  Polygon poly;
  for (double th : angles) poly.points.push_back(centre + Vec2{rx * std::cos(th), ry * std::sin(th)});
  ASSERT_FALSE(rattle::validationError(poly).has_value()) << *rattle::validationError(poly);
  std::vector<LVec> lp;
  for (Vec2 p : poly.points) lp.push_back(lv(p));

  const double ra = radius(rng);
  const double extent = std::max(rx, ry);
  const Vec2 aim = centre + Vec2{(extent + 1.5 * ra) * (2 * unit(rng) - 1), (extent + 1.5 * ra) * (2 * unit(rng) - 1)};
  const Path m = mode == 1 ? grazingPath(rng, centre, extent, ra, randomGap(rng),
                                         [&](Vec2 w) {
                                           double best = -std::numeric_limits<double>::infinity();
                                           for (Vec2 p : poly.points) best = std::max(best, rattle::dot(w, p));
                                           return best;
                                         })
                           : aimedPath(rng, centre, extent, ra, aim, mode == 2 ? g(rng) : 0.0);
  auto closest = [&](LVec p) { return closestOnPolygon(p, lp); };
  auto distance = [&](LVec p) { return llen(lsub(p, closest(p))); };
  if (distance(lv(m.c0)) <= ra + 1e-3) return;
  const Reference full = bruteForce(distance, m, ra, m.maxTime * (1 + 1e-6));
  Reference ref = full;
  if (ref.hit && ref.time > m.maxTime) ref.hit = false;
  const bool skip = full.grazing || nearMaxTime(full, m.maxTime);
  const Circle mover{m.c0, ra};
  const auto got = rattle::timeOfImpactCirclePolygon(mover, m.motion(), poly, m.maxTime);

  // The feature at the reference contact: corner k when the centre projects beyond both edges meeting at k
  // (by a margin), edge i when it projects inside edge i (by a margin) and edge i is the nearest; else
  // unchecked.
  int feature = -1;
  if (ref.hit && !skip) {
    const LVec c = m.at(ref.time);
    const LVec q = closest(c);
    for (int k = 0; k < n && feature < 0; ++k) {
      LD before = 0, after = 0;
      closestOnSegment(c, lp[(k + n - 1) % n], lp[k], &before);  // the edge ending at k
      closestOnSegment(c, lp[k], lp[(k + 1) % n], &after);       // the edge starting at k
      if (before > 1 + 1e-6L && after < -1e-6L) feature = n + k, ++tally.cornerFeatures;
    }
    if (feature < 0) {
      LD bestEdge = std::numeric_limits<LD>::infinity();
      int edge = -1;
      for (int e = 0; e < n; ++e) {
        const LD d = llen(lsub(closestOnSegment(c, lp[e], lp[(e + 1) % n]), q));
        if (d < bestEdge) bestEdge = d, edge = e;
      }
      LD param = 0;
      closestOnSegment(c, lp[edge], lp[(edge + 1) % n], &param);
      if (param > 1e-6L && param < 1 - 1e-6L) feature = edge, ++tally.edgeFeatures;
    }
  }
  compare("circle-polygon", index, got, ref, m, ra, closest, tally, skip, feature);
  compareSwapped("circle-polygon", index, got, poly, mover, m, tally);
}

void expectUseful(const Tally& t) {
  EXPECT_EQ(t.failures, 0);
  EXPECT_GT(t.hits, t.cases / 5) << "too few impacts for a meaningful comparison";
  EXPECT_GT(t.nones, t.cases / 5) << "too few misses for a meaningful comparison";
  EXPECT_LT(t.skipped, t.cases / 8) << "too many excluded cases";
}

TEST(TimeOfImpactRandomized, CircleCircleAgainstBruteForce) {
  std::mt19937_64 rng(20240611);
  Tally tally;
  for (int i = 0; i < 3000; ++i) circleCase(rng, i, i % 5 == 4 ? 1 : 0, tally);
  report("circle-circle", tally);
  expectUseful(tally);
}

TEST(TimeOfImpactRandomized, CircleSegmentAgainstBruteForce) {
  std::mt19937_64 rng(987654321);
  Tally tally;
  for (int i = 0; i < 3000; ++i) segmentCase(rng, i, 0, tally);
  report("circle-segment", tally);
  expectUseful(tally);
  EXPECT_GT(tally.endContacts, 100);
}

TEST(TimeOfImpactRandomized, CirclePolygonAgainstBruteForce) {
  std::mt19937_64 rng(1122334455);
  Tally tally;
  for (int i = 0; i < 3000; ++i) {
    polygonCase(rng, i, i % 5 == 4 ? 1 : 0, tally);
    if (HasFatalFailure()) return;
  }
  report("circle-polygon", tally);
  expectUseful(tally);
  EXPECT_GT(tally.cornerFeatures, 100);
  EXPECT_GT(tally.edgeFeatures, 100);
}

TEST(TimeOfImpactRandomized, UnderGravityAgainstBruteForce) {
  std::mt19937_64 rng(55555);
  Tally circles, segments, polygons;
  for (int i = 0; i < 1000; ++i) {
    circleCase(rng, i, 2, circles);
    segmentCase(rng, i, 2, segments);
    polygonCase(rng, i, 2, polygons);
    if (HasFatalFailure()) return;
  }
  report("circle-circle, gravity", circles);
  report("circle-segment, gravity", segments);
  report("circle-polygon, gravity", polygons);
  expectUseful(circles);
  expectUseful(segments);
  expectUseful(polygons);
}

}  // namespace

namespace {

// A state a world reached in a valley of two faces, a -> b -> c: a point sliding down the first (its
// acceleration gravity's part along it), about to meet the second at the joint b.
const Vec2 kValleyA{-5.8634251017531076, 1.5205368596077589}, kValleyB{0.19278175673494327, 0.1787593943361139},
    kValleyC{3.4773275219891642, 1.7454038250727189};
const Circle kValleyPoint{{0.16869278272348012, 0.18409640531432719}, 0};
const rattle::Motion kValleyMotion{{3.5879712895623133, -0.79492975303988767},
                                   {2.0717512907766413, -0.45900499447364318}};

// The second face's normal on the valley's side (left of b -> c), and when the point's path crosses its
// line, n.(c(t) - b) = 0, solved in long double (the smaller root, cancellation-free).
Vec2 valleySecondFaceNormal() {
  const Vec2 d = kValleyC - kValleyB;
  return Vec2{-d.y, d.x} * (1.0 / length(d));
}
double valleySecondFaceCrossing() {
  using L = long double;
  const Vec2 n = valleySecondFaceNormal();
  const Vec2 c = kValleyPoint.center, v = kValleyMotion.velocity, a = kValleyMotion.acceleration;
  const L g0 = L(n.x) * (L(c.x) - L(kValleyB.x)) + L(n.y) * (L(c.y) - L(kValleyB.y));
  const L g1 = L(n.x) * L(v.x) + L(n.y) * L(v.y);
  const L g2 = (L(n.x) * L(a.x) + L(n.y) * L(a.y)) / 2;
  return static_cast<double>(2 * g0 / (-g1 + std::sqrt(g1 * g1 - 4 * g2 * g0)));
}

}  // namespace

// A point sliding down one segment of a Polyline into a valley lies on that segment's line only to
// round-off, and must meet the next segment at the joint. Its path crossed the next segment's line
// 4e-15 before the segment's start, an ulp further than a point's round-off allowance there, and it met
// neither the segment nor the corner: it left the valley. Expected: the next segment's feature and
// normal, at the time its path crosses that line.
TEST(TimeOfImpactPolyline, APointSlidingIntoAValleyMeetsTheNextSegmentAtTheJoint) {
  const auto hit = rattle::timeOfImpactCirclePolyline(kValleyPoint, kValleyMotion,
                                                      Polyline{{kValleyA, kValleyB, kValleyC}}, 1.0 / 60);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->feature, 1);
  const Vec2 n = valleySecondFaceNormal();
  EXPECT_NEAR(hit->normal.x, n.x, 1e-12);
  EXPECT_NEAR(hit->normal.y, n.y, 1e-12);
  EXPECT_NEAR(hit->time, valleySecondFaceCrossing(), 1e-15);
}

// The same state against the valley's second face as a Segment of its own (two Segments in a V): its
// face reaches past its ends by its own round-off over the sine of the approach, as a Polyline's segment
// does at an inner corner. Without that the path, 4e-15 before the Segment's start, missed it.
TEST(TimeOfImpactSegment, APointReachesPastItsEndByTheRoundOffOfItsCoordinates) {
  const auto hit =
      rattle::timeOfImpactCircleSegment(kValleyPoint, kValleyMotion, Segment{kValleyB, kValleyC}, 1.0 / 60);
  ASSERT_TRUE(hit);
  const Vec2 n = valleySecondFaceNormal();
  EXPECT_NEAR(hit->normal.x, n.x, 1e-12);
  EXPECT_NEAR(hit->normal.y, n.y, 1e-12);
  EXPECT_NEAR(hit->time, valleySecondFaceCrossing(), 1e-15);
}
