// Sensor tests (hybrid and predictive modes): begin and end events at analytic times for every kind of sensor and
// visitor (static, dynamic and kinematic bodies, straight and parabolic paths), the rules (sensors never
// touch each other, never change motion), the bookkeeping (sensorOverlaps, ends on destroy and filter
// changes, begins and ends always pairing up) and a brute-force comparison with the geometry layer's
// overlaps() over random scenes.
//
// Regression guard for an engine bug found by these tests at commit 1bf705e: after a begin or end event at
// time t the pair was predicted again from t with the new state, but the disk's position at the computed
// root lay on the old side of the boundary by round-off, so timeOfOverlapChange() found a mismatch in a
// piece of round-off length and returned it: a spurious end (or begin) at the same instant, then the real
// state again (892 of 1361 events in SensorBruteForce). Minimal repro: static Polygon sensor [-1, 1]^2,
// dynamic disk r = 0.3 at (-4, 0) moving at (1, 0), 128 steps of 1/16: begin 2.7, end 2.7, begin 2.7,
// end 5.3 instead of begin 2.7, end 5.3. The analytic tests below require exactly one begin and one end
// per visit, and the brute-force test counts same-instant pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <compare>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "rattle/rattle.h"
#include "hard_case_support.h"
#include "world_test_support.h"

namespace {

using namespace rattle_test;
using rattle::Circle;
using rattle::Geometry;
using rattle::Point;
using rattle::Polygon;
using rattle::Polyline;
using rattle::Segment;
using rattle::SensorEvent;
using rattle::WorldDef;
using rattle::StepMode;
using hard_case::ModeTest;
using hard_case::ModeParamName;

using LD = long double;

// ------------------------------------------------------------------------------------------------
// Helpers.

/// A sensor event with the step start added: its time from the world's creation.
struct TimedEvent {
  double time;  // absolute
  double stepTime;
  bool begin;
  FixtureId sensor, visitor;
  BodyId sensorBody, visitorBody;
};

std::vector<TimedEvent> stepAndCollect(World& world, double dt) {
  const double t0 = world.time();
  world.step(dt);
  std::vector<TimedEvent> out;
  for (const SensorEvent& e : world.sensorEvents())
    out.push_back({t0 + e.time, e.time, e.begin, e.sensor, e.visitor, e.sensorBody, e.visitorBody});
  return out;
}

std::vector<TimedEvent> runAndCollect(World& world, double dt, int steps) {
  std::vector<TimedEvent> all;
  for (int i = 0; i < steps; ++i) {
    auto ev = stepAndCollect(world, dt);
    all.insert(all.end(), ev.begin(), ev.end());
  }
  return all;
}

std::vector<TimedEvent> eventsOf(const std::vector<TimedEvent>& all, FixtureId sensor, FixtureId visitor) {
  std::vector<TimedEvent> out;
  for (const TimedEvent& e : all)
    if (e.sensor == sensor && e.visitor == visitor) out.push_back(e);
  return out;
}

FixtureId addFixture(World& world, BodyId body, const Geometry& g, bool sensor, double restitution = 0.0,
                     rattle::Filter filter = {}) {
  FixtureDef fd;
  fd.geometry = g;
  fd.sensor = sensor;
  fd.restitution = restitution;
  fd.filter = filter;
  return world.createFixture(body, fd);
}

/// The two roots (t1 <= t2) of |p + v t - q|^2 = R^2, in long double; the circle of radius R about q
/// is entered at t1 and left at t2. Requires a real crossing.
std::pair<LD, LD> circleCrossings(Vec2 p, Vec2 v, Vec2 q, LD R) {
  const LD dx = LD(p.x) - q.x, dy = LD(p.y) - q.y;
  const LD a = LD(v.x) * v.x + LD(v.y) * v.y;
  const LD b = dx * v.x + dy * v.y;  // half the linear coefficient
  const LD c = dx * dx + dy * dy - R * R;
  const LD disc = b * b - a * c;
  EXPECT_GT(disc, 0) << "no crossing";
  const LD s = std::sqrt(disc);
  return {(-b - s) / a, (-b + s) / a};
}

/// The two roots (t1 <= t2) of y0 + vy t + g t^2 / 2 = h.
std::pair<LD, LD> parabolaCrossings(LD y0, LD vy, LD g, LD h) {
  const LD a = g / 2, b = vy, c = y0 - h;
  const LD disc = b * b - 4 * a * c;
  EXPECT_GT(disc, 0);
  const LD s = std::sqrt(disc);
  LD r1 = (-b - s) / (2 * a), r2 = (-b + s) / (2 * a);
  if (r1 > r2) std::swap(r1, r2);
  return {r1, r2};
}

/// Every event is of one of the given (sensor, visitor) pairs.
void expectOnlyPairs(const std::vector<TimedEvent>& all, std::vector<std::pair<FixtureId, FixtureId>> pairs) {
  for (const TimedEvent& e : all) {
    const bool known = std::any_of(pairs.begin(), pairs.end(),
                                   [&](const auto& p) { return p.first == e.sensor && p.second == e.visitor; });
    EXPECT_TRUE(known) << "unexpected event: sensor " << e.sensor.index << ", visitor " << e.visitor.index << " at t = "
                       << e.time;
  }
}

std::string describe(const std::vector<TimedEvent>& ev) {
  std::string s;
  char buf[160];
  for (const TimedEvent& e : ev) {
    std::snprintf(buf, sizeof buf, "  %s t=%.17g sensor=%u visitor=%u\n", e.begin ? "begin" : "end  ", e.time,
                  e.sensor.index, e.visitor.index);
    s += buf;
  }
  return s;
}

/// Checks that the events of one (sensor, visitor) pair are exactly: begin at `begin`, end at `end`.
/// When there are more (spurious extra changes), the first and last are still checked against the
/// analytic times, so a failure shows both problems.
void expectBeginEnd(const std::vector<TimedEvent>& all, FixtureId sensor, FixtureId visitor, LD begin, LD end,
                    double tol = 1e-12) {
  const auto ev = eventsOf(all, sensor, visitor);
  EXPECT_EQ(ev.size(), 2u) << "sensor " << sensor.index << ", visitor " << visitor.index << ":\n" << describe(ev);
  ASSERT_GE(ev.size(), 2u);
  for (size_t i = 0; i < ev.size(); ++i) EXPECT_EQ(ev[i].begin, i % 2 == 0) << "event " << i;
  EXPECT_TRUE(ev.front().begin);
  EXPECT_FALSE(ev.back().begin);
  EXPECT_NEAR(ev.front().time, static_cast<double>(begin), tol);
  EXPECT_NEAR(ev.back().time, static_cast<double>(end), tol);
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Signed clearance between a disk (centre c, radius r) and a placed geometry: > 0 apart, < 0
/// overlapping (-r when the centre is inside a polygon or circle), 0 touching.
double clearance(const Geometry& g, Vec2 position, Vec2 c, double r) {
  return rattle::distanceTo(g, c - position) - r;
}

// Every suite runs in the hybrid and the predictive mode (the discrete mode sees sensors only where
// bodies end a step: tests/test_discrete.cpp).
class SensorDoorway : public ModeTest {};
class SensorRoom : public ModeTest {};
class SensorSight : public ModeTest {};
class SensorRules : public ModeTest {};
class SensorKinematic : public ModeTest {};
class SensorBounce : public ModeTest {};
class SensorResting : public ModeTest {};
class SensorTeleport : public ModeTest {};
class SensorGravity : public ModeTest {};
class SensorOverlaps : public ModeTest {};
class SensorPairing : public ModeTest {};
class SensorBruteForce : public ModeTest {};

// ------------------------------------------------------------------------------------------------
// A static doorway: a Segment sensor.

TEST_P(SensorDoorway, DiskCrossingSegmentBeginsAndEndsAtAnalyticTimes) {
  World world(def());
  const BodyId door = world.createBody(bodyDef(BodyType::Static));
  const FixtureId sensor = addFixture(world, door, Segment{{0, -1}, {0, 1}}, true);

  // Through the inside: touches the segment's line when x + r = 0, leaves when x - r = 0.
  const Disk through = addDisk(world, DiskSpec{{-2, 0.5}, {1.5, 0}, 0.25, 1, 0});
  // Past the upper end, 0.15 above it: first and last touches are with the end point (0, 1):
  // x^2 + 0.15^2 = 0.25^2, x = -+0.2.
  const Disk overEnd = addDisk(world, DiskSpec{{-2, 1.15}, {1.5, 0}, 0.25, 1, 0});
  // Grazing the lower end exactly (a tangent touch at one instant): no event.
  const Disk grazing = addDisk(world, DiskSpec{{-2, -1.25}, {1.5, 0}, 0.25, 1, 0});

  const auto all = runAndCollect(world, 1.0 / 16, 48);  // 3 s
  expectBeginEnd(all, sensor, through.fixture, LD(1.75) / 1.5L, LD(2.25) / 1.5L);
  expectBeginEnd(all, sensor, overEnd.fixture, LD(1.8) / 1.5L, LD(2.2) / 1.5L);
  EXPECT_TRUE(eventsOf(all, sensor, grazing.fixture).empty()) << describe(all);
  expectOnlyPairs(all, {{sensor, through.fixture}, {sensor, overEnd.fixture}});
  // Every event names the bodies too.
  for (const TimedEvent& e : all) {
    EXPECT_EQ(e.sensorBody, door);
    EXPECT_EQ(e.visitorBody, world.body(e.visitor));
  }
  EXPECT_TRUE(world.sensorOverlaps(sensor).empty());
}

TEST_P(SensorDoorway, FastDiskCrossingInsideOneStepGetsBeginAndEnd) {
  World world(def());
  const BodyId door = world.createBody(bodyDef(BodyType::Static));
  const FixtureId sensor = addFixture(world, door, Segment{{0, -1}, {0, 1}}, true);
  // Moves 6.25 per step; the doorway is crossed between t = 0.009 and 0.011.
  const Disk fast = addDisk(world, DiskSpec{{-1, 0}, {100, 0}, 0.1, 1, 0});
  const double dt = 1.0 / 16;
  const auto ev = stepAndCollect(world, dt);
  for (const TimedEvent& e : ev) {
    EXPECT_GE(e.stepTime, 0.0);
    EXPECT_LE(e.stepTime, dt);
    EXPECT_EQ(e.sensor, sensor);
    EXPECT_EQ(e.visitor, fast.fixture);
  }
  expectBeginEnd(ev, sensor, fast.fixture, 0.009L, 0.011L);
  EXPECT_LT(ev.front().stepTime, ev.back().stepTime);
  EXPECT_TRUE(world.sensorOverlaps(sensor).empty());
  // Motion untouched.
  EXPECT_TRUE(sameBits(world.velocity(fast.body).x, 100.0));
  EXPECT_TRUE(world.contactEvents().empty());
}

// ------------------------------------------------------------------------------------------------
// A room (a static Polygon sensor) and a sight sensor (a Circle sensor on a dynamic body).

TEST_P(SensorRoom, PolygonSensorOnStaticBodyEdgeAndCornerExits) {
  World world(def());
  // The room is [10, 14] x [5, 8] in the world: a polygon given relative to a body at (10, 5).
  const Vec2 origin{10, 5};
  const BodyId roomBody = world.createBody(bodyDef(BodyType::Static, origin));
  const FixtureId room = addFixture(world, roomBody, Polygon{{{0, 0}, {4, 0}, {4, 3}, {0, 3}}}, true);

  // A: enters through the left edge (x + r = 10) at t = 0.5 and leaves through the right edge
  // (x - r = 14) at t = 5.5, inside the edges' spans both times.
  const Disk a = addDisk(world, DiskSpec{{9, 6.5}, {1, 0.2}, 0.5, 1, 0});
  // B: created inside (begins at time 0 of the first step) and leaves past the corner (14, 8): the
  // larger root of |c(t) - (14, 8)| = r, with the centre then beyond both edges' lines.
  const Disk b = addDisk(world, DiskSpec{{12, 6.2}, {1, 1}, 0.5, 1, 0});
  const auto [bIn, bOut] = circleCrossings({12, 6.2}, {1, 1}, {14, 8}, 0.5L);
  (void)bIn;
  ASSERT_GT(12 + bOut, 14.0L);
  ASSERT_GT(6.2L + bOut, 8.0L);

  const double dt = 1.0 / 16;
  std::vector<TimedEvent> all;
  for (int i = 0; i < 112; ++i) {  // 7 s
    auto ev = stepAndCollect(world, dt);
    all.insert(all.end(), ev.begin(), ev.end());
    // The visitors listed now, sorted by fixture index (a was created first). At a transition instant
    // (touching) either answer is right.
    const double t = world.time();
    const double transitions[3] = {0.5, 5.5, static_cast<double>(bOut)};
    if (std::any_of(std::begin(transitions), std::end(transitions), [&](double x) { return std::fabs(t - x) < 1e-9; }))
      continue;
    std::vector<FixtureId> expected;
    if (t > 0.5 && t < 5.5) expected.push_back(a.fixture);
    if (t < static_cast<double>(bOut)) expected.push_back(b.fixture);
    EXPECT_EQ(world.sensorOverlaps(room), expected) << "t = " << t;
  }
  expectBeginEnd(all, room, a.fixture, 0.5L, 5.5L);
  expectBeginEnd(all, room, b.fixture, 0.0L, bOut);
  const auto ofB = eventsOf(all, room, b.fixture);
  ASSERT_FALSE(ofB.empty());
  EXPECT_EQ(ofB[0].stepTime, 0.0);  // created inside: time 0 of the first step
}

TEST_P(SensorSight, CircleSensorOnDynamicBodySeesAnotherMovingDisk) {
  World world(def());
  // The watcher: a physical circle of radius 0.5 and a concentric sight circle of radius 3.
  const Disk watcher = addDisk(world, DiskSpec{{0, 0}, {1, 0}, 0.5, 1, 0});
  const FixtureId sight = addFixture(world, watcher.body, Circle{{0, 0}, 3.0}, true);
  EXPECT_DOUBLE_EQ(world.mass(watcher.body), std::numbers::pi * 0.25);  // a sensor has no mass
  // The other disk passes 1.5 above it the other way (never touching physically: 1.5 > 0.9).
  const Disk other = addDisk(world, DiskSpec{{10, 1.5}, {-1, 0}, 0.4, 1, 0});

  // d(t) = other - watcher = (10 - 2t, 1.5): seen while |d| <= 3 + 0.4.
  const auto [tIn, tOut] = circleCrossings({10, 1.5}, {-2, 0}, {0, 0}, 3.4L);
  const auto all = runAndCollect(world, 1.0 / 16, 160);  // 10 s
  expectBeginEnd(all, sight, other.fixture, tIn, tOut);
  expectOnlyPairs(all, {{sight, other.fixture}});
  for (const TimedEvent& e : all) {
    EXPECT_EQ(e.sensorBody, watcher.body);
    EXPECT_EQ(e.visitorBody, other.body);
  }
  EXPECT_TRUE(world.contactEvents().empty());
  EXPECT_EQ(world.velocity(watcher.body), Vec2(1, 0));
  EXPECT_EQ(world.velocity(other.body), Vec2(-1, 0));
}

// ------------------------------------------------------------------------------------------------
// Rules: sensors do not sense sensors and never change motion.

TEST_P(SensorRules, SensorsNeverSenseEachOther) {
  World world(def());
  // Two dynamic bodies holding only sensors pass through each other.
  const BodyId s1 = world.createBody(bodyDef(BodyType::Dynamic, {-3, 0}, {1, 0}));
  const FixtureId f1 = addFixture(world, s1, Circle{{0, 0}, 1.0}, true);
  const BodyId s2 = world.createBody(bodyDef(BodyType::Dynamic, {3, 0}, {-1, 0}));
  const FixtureId f2 = addFixture(world, s2, Circle{{0, 0}, 1.0}, true);
  // Far above: a sensor-only dynamic body crosses a static Polygon sensor, and a body with a physical
  // circle (0.3) and a sight sensor (1) crosses another static Polygon sensor; only the physical
  // circle is seen, by the static sensor.
  const BodyId room1 = world.createBody(bodyDef(BodyType::Static, {0, 20}));
  const FixtureId r1 = addFixture(world, room1, Polygon{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}}, true);
  const BodyId s3 = world.createBody(bodyDef(BodyType::Dynamic, {-4, 20}, {1, 0}));
  const FixtureId f3 = addFixture(world, s3, Circle{{0, 0}, 0.5}, true);
  const BodyId room2 = world.createBody(bodyDef(BodyType::Static, {0, 40}));
  const FixtureId r2 = addFixture(world, room2, Polygon{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}}, true);
  const Disk mixed = addDisk(world, DiskSpec{{-4, 40}, {1, 0}, 0.3, 1, 0});
  const FixtureId mixedSight = addFixture(world, mixed.body, Circle{{0, 0}, 1.0}, true);

  const double dt = 1.0 / 16;
  std::vector<TimedEvent> all;
  for (int i = 0; i < 128; ++i) {
    auto ev = stepAndCollect(world, dt);
    all.insert(all.end(), ev.begin(), ev.end());
    for (FixtureId f : {f1, f2, f3, mixedSight}) EXPECT_TRUE(world.sensorOverlaps(f).empty());
    EXPECT_TRUE(world.sensorOverlaps(r1).empty());
    EXPECT_TRUE(world.contactEvents().empty());
  }
  // Only the physical circle in room 2: |x| <= 1 + 0.3 with x = -4 + t.
  expectBeginEnd(all, r2, mixed.fixture, 2.7L, 5.3L);
  expectOnlyPairs(all, {{r2, mixed.fixture}});
}

TEST_P(SensorRules, SensorNeverChangesMotion) {
  World world(def());
  // One sensor of every geometry along the disk's path y = 0.3 + 0.08 t, x = -5 + 1.25 t.
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  std::vector<FixtureId> sensors{
      addFixture(world, holder, Point{{-3, 0.4}}, true, 1.0),
      addFixture(world, holder, Circle{{-1, 0.2}, 0.6}, true, 1.0),
      addFixture(world, holder, Segment{{1, -1}, {1.2, 2}}, true, 1.0),
      addFixture(world, holder, Polyline{{{3, -1}, {3.5, 1}, {3, 2}}}, true, 1.0),
      addFixture(world, holder, Polygon{{{5, -1}, {7, -0.5}, {6, 2}}}, true, 1.0),
  };
  const Vec2 v{1.25, 0.08};
  const Disk disk = addDisk(world, DiskSpec{{-5, 0.3}, v, 0.35, 2.0, 1.0});
  const double dt = 1.0 / 16;
  Vec2 expected{-5, 0.3};
  std::vector<TimedEvent> all;
  for (int i = 0; i < 224; ++i) {  // 14 s: past every sensor
    auto ev = stepAndCollect(world, dt);
    all.insert(all.end(), ev.begin(), ev.end());
    ASSERT_TRUE(world.contactEvents().empty()) << "step " << i;
    const Vec2 got = world.velocity(disk.body);
    ASSERT_TRUE(sameBits(got.x, v.x) && sameBits(got.y, v.y)) << "step " << i;
    expected = expected + v * dt;
    EXPECT_NEAR(world.position(disk.body).x, expected.x, 1e-12);
    EXPECT_NEAR(world.position(disk.body).y, expected.y, 1e-12);
  }
  // Each sensor was visited once: a begin then an end.
  for (FixtureId s : sensors) {
    const auto ev = eventsOf(all, s, disk.fixture);
    EXPECT_EQ(ev.size(), 2u) << "sensor " << s.index << "\n" << describe(ev);
    ASSERT_GE(ev.size(), 2u);
    for (size_t i = 0; i < ev.size(); ++i) EXPECT_EQ(ev[i].begin, i % 2 == 0);
    EXPECT_LT(ev.front().time, ev.back().time);
  }
}

TEST_P(SensorRules, SensorOnDynamicBodyDoesNotCollideWithWalls) {
  World world(def());
  const BodyId wallBody = world.createBody(bodyDef(BodyType::Static));
  const FixtureId wall = addFixture(world, wallBody, Segment{{0, -5}, {0, 5}}, false, 1.0);
  // A sensor-only body passes straight through the wall (the wall is a physical fixture, so it is
  // reported as a visitor of the moving sensor).
  const BodyId ghost = world.createBody(bodyDef(BodyType::Dynamic, {-3, 3}, {1, 0}));
  const FixtureId ghostSensor = addFixture(world, ghost, Circle{{0, 0}, 1.0}, true, 1.0);
  // A body with a small physical circle (0.1) and a large sight circle (1): the sight circle reaches the
  // wall at t = 2, but the body bounces only when its physical circle does, at t = 2.9, and the sight
  // circle leaves the wall at t = 2.9 + 0.9.
  const Disk probe = addDisk(world, DiskSpec{{-3, -3}, {1, 0}, 0.1, 1, 1.0});
  const FixtureId probeSight = addFixture(world, probe.body, Circle{{0, 0}, 1.0}, true, 1.0);

  const double dt = 1.0 / 16;
  std::vector<TimedEvent> all;
  std::vector<rattle::ContactEvent> contacts;
  for (int i = 0; i < 96; ++i) {  // 6 s
    const double t0 = world.time();
    auto ev = stepAndCollect(world, dt);
    all.insert(all.end(), ev.begin(), ev.end());
    for (auto c : world.contactEvents()) {
      c.time += t0;
      contacts.push_back(c);
    }
  }
  ASSERT_EQ(contacts.size(), 1u);
  EXPECT_NEAR(contacts[0].time, 2.9, 1e-12);
  EXPECT_TRUE(contacts[0].fixtureA == probe.fixture || contacts[0].fixtureB == probe.fixture);
  EXPECT_EQ(world.velocity(ghost), Vec2(1, 0));
  EXPECT_NEAR(world.position(ghost).x, 3.0, 1e-12);
  EXPECT_NEAR(world.velocity(probe.body).x, -1.0, 1e-12);
  // The ghost's sensor overlaps the wall while |x| <= 1: t in [2, 4].
  expectBeginEnd(all, ghostSensor, wall, 2.0L, 4.0L);
  expectBeginEnd(all, probeSight, wall, 2.0L, 3.8L);
  expectOnlyPairs(all, {{ghostSensor, wall}, {probeSight, wall}});
}

// ------------------------------------------------------------------------------------------------
// Kinematic bodies' physical fixtures trigger sensors.

TEST_P(SensorKinematic, PolygonSlidingAcrossStaticPolygonSensor) {
  World world(def());
  // A diamond sensor |x| + |y| <= 1.
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  const FixtureId diamond = addFixture(world, holder, Polygon{{{1, 0}, {0, 1}, {-1, 0}, {0, -1}}}, true);
  // A unit square centred at (X, 1.2), X = -5 + 2t. Its bottom edge y = 0.7 meets the diamond where
  // |x| <= 0.3: its lower right corner crosses the edge y = x + 1 when X + 0.5 = -0.3 (t = 2.1), and its
  // lower left corner leaves the edge y = 1 - x when X - 0.5 = 0.3 (t = 2.9).
  const BodyId high = world.createBody(bodyDef(BodyType::Kinematic, {-5, 1.2}, {2, 0}));
  const FixtureId highSquare =
      addFixture(world, high, Polygon{{{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}}, false);
  // A second square centred on the diamond's axis, X = 5 - 2.5 t, moving left: its left edge touches the
  // corner (1, 0) when X - 0.5 = 1 (t = 1.4); its right edge leaves the corner (-1, 0) when
  // X + 0.5 = -1 (t = 2.6).
  const BodyId level = world.createBody(bodyDef(BodyType::Kinematic, {5, 0.25}, {-2.5, 0}));
  const FixtureId levelSquare =
      addFixture(world, level, Polygon{{{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}}, false);

  const auto all = runAndCollect(world, 1.0 / 16, 80);  // 5 s
  expectBeginEnd(all, diamond, highSquare, 2.1L, 2.9L);
  expectBeginEnd(all, diamond, levelSquare, 1.4L, 2.6L);
  expectOnlyPairs(all, {{diamond, highSquare}, {diamond, levelSquare}});
  EXPECT_TRUE(world.contactEvents().empty());
}

TEST_P(SensorKinematic, SegmentSlidingAcrossStaticCircleSensor) {
  World world(def());
  const Vec2 centre{20, -3};
  const BodyId holder = world.createBody(bodyDef(BodyType::Static, centre));
  const FixtureId disk = addFixture(world, holder, Circle{{0, 0}, 1.0}, true);
  // A vertical segment spanning y in [0.3, 1.3] relative to the centre, moving right at 1.5: its lower
  // end is the closest point, at distance 1 when X = -+sqrt(0.91).
  const BodyId upper = world.createBody(bodyDef(BodyType::Kinematic, centre + Vec2{-3, 0.8}, {1.5, 0}));
  const FixtureId upperSegment = addFixture(world, upper, Segment{{0, -0.5}, {0, 0.5}}, false);
  // One spanning y in [-0.5, 0.5]: touched through its inside when X = -+1.
  const BodyId middle = world.createBody(bodyDef(BodyType::Kinematic, centre + Vec2{-3, 0}, {1.5, 0}));
  const FixtureId middleSegment = addFixture(world, middle, Segment{{0, -0.5}, {0, 0.5}}, false);

  const auto all = runAndCollect(world, 1.0 / 16, 80);  // 5 s
  const LD s = std::sqrt(0.91L);
  expectBeginEnd(all, disk, upperSegment, (3 - s) / 1.5L, (3 + s) / 1.5L);
  expectBeginEnd(all, disk, middleSegment, 2 / 1.5L, 4 / 1.5L);
  expectOnlyPairs(all, {{disk, upperSegment}, {disk, middleSegment}});
}

// ------------------------------------------------------------------------------------------------
// Collisions inside a step change the paths sensors see.

TEST_P(SensorBounce, ReEntersAfterBouncingOffAWall) {
  World world(def());
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  addFixture(world, holder, Segment{{0, -5}, {0, 5}}, false, 1.0);
  const FixtureId strip = addFixture(world, holder, Polygon{{{-1.5, -2}, {-1, -2}, {-1, 2}, {-1.5, 2}}}, true);
  // x = -3 + 2t, r = 0.25: in the strip while x + r >= -1.5 and x - r <= -1 (t in [0.625, 1.125]); bounces
  // at x = -0.25 (t = 1.375); back in while x - r <= -1 (t = 1.625) until x + r < -1.5 (t = 2.125).
  const Disk d = addDisk(world, DiskSpec{{-3, 0}, {2, 0}, 0.25, 1, 1.0});
  const auto all = runAndCollect(world, 0.1, 30);
  const auto ev = eventsOf(all, strip, d.fixture);
  EXPECT_EQ(ev.size(), 4u) << describe(ev);
  ASSERT_GE(ev.size(), 4u);
  const double expected[4] = {0.625, 1.125, 1.625, 2.125};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(ev[i].begin, i % 2 == 0) << "event " << i;
    EXPECT_NEAR(ev[i].time, expected[i], 1e-12) << "event " << i;
  }
}

TEST_P(SensorBounce, PathTurnedMidStepIntoASensorOutsideTheSweptBox) {
  World world(def());
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  addFixture(world, holder, Segment{{0, -5}, {0, 5}}, false, 1.0);
  // Behind the disk's start: its swept box for the step (moving right) does not reach it.
  const FixtureId behind = addFixture(world, holder, Polygon{{{-1.5, -1}, {-1.2, -1}, {-1.2, 1}, {-1.5, 1}}}, true);
  // r = 0.1 from x = -0.5 at 10: bounces at x = -0.1 (t = 0.04), then x = -0.1 - 10 (t - 0.04): in the
  // sensor from x - r = -1.2 (t = 0.14) until x + r = -1.5 (t = 0.19), all inside one step of 0.25.
  const Disk d = addDisk(world, DiskSpec{{-0.5, 0}, {10, 0}, 0.1, 1, 1.0});
  const auto ev = stepAndCollect(world, 0.25);
  ASSERT_EQ(world.contactEvents().size(), 1u);
  EXPECT_NEAR(world.contactEvents()[0].time, 0.04, 1e-12);
  expectBeginEnd(ev, behind, d.fixture, 0.14L, 0.19L);
}

// ------------------------------------------------------------------------------------------------
// Bodies that stop, and bodies moved by hand.

TEST_P(SensorResting, SleepingBodyStaysInsideUntilItMovesOut) {
  WorldDef def = ModeTest::def();
  def.gravity = {0, -10};
  World world(def);
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  addFixture(world, holder, Segment{{-5, 0}, {5, 0}}, false, 0.0);
  const FixtureId zone = addFixture(world, holder, Polygon{{{-1, 0}, {1, 0}, {1, 1}, {-1, 1}}}, true);
  // Created inside, it falls 0.25 onto the floor, stops (restitution 0) and sleeps there.
  const Disk ball = addDisk(world, DiskSpec{{0, 0.5}, {0, 0}, 0.25, 1, 0.0});
  auto all = runAndCollect(world, 0.05, 100);
  EXPECT_TRUE(world.isAsleep(ball.body));
  ASSERT_EQ(all.size(), 1u) << describe(all);  // a sleeping body in a static sensor ends nothing
  EXPECT_TRUE(all[0].begin);
  EXPECT_EQ(all[0].time, 0.0);
  EXPECT_EQ(world.sensorOverlaps(zone), std::vector<FixtureId>{ball.fixture});
  // Pushed sideways at 3, it slides along the floor (y = 0.25) and leaves when x - r = 1: 1.25 / 3 later.
  const double t0 = world.time();
  world.setVelocity(ball.body, {3, 0});
  all = runAndCollect(world, 0.05, 20);
  const auto ev = eventsOf(all, zone, ball.fixture);
  ASSERT_EQ(ev.size(), 1u) << describe(all);
  EXPECT_FALSE(ev[0].begin);
  EXPECT_NEAR(ev[0].time, t0 + 1.25 / 3, 1e-9);
  EXPECT_TRUE(world.sensorOverlaps(zone).empty());
}

TEST_P(SensorTeleport, SetPositionOutEndsAtTimeZeroAndBackInBegins) {
  World world(def());
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  const FixtureId diamond = addFixture(world, holder, Polygon{{{1, 0}, {0, 1}, {-1, 0}, {0, -1}}}, true);
  // Overlapping the edge x + y = 1 (clearance (1.2 - 1) / sqrt 2 - 0.2 < 0), at rest.
  const Disk d = addDisk(world, DiskSpec{{0.6, 0.6}, {0, 0}, 0.2, 1, 0});
  auto expectOne = [&](bool begin, const char* what) {
    const auto ev = stepAndCollect(world, 0.1);
    ASSERT_EQ(ev.size(), 1u) << what << "\n" << describe(ev);
    EXPECT_EQ(ev[0].begin, begin) << what;
    EXPECT_EQ(ev[0].stepTime, 0.0) << what;
    EXPECT_EQ(ev[0].visitor, d.fixture) << what;
  };
  expectOne(true, "created inside");
  // Just outside, where the boxes still overlap (the sweep sees the pair): ends at time 0.
  world.setPosition(d.body, {0.7, 0.7});
  expectOne(false, "moved just outside");
  EXPECT_TRUE(world.sensorOverlaps(diamond).empty());
  // Far away, then back inside, then far away again (the sweep does not see the pair then).
  world.setPosition(d.body, {50, 50});
  EXPECT_TRUE(stepAndCollect(world, 0.1).empty());
  world.setPosition(d.body, {0, 0});
  expectOne(true, "moved back inside");
  EXPECT_EQ(world.sensorOverlaps(diamond), std::vector<FixtureId>{d.fixture});
  world.setPosition(d.body, {50, 50});
  expectOne(false, "moved far away");
  EXPECT_TRUE(world.sensorOverlaps(diamond).empty());
}

// ------------------------------------------------------------------------------------------------
// Gravity: parabolic paths.

TEST_P(SensorGravity, BallFallsThroughHorizontalStrip) {
  WorldDef def = ModeTest::def();
  def.gravity = {0, -9.81};
  World world(def);
  // The strip: 0 <= y <= 0.5, wide.
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  const FixtureId strip = addFixture(world, holder, Polygon{{{-10, 0}, {10, 0}, {10, 0.5}, {-10, 0.5}}}, true);
  const double r = 0.25;
  // Dropped from y = 5 with a sideways speed: begins when y - r = 0.5, ends when y + r = 0.
  const Disk dropped = addDisk(world, DiskSpec{{0, 5}, {0.3, 0}, r, 1, 0});
  // Thrown up from below (x far away) through the strip, turning above it and coming back down: two
  // visits, four events.
  const Disk thrown = addDisk(world, DiskSpec{{5, -2}, {-0.5, 8}, r, 1, 0});

  const auto all = runAndCollect(world, 1.0 / 16, 40);  // 2.5 s
  const LD g = -9.81L;
  const LD beginDrop = parabolaCrossings(5, 0, g, 0.5L + r).second;
  const LD endDrop = parabolaCrossings(5, 0, g, -r).second;
  expectBeginEnd(all, strip, dropped.fixture, beginDrop, endDrop, 1e-11);

  const auto [upIn, downOut] = parabolaCrossings(-2, 8, g, -r);
  const auto [upOut, downIn] = parabolaCrossings(-2, 8, g, 0.5L + r);
  const auto ev = eventsOf(all, strip, thrown.fixture);
  ASSERT_EQ(ev.size(), 4u) << describe(all);
  const LD expected[4] = {upIn, upOut, downIn, downOut};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(ev[static_cast<size_t>(i)].begin, i % 2 == 0);
    EXPECT_NEAR(ev[static_cast<size_t>(i)].time, static_cast<double>(expected[i]), 1e-11) << "event " << i;
  }
  expectOnlyPairs(all, {{strip, dropped.fixture}, {strip, thrown.fixture}});
}

// ------------------------------------------------------------------------------------------------
// sensorOverlaps, destroying and filtering.

std::vector<uint32_t> indicesOf(const std::vector<FixtureId>& ids) {
  std::vector<uint32_t> out;
  for (FixtureId f : ids) out.push_back(f.index);
  return out;
}

TEST_P(SensorOverlaps, SortedVisitorsAndEndsOnDestroyAndFilterChange) {
  World world(def());
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  const FixtureId room = addFixture(world, holder, Polygon{{{0, 0}, {4, 0}, {4, 4}, {0, 4}}}, true);
  // Created in this order (fixture indices increasing), they enter in another order: c at time 0 (created
  // inside, at rest), b at t = 1.5, a at t = 4.5; sensorOverlaps lists them by index anyway. Their paths
  // keep them apart (y = 0.6, 3.5 and c at y = 2).
  const Disk a = addDisk(world, DiskSpec{{-5, 0.6}, {1, 0}, 0.5, 1, 0});
  const Disk b = addDisk(world, DiskSpec{{-2, 3.5}, {1, 0}, 0.5, 1, 0});
  const Disk c = addDisk(world, DiskSpec{{2, 2}, {0, 0}, 0.5, 1, 0});
  const double dt = 0.25;

  auto ev = stepAndCollect(world, dt);
  ASSERT_EQ(ev.size(), 1u) << describe(ev);
  EXPECT_TRUE(ev[0].begin);
  EXPECT_EQ(ev[0].visitor, c.fixture);
  EXPECT_EQ(ev[0].stepTime, 0.0);
  EXPECT_EQ(world.sensorOverlaps(room), std::vector<FixtureId>{c.fixture});
  std::vector<TimedEvent> all;
  for (int i = 0; i < 7; ++i) stepAndCollect(world, dt);  // t = 2
  EXPECT_EQ(indicesOf(world.sensorOverlaps(room)), (std::vector<uint32_t>{b.fixture.index, c.fixture.index}));
  for (int i = 0; i < 12; ++i) stepAndCollect(world, dt);  // t = 5: a at x = 0, b at x = 3 (leaving at 6.5)
  EXPECT_EQ(world.sensorOverlaps(room), (std::vector<FixtureId>{a.fixture, b.fixture, c.fixture}));

  // Destroying a visitor's body: gone from sensorOverlaps at once, ended at time 0 of the next step
  // (under its old ids); the last step's events stay as they were.
  const auto before = world.sensorEvents().size();
  world.destroyBody(b.body);
  EXPECT_EQ(world.sensorOverlaps(room), (std::vector<FixtureId>{a.fixture, c.fixture}));
  EXPECT_EQ(world.sensorEvents().size(), before);

  // Filter changes that still let the two meet change nothing.
  world.setFilter(c.fixture, filterOf(0x0004, 0xFFFFFFFB));  // category 4, ignoring only category 4
  world.setFilter(c.fixture, filterOf(0x0001, 0xFFFFFFFF, 3));  // a group of its own
  EXPECT_EQ(world.sensorOverlaps(room), (std::vector<FixtureId>{a.fixture, c.fixture}));
  // One that does not: c ignores the room's category 1.
  world.setFilter(c.fixture, filterOf(0x0004, 0x0002));
  EXPECT_EQ(world.sensorOverlaps(room), (std::vector<FixtureId>{a.fixture}));

  ev = stepAndCollect(world, dt);  // to t = 5.25
  ASSERT_EQ(ev.size(), 2u) << describe(ev);
  EXPECT_FALSE(ev[0].begin);
  EXPECT_EQ(ev[0].visitor, b.fixture);
  EXPECT_EQ(ev[0].visitorBody, b.body);
  EXPECT_EQ(ev[0].sensor, room);
  EXPECT_EQ(ev[0].stepTime, 0.0);
  EXPECT_FALSE(ev[1].begin);
  EXPECT_EQ(ev[1].visitor, c.fixture);
  EXPECT_EQ(ev[1].stepTime, 0.0);
  EXPECT_FALSE(world.isValid(b.fixture));
  EXPECT_EQ(world.sensorOverlaps(room), (std::vector<FixtureId>{a.fixture}));

  // From the sensor's side: a and the room in one group end a's overlap. Restoring c's filter lets it
  // begin again at time 0 of the next step, as it is still inside; the begin waits for that step.
  world.setFilter(a.fixture, filterOf(0x0001, 0xFFFFFFFF, 7));
  EXPECT_EQ(world.sensorOverlaps(room), (std::vector<FixtureId>{a.fixture}));  // different groups still meet
  world.setFilter(room, filterOf(0x0001, 0xFFFFFFFF, 7));
  EXPECT_TRUE(world.sensorOverlaps(room).empty());
  world.setFilter(c.fixture, filterOf());
  EXPECT_TRUE(world.sensorOverlaps(room).empty());
  ev = stepAndCollect(world, dt);  // to t = 5.5
  ASSERT_EQ(ev.size(), 2u) << describe(ev);
  EXPECT_FALSE(ev[0].begin);
  EXPECT_EQ(ev[0].visitor, a.fixture);
  EXPECT_EQ(ev[0].stepTime, 0.0);
  EXPECT_TRUE(ev[1].begin);
  EXPECT_EQ(ev[1].visitor, c.fixture);
  EXPECT_EQ(ev[1].stepTime, 0.0);
  EXPECT_EQ(world.sensorOverlaps(room), std::vector<FixtureId>{c.fixture});

  // Destroying only the visiting fixture (its body stays).
  world.destroyFixture(c.fixture);
  EXPECT_TRUE(world.sensorOverlaps(room).empty());
  EXPECT_TRUE(world.isValid(c.body));
  ev = stepAndCollect(world, dt);  // to t = 5.75
  ASSERT_EQ(ev.size(), 1u) << describe(ev);
  EXPECT_FALSE(ev[0].begin);
  EXPECT_EQ(ev[0].visitor, c.fixture);
  EXPECT_EQ(ev[0].stepTime, 0.0);

  // The room leaves the group: a (at x = 0.75) begins at time 0 of the next step, and ends when it
  // leaves at t = 9.5.
  world.setFilter(room, filterOf());
  all = runAndCollect(world, dt, 17);  // to t = 10
  ASSERT_EQ(all.size(), 2u) << describe(all);
  EXPECT_TRUE(all[0].begin);
  EXPECT_EQ(all[0].visitor, a.fixture);
  EXPECT_EQ(all[0].time, 5.75);
  EXPECT_FALSE(all[1].begin);
  EXPECT_EQ(all[1].visitor, a.fixture);
  EXPECT_NEAR(all[1].time, 9.5, 1e-12);
  EXPECT_TRUE(world.sensorOverlaps(room).empty());
}

TEST_P(SensorOverlaps, ZeroLengthStepBeginsWhatWasCreatedInside) {
  World world(def());
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  const FixtureId zone = addFixture(world, holder, Circle{{0, 0}, 1.0}, true);
  const Disk d = addDisk(world, DiskSpec{{0.5, 0}, {1, 0}, 0.2, 1, 0});
  EXPECT_TRUE(world.sensorOverlaps(zone).empty());  // begins are found by the next step
  const auto ev = stepAndCollect(world, 0.0);
  ASSERT_EQ(ev.size(), 1u) << describe(ev);
  EXPECT_TRUE(ev[0].begin);
  EXPECT_EQ(ev[0].stepTime, 0.0);
  EXPECT_EQ(world.sensorOverlaps(zone), std::vector<FixtureId>{d.fixture});
  // Leaves when x - r = 1: t = 0.7.
  const auto later = runAndCollect(world, 0.25, 4);
  ASSERT_EQ(later.size(), 1u) << describe(later);
  EXPECT_FALSE(later[0].begin);
  EXPECT_NEAR(later[0].time, 0.7, 1e-12);
}

// A brute-force pairing check over a busy scene: 100 moving disks bouncing in a box, 10 static sensors
// (two of each geometry), 300 steps with random destroys, re-creations and filter changes on both sides.
struct PairKey {
  uint32_t sensorIndex, sensorGeneration, visitorIndex, visitorGeneration;
  auto operator<=>(const PairKey&) const = default;
};

PairKey keyOf(const SensorEvent& e) {
  return {e.sensor.index, e.sensor.generation, e.visitor.index, e.visitor.generation};
}

Geometry randomSensorGeometry(int kind, std::mt19937_64& rng) {
  auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53); };
  switch (kind) {
    case 0:
      return Point{{uniform(-0.5, 0.5), uniform(-0.5, 0.5)}};
    case 1:
      return Circle{{uniform(-0.5, 0.5), uniform(-0.5, 0.5)}, uniform(0.3, 2.0)};
    case 2: {
      const double a = uniform(0, std::numbers::pi), l = uniform(1, 4);
      return Segment{{-l * std::cos(a), -l * std::sin(a)}, {l * std::cos(a), l * std::sin(a)}};
    }
    case 3: {
      Polyline p;
      const int n = 3 + static_cast<int>(rng() % 3);
      for (int i = 0; i < n; ++i) p.points.push_back({-2.0 + 1.1 * i, uniform(-1.5, 1.5)});
      return p;
    }
    default: {
      Polygon p;
      const int n = 3 + static_cast<int>(rng() % 4);
      const double rad = uniform(0.5, 2.5), phase = uniform(0, 1);
      for (int i = 0; i < n; ++i) {
        const double a = 2 * std::numbers::pi * (i + phase) / n;
        p.points.push_back({rad * std::cos(a), rad * std::sin(a) * 0.7});
      }
      return p;
    }
  }
}

TEST_P(SensorPairing, BeginsAndEndsAlwaysPairUpUnderDestroysAndFilterChanges) {
  World world(def());
  const ClosedBox box = makeClosedBox(world, 0, 0, 20, 20, 1.0);
  RandomDiskOptions opt;
  opt.count = 100;
  opt.seed = 17;
  opt.xmin = 0, opt.ymin = 0, opt.xmax = 20, opt.ymax = 20;
  opt.minRadius = 0.2, opt.maxRadius = 0.6;
  opt.minSpeed = 1, opt.maxSpeed = 6;
  std::vector<Disk> disks = addDisks(world, randomDisks(opt));

  std::mt19937_64 rng(99);
  auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53); };
  struct SensorSlot {
    BodyId body;
    FixtureId fixture;
    Geometry geometry;
  };
  std::vector<SensorSlot> sensors;
  for (int i = 0; i < 10; ++i) {
    SensorSlot s;
    s.body = world.createBody(bodyDef(BodyType::Static, {uniform(3, 17), uniform(3, 17)}));
    s.geometry = randomSensorGeometry(i % 5, rng);
    s.fixture = addFixture(world, s.body, s.geometry, true, 0.0, filterOf(0x0002));
    sensors.push_back(s);
  }

  std::map<PairKey, double> open;  // begin time (absolute) of every overlap begun and not ended
  int begins = 0, ends = 0, destroys = 0, filterChanges = 0, sensorRebuilds = 0;
  const double dt = 1.0 / 30;
  for (int step = 0; step < 300; ++step) {
    const double t0 = world.time();
    world.step(dt);
    double last = 0;
    for (const SensorEvent& e : world.sensorEvents()) {
      ASSERT_GE(e.time, last) << "events out of order at step " << step;
      ASSERT_LE(e.time, dt);
      last = e.time;
      const PairKey k = keyOf(e);
      if (e.begin) {
        ++begins;
        ASSERT_EQ(open.count(k), 0u) << "second begin without an end: step " << step << " sensor " << k.sensorIndex
                                     << " visitor " << k.visitorIndex;
        open[k] = t0 + e.time;
      } else {
        ++ends;
        auto it = open.find(k);
        ASSERT_NE(it, open.end()) << "end without a begin: step " << step << " sensor " << k.sensorIndex << " visitor "
                                  << k.visitorIndex;
        ASSERT_LE(it->second, t0 + e.time);
        open.erase(it);
      }
    }
    // After each step the open begins are exactly what sensorOverlaps lists.
    std::map<std::pair<uint32_t, uint32_t>, std::vector<FixtureId>> bySensor;
    for (const auto& [k, t] : open) {
      ASSERT_TRUE(world.isValid(FixtureId{k.sensorIndex, k.sensorGeneration})) << "open overlap of a dead sensor";
      ASSERT_TRUE(world.isValid(FixtureId{k.visitorIndex, k.visitorGeneration})) << "open overlap of a dead visitor";
      bySensor[{k.sensorIndex, k.sensorGeneration}].push_back({k.visitorIndex, k.visitorGeneration});
    }
    for (const SensorSlot& s : sensors) {
      auto expected = bySensor[{s.fixture.index, s.fixture.generation}];
      std::sort(expected.begin(), expected.end(), [](FixtureId x, FixtureId y) { return x.index < y.index; });
      ASSERT_EQ(world.sensorOverlaps(s.fixture), expected) << "step " << step << " sensor " << s.fixture.index;
    }

    // Mutations between steps.
    const uint64_t roll = rng() % 100;
    if (roll < 8) {
      // Destroy a disk, and add one at a free spot (somewhere not overlapping any other disk).
      const size_t i = rng() % disks.size();
      world.destroyBody(disks[i].body);
      ++destroys;
      bool placed = false;
      for (int attempt = 0; attempt < 1000 && !placed; ++attempt) {
        DiskSpec d;
        d.radius = uniform(0.2, 0.6);
        d.position = {uniform(1, 19), uniform(1, 19)};
        const double angle = uniform(0, 2 * std::numbers::pi), speed = uniform(1, 6);
        d.velocity = {speed * std::cos(angle), speed * std::sin(angle)};
        bool free = true;
        for (size_t j = 0; j < disks.size() && free; ++j) {
          if (j == i) continue;
          free = rattle::length(world.position(disks[j].body) - d.position) > disks[j].radius + d.radius + 1e-3;
        }
        if (!free) continue;
        disks[i] = addDisk(world, d);
        placed = true;
      }
      if (!placed) disks.erase(disks.begin() + static_cast<std::ptrdiff_t>(i));
    } else if (roll < 25) {
      // Toggle a disk between seeing the sensors (category 2) and not.
      const size_t i = rng() % disks.size();
      const auto f = world.filter(disks[i].fixture);
      world.setFilter(disks[i].fixture, f.maskBits == 0xFFFFFFFF ? filterOf(0x0001, 0xFFFFFFFD) : filterOf());
      ++filterChanges;
    } else if (roll < 30) {
      // A sensor stops seeing disks (category 1), or starts again.
      SensorSlot& s = sensors[rng() % sensors.size()];
      const auto f = world.filter(s.fixture);
      world.setFilter(s.fixture, f.maskBits == 0xFFFFFFFF ? filterOf(0x0002, 0xFFFFFFFE) : filterOf(0x0002));
      ++filterChanges;
    } else if (roll < 33) {
      // A sensor fixture is destroyed and rebuilt on its body.
      SensorSlot& s = sensors[rng() % sensors.size()];
      world.destroyFixture(s.fixture);
      s.fixture = addFixture(world, s.body, s.geometry, true, 0.0, filterOf(0x0002));
      ++sensorRebuilds;
    }
  }
  std::printf("[ pairing  ] %d begins, %d ends, %zu open at the end; %d destroys, %d filter changes, %d sensor rebuilds\n",
              begins, ends, open.size(), destroys, filterChanges, sensorRebuilds);
  EXPECT_GT(begins, 80);
  EXPECT_GT(destroys, 10);
  (void)box;
}

// ------------------------------------------------------------------------------------------------
// Brute force: random disks on straight paths through static sensors of every geometry, compared with
// overlaps() at the end of every step, at samples inside every step and just before and after every event.

struct BruteStats {
  long endChecks = 0, sampleChecks = 0, eventChecks = 0, skippedNearTouch = 0, events = 0, chatter = 0;
};

void bruteForceScene(rattle::StepMode mode, uint64_t seed, Vec2 gravity, BruteStats& stats) {
  SCOPED_TRACE("seed " + std::to_string(seed) + (gravity == Vec2{} ? "" : ", under gravity"));
  WorldDef def;
  def.mode = mode;
  def.gravity = gravity;
  World world(def);
  std::mt19937_64 rng(seed);
  auto uniform = [&rng](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53); };
  // Disks see sensors but not each other, and there are no walls: every path is straight.
  const rattle::Filter diskFilter = filterOf(0x0001, 0x0002);
  const rattle::Filter sensorFilter = filterOf(0x0002, 0x0001);
  struct Placed {
    FixtureId fixture;
    BodyId body;
    Geometry geometry;
  };
  std::vector<Placed> sensors;
  // 10 sensors of each geometry, some sharing a body.
  for (int i = 0; i < 50; ++i) {
    const int kind = i % 5;
    Placed s;
    const Vec2 at{uniform(2, 28), uniform(2, 28)};
    if (i % 3 == 0 && !sensors.empty()) {
      s.body = sensors.back().body;  // shares the last one's body, offset within it
      Geometry g = randomSensorGeometry(kind, rng);
      const Vec2 off{uniform(-3, 3), uniform(-3, 3)};
      std::visit(
          [&](auto& shape) {
            using T = std::decay_t<decltype(shape)>;
            if constexpr (std::is_same_v<T, Point>) shape.position += off;
            if constexpr (std::is_same_v<T, Circle>) shape.center += off;
            if constexpr (std::is_same_v<T, Segment>) shape.a += off, shape.b += off;
            if constexpr (std::is_same_v<T, Polyline> || std::is_same_v<T, Polygon>)
              for (Vec2& p : shape.points) p += off;
          },
          g);
      s.geometry = g;
    } else {
      s.body = world.createBody(bodyDef(BodyType::Static, at));
      s.geometry = randomSensorGeometry(kind, rng);
    }
    s.fixture = addFixture(world, s.body, s.geometry, true, 0, sensorFilter);
    s.geometry = world.geometry(s.fixture);  // as stored (counter-clockwise)
    sensors.push_back(s);
  }
  struct Mover {
    BodyId body;
    FixtureId fixture;
    double radius;
    Vec2 velocity;
  };
  std::vector<Mover> movers;
  for (int i = 0; i < 40; ++i) {
    Mover m;
    m.radius = uniform(0.1, 0.8);
    const double angle = uniform(0, 2 * std::numbers::pi), speed = uniform(0.5, 4);
    m.velocity = {speed * std::cos(angle), speed * std::sin(angle)};
    m.body = world.createBody(bodyDef(BodyType::Dynamic, {uniform(0, 30), uniform(0, 30)}, m.velocity));
    m.fixture = addFixture(world, m.body, Circle{{0, 0}, m.radius}, false, 0, diskFilter);
    movers.push_back(m);
  }

  const double dt = 0.05;
  const double nearTouch = 1e-9;
  const double eventEps = 1e-7;
  // state[(s, m)]: overlapping now, as the events say.
  std::vector<std::vector<char>> state(sensors.size(), std::vector<char>(movers.size(), 0));
  for (int step = 0; step < 120; ++step) {
    const double t0 = world.time();
    std::vector<Vec2> start(movers.size()), startVelocity(movers.size());
    for (size_t m = 0; m < movers.size(); ++m) {
      start[m] = world.position(movers[m].body);
      startVelocity[m] = world.velocity(movers[m].body);
    }
    world.step(dt);
    ASSERT_TRUE(world.contactEvents().empty());

    // Events per pair, in order.
    std::map<std::pair<size_t, size_t>, std::vector<std::pair<double, bool>>> perPair;
    std::map<uint32_t, size_t> sensorByIndex, moverByIndex;
    for (size_t s = 0; s < sensors.size(); ++s) sensorByIndex[sensors[s].fixture.index] = s;
    for (size_t m = 0; m < movers.size(); ++m) moverByIndex[movers[m].fixture.index] = m;
    double last = 0;
    for (const SensorEvent& e : world.sensorEvents()) {
      ASSERT_GE(e.time, last);
      ASSERT_LE(e.time, dt);
      last = e.time;
      ++stats.events;
      perPair[{sensorByIndex.at(e.sensor.index), moverByIndex.at(e.visitor.index)}].push_back({e.time, e.begin});
    }
    // The path within the step (a parabola under gravity), in the engine's own expression order.
    auto pathAt = [&](size_t m, double t) { return start[m] + startVelocity[m] * t + gravity * (0.5 * t * t); };
    for (const auto& [pair, list] : perPair) {
      const auto [s, m] = pair;
      const Placed& sensor = sensors[s];
      const Vec2 sp = world.position(sensor.body);
      bool cur = state[s][m];
      for (size_t k = 0; k < list.size(); ++k) {
        const auto [te, begin] = list[k];
        // Two changes of one pair within round-off of each other: a disk on a straight path does not
        // leave a sensor it has just entered (a tangent touch changes nothing at all).
        if (k > 0 && te - list[k - 1].first < 1e-9) {
          if (stats.chatter++ < 3)
            ADD_FAILURE() << "spurious " << (list[k - 1].second ? "begin" : "end") << "/" << (begin ? "begin" : "end")
                          << " pair " << te - list[k - 1].first << " s apart at step " << step << " + " << te
                          << ": sensor " << s << " (" << rattle::nameOf(rattle::typeOf(sensor.geometry)) << "), mover "
                          << m;
        }
        ASSERT_NE(begin, cur) << "a " << (begin ? "begin" : "end") << " while already " << (cur ? "in" : "out")
                              << ": step " << step << " sensor " << s << " mover " << m;
        cur = begin;
        // Just before and just after the event, along the straight path.
        const bool crowdedBefore = k > 0 && te - list[k - 1].first < 2 * eventEps;
        const bool crowdedAfter = k + 1 < list.size() && list[k + 1].first - te < 2 * eventEps;
        const Circle disk{{0, 0}, movers[m].radius};
        for (double side : {-1.0, 1.0}) {
          if ((side < 0 && crowdedBefore) || (side > 0 && crowdedAfter)) continue;
          const double t = te + side * eventEps;
          if (t0 + t < 0) continue;  // before the disk existed
          const Vec2 c = pathAt(m, t);
          const double gap = clearance(sensor.geometry, sp, c, movers[m].radius);
          if (std::fabs(gap) < nearTouch) {
            ++stats.skippedNearTouch;
            continue;
          }
          const bool expected = side < 0 ? !begin : begin;
          ++stats.eventChecks;
          EXPECT_EQ(rattle::overlaps(disk, c, sensor.geometry, sp), expected)
              << (begin ? "begin" : "end") << " at step " << step << " + " << te << " (absolute " << t0 + te
              << "), checked at offset " << side * eventEps << ": sensor " << s << " ("
              << rattle::nameOf(rattle::typeOf(sensor.geometry)) << "), mover " << m << ", clearance " << gap;
        }
      }
    }
    // Samples inside the step: the state the events imply against the geometry.
    for (size_t s = 0; s < sensors.size(); ++s) {
      const Vec2 sp = world.position(sensors[s].body);
      for (size_t m = 0; m < movers.size(); ++m) {
        const auto it = perPair.find({s, m});
        for (int k = 0; k < 8; ++k) {
          const double t = dt * (k + 0.5) / 8;
          bool implied = state[s][m];
          bool nearEvent = false;
          if (it != perPair.end()) {
            for (const auto& [te, begin] : it->second) {
              if (std::fabs(te - t) < 1e-9) nearEvent = true;
              if (te <= t) implied = begin;
            }
          }
          if (nearEvent) continue;
          const Vec2 c = pathAt(m, t);
          const double gap = clearance(sensors[s].geometry, sp, c, movers[m].radius);
          if (std::fabs(gap) < nearTouch) {
            ++stats.skippedNearTouch;
            continue;
          }
          ++stats.sampleChecks;
          EXPECT_EQ(gap < 0, implied) << "inside step " << step << " at +" << t << ": sensor " << s << " ("
                                      << rattle::nameOf(rattle::typeOf(sensors[s].geometry)) << "), mover " << m
                                      << ", clearance " << gap;
        }
        if (it != perPair.end()) state[s][m] = it->second.back().second;
      }
    }
    // End of the step: sensorOverlaps against overlaps() where the bodies are.
    for (size_t s = 0; s < sensors.size(); ++s) {
      const auto listed = world.sensorOverlaps(sensors[s].fixture);
      const Vec2 sp = world.position(sensors[s].body);
      for (size_t m = 0; m < movers.size(); ++m) {
        const Vec2 c = world.position(movers[m].body);
        ASSERT_EQ(c, pathAt(m, dt));  // nothing but gravity changed the path
        const bool inList = std::find(listed.begin(), listed.end(), movers[m].fixture) != listed.end();
        EXPECT_EQ(inList, static_cast<bool>(state[s][m]));
        const double gap = clearance(sensors[s].geometry, sp, c, movers[m].radius);
        if (std::fabs(gap) < nearTouch) {
          ++stats.skippedNearTouch;
          continue;
        }
        ++stats.endChecks;
        const bool geometric = rattle::overlaps(Circle{{0, 0}, movers[m].radius}, c, sensors[s].geometry, sp);
        EXPECT_EQ(geometric, gap < 0);
        EXPECT_EQ(inList, geometric) << "end of step " << step << ": sensor " << s << " ("
                                     << rattle::nameOf(rattle::typeOf(sensors[s].geometry)) << "), mover " << m
                                     << ", clearance " << gap;
      }
    }
  }
}

TEST_P(SensorBruteForce, RandomStraightPathsAgreeWithGeometry) {
  BruteStats stats;
  for (uint64_t seed : {1u, 2u, 3u}) bruteForceScene(GetParam(), seed, Vec2{}, stats);
  std::printf("[ brute    ] %ld events (%ld in spurious same-instant pairs), %ld event-side checks, %ld in-step "
              "samples, %ld end-of-step checks, %ld skipped within 1e-9 of touching\n",
              stats.events, stats.chatter, stats.eventChecks, stats.sampleChecks, stats.endChecks,
              stats.skippedNearTouch);
  EXPECT_EQ(stats.chatter, 0);
  EXPECT_GT(stats.events, 200);
}

// The same under gravity: parabolic paths, whose corner roots are quartics.
TEST_P(SensorBruteForce, RandomParabolicPathsAgreeWithGeometry) {
  BruteStats stats;
  for (uint64_t seed : {4u, 5u}) bruteForceScene(GetParam(), seed, Vec2{0.3, -1.5}, stats);
  std::printf("[ brute    ] %ld events (%ld in spurious same-instant pairs), %ld event-side checks, %ld in-step "
              "samples, %ld end-of-step checks, %ld skipped within 1e-9 of touching\n",
              stats.events, stats.chatter, stats.eventChecks, stats.sampleChecks, stats.endChecks,
              stats.skippedNearTouch);
  EXPECT_EQ(stats.chatter, 0);
  EXPECT_GT(stats.events, 200);
}

INSTANTIATE_TEST_SUITE_P(, SensorDoorway, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorRoom, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorSight, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorRules, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorKinematic, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorBounce, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorResting, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorTeleport, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorGravity, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorOverlaps, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorPairing, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());
INSTANTIATE_TEST_SUITE_P(, SensorBruteForce, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());

}  // namespace
