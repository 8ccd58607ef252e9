// A Point on a sloped face under gravity: it slides along the face, and in the bottom of a V it comes to
// rest, without a step at the event budget. A point has no extent, so round-off alone says which side
// of a line it lies on, and three faults came of it:
//  - a point sliding along a sloped segment, its acceleration gravity's part along it, read as
//    pressed into one side by round-off: it met the segment at once, was dismissed, and was predicted
//    again at the same instant a million times (each step of the slide cost 0.6 s);
//  - a point that slid into the bottom of a V of two faces slid down each into the other, ever faster,
//    until the budget ran out, step after step: a point touches at distance 0, where nothing it touches
//    gave a direction to hold it up;
//  - a point that slid off the end of one face of the V, round-off beyond it, met that face again at
//    once and started the same slide, at one instant without end.
// The geometries are those a random search found (hex floats: the round-off is the point).
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <cmath>
#include <iterator>
#include <string>

using namespace rattle;

namespace {

constexpr StepMode kExactModes[] = {StepMode::Hybrid, StepMode::Predictive};
constexpr double kDt = 1.0 / 60;
constexpr Vec2 kGravity{0, -9.81};

std::string nameOf(StepMode m) { return m == StepMode::Hybrid ? "hybrid" : "predictive"; }

// Signed distance of p from the line through a and b, positive on its left.
double leftOf(Vec2 a, Vec2 b, Vec2 p) { return cross(b - a, p - a) / length(b - a); }

}  // namespace

// The first slope of a Polyline that turns back at 87 degrees; the point starts halfway along it,
// moving up it at 2. It slides as a point on an incline does: s(t) = s0 + 2 t + (g.u) t^2 / 2 along the
// slope's direction u, until it leaves by the lower end.
TEST(PointsOnSlopes, APointSlidesAlongASlopeAtItsAnalyticPosition) {
  const Vec2 a{0.536, 0.0273}, b{7.5035, 3.3175}, c{5.898, 6.3175};
  const Vec2 u = (b - a) * (1.0 / length(b - a));
  const Vec2 start = (a + b) * 0.5;
  for (StepMode mode : kExactModes) {
    SCOPED_TRACE(nameOf(mode));
    WorldDef def;
    def.mode = mode;
    def.gravity = kGravity;
    World w(def);
    const BodyId ground = w.createBody({.type = BodyType::Static});
    w.createFixture(ground, {.geometry = Polyline{{a, b, c}}});
    const BodyId p = w.createBody({.type = BodyType::Dynamic, .position = start, .velocity = u * 2.0});
    w.createFixture(p, {.geometry = Point{}, .restitution = 1});
    const double along = dot(kGravity, u);
    // It is back at the start at t = -4 / along (about 0.95 s); stop well before the lower end.
    for (int k = 1; k <= 90; ++k) {
      w.step(kDt);
      ASSERT_FALSE(w.stats().eventBudgetReached) << "step " << k;
      ASSERT_LE(w.stats().eventsProcessed, 2) << "step " << k;
      ASSERT_LE(w.stats().staleEvents, 8) << "step " << k;  // predicted again at one instant: 10^6
      const double t = k * kDt;
      const Vec2 expected = start + u * (2 * t + 0.5 * along * t * t);
      EXPECT_NEAR(w.position(p).x, expected.x, 1e-9) << "step " << k;
      EXPECT_NEAR(w.position(p).y, expected.y, 1e-9) << "step " << k;
    }
  }
}

namespace {

struct Valley {
  Vec2 a, b, c;  // a and c the rims, b the bottom
  double speed;  // down the first slope, from its middle
  double restitution;
};

// Points found by a random search that stalled: the first two in a Polyline, the third in two Segments.
constexpr Valley kValleys[] = {
    {{-0x1.2b37cafe3acf4p-2, 0x1.34c507d9a51dcp+2},
     {0x1.ee83de1050644p-1, 0x1.a03ed18f84124p-1},
     {0x1.3876217fdfae6p+1, 0x1.84fd308d1179p+2},
     0x1.ffc1ed702b256p+1,
     0x1.82ee347811548p-5},
    {{-0x1.77425b5ba4cdfp+2, 0x1.8541e75460bbfp+0},
     {0x1.8ad12963893c1p-3, 0x1.6e1967c436051p-3},
     {0x1.bd191178364b9p+1, 0x1.bed2c8fb00297p+0},
     0x1.567031a311526p-1,
     0x1.48781a68da0bdp-1},
    {{-0x1.1550b6cc4de2ap+0, 0x1.e260a8c65edb3p+1},
     {0x1.328ab146e47ffp-1, 0x1.02752fd079842p-2},
     {0x1.3a38de1a5ecfdp+2, 0x1.07aad7adb1509p+2},
     0x1.4e3e83a7b30c3p+1,
     0x1.beab668b24d3p-2},
};

World valleyWorld(const Valley& v, StepMode mode, bool polyline, BodyId& point) {
  WorldDef def;
  def.mode = mode;
  def.gravity = kGravity;
  World w(def);
  const BodyId ground = w.createBody({.type = BodyType::Static});
  if (polyline) {
    w.createFixture(ground, {.geometry = Polyline{{v.a, v.b, v.c}}});
  } else {
    w.createFixture(ground, {.geometry = Segment{v.a, v.b}});
    w.createFixture(ground, {.geometry = Segment{v.b, v.c}});
  }
  const Vec2 down = (v.b - v.a) * (1.0 / length(v.b - v.a));
  point = w.createBody({.type = BodyType::Dynamic, .position = (v.a + v.b) * 0.5, .velocity = down * v.speed});
  w.createFixture(point, {.geometry = Point{}, .restitution = v.restitution});
  return w;
}

// Above both faces' lines (a -> b runs down and c -> b too: above is on the left of the first and the
// right of the second), to round-off.
bool aboveBothFaces(const Valley& v, Vec2 q) { return leftOf(v.a, v.b, q) >= -1e-9 && leftOf(v.b, v.c, q) >= -1e-9; }

}  // namespace

// Each valley as a Polyline and as two Segments, 5 s: no step reaches the event budget, and each takes
// a handful of events (a point that slides back and forth through the bottom, frictionless, meets it
// once a pass). The first and the third come to rest in the bottom.
TEST(PointsOnSlopes, APointInAValleyNeverStallsAStep) {
  for (size_t i = 0; i < std::size(kValleys); ++i) {
    const Valley& v = kValleys[i];
    for (bool polyline : {true, false}) {
      for (StepMode mode : kExactModes) {
        SCOPED_TRACE(nameOf(mode) + (polyline ? " polyline " : " segments ") + std::to_string(i));
        BodyId p;
        World w = valleyWorld(v, mode, polyline, p);
        for (int k = 1; k <= 300; ++k) {
          w.step(kDt);
          ASSERT_FALSE(w.stats().eventBudgetReached) << "step " << k;
          ASSERT_LE(w.stats().eventsProcessed, 200) << "step " << k;
        }
        if (i == 1) continue;  // still sliding to and fro (restitution 0.64)
        EXPECT_TRUE(w.isAsleep(p));
        EXPECT_TRUE(aboveBothFaces(v, w.position(p)));
        EXPECT_NEAR(w.position(p).x, v.b.x, 1e-6);
        EXPECT_NEAR(w.position(p).y, v.b.y, 1e-6);
      }
    }
  }
}

// Pending (issue 10): a point that slides through the bottom of a V again and again gets below one of
// its faces now and then: in 2-3% of random valleys (Polylines or two Segments). Here the second
// valley as two Segments, hybrid, at step 86. The last such escape traced: a point sliding on one face,
// resolved against the other at the joint while the slide still held it, left with a velocity into
// that face, taken as leaving both. Enable when fixed.
TEST(PointsOnSlopes, DISABLED_APointInAValleyStaysAboveItsFaces) {
  for (const Valley& v : kValleys) {
    for (bool polyline : {true, false}) {
      for (StepMode mode : kExactModes) {
        SCOPED_TRACE(nameOf(mode) + (polyline ? " polyline" : " segments"));
        BodyId p;
        World w = valleyWorld(v, mode, polyline, p);
        for (int k = 1; k <= 300; ++k) {
          w.step(kDt);
          ASSERT_TRUE(aboveBothFaces(v, w.position(p))) << "step " << k;
        }
      }
    }
  }
}
