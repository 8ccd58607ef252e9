// A body's fixtures changed between hybrid steps are what the next step collides with.
//
// The world keeps, for a body whose fixtures are one centred circle, that circle's radius, fixture and
// group apart from the fixtures (detail::WorldState::diskShapes), so that the hybrid step's first pass
// need not read them every step; every change World allows to a body's fixtures (a filter, a fixture
// created or destroyed, a body destroyed and its slot reused) must reach the next step. Each case steps once before
// the change, so the shape is known, and checks the next steps against the closed form of a head-on
// collision of two equal disks: they meet when the gap between their centres has closed to the sum of
// the radii, and swap velocities (restitution 1).
#include <gtest/gtest.h>

#include <cmath>
#include <optional>

#include "world_test_support.h"

namespace {

using rattle_test::bodyDef;
using rattle_test::filterOf;
using namespace rattle;

FixtureDef diskDef(double radius, Filter filter = {}, bool sensor = false) {
  FixtureDef d;
  d.geometry = Circle{{0, 0}, radius};
  d.restitution = 1;
  d.filter = filter;
  d.sensor = sensor;
  return d;
}

struct Pair {
  World world;
  BodyId left, right;
  FixtureId leftDisk, rightDisk;
};

// Two disks of the given radius on the x axis, centres 10 apart, closing at 2 units per second (1 each),
// after one step of 0.25 s (in which the hybrid step learns their shapes): centres at -4.75 and 4.75.
void makeSteppedPair(Pair& p, double radius, Filter filter = {}) {
  p.left = p.world.createBody(bodyDef(BodyType::Dynamic, {-5, 0}, {1, 0}));
  p.right = p.world.createBody(bodyDef(BodyType::Dynamic, {5, 0}, {-1, 0}));
  p.leftDisk = p.world.createFixture(p.left, diskDef(radius, filter));
  p.rightDisk = p.world.createFixture(p.right, diskDef(radius, filter));
  p.world.step(0.25);
}

// The world time of the first contact in the steps up to `until` (steps of 0.25 s), if any.
std::optional<double> firstContact(World& world, double until) {
  while (world.time() < until - 1e-12) {
    const double start = world.time();
    world.step(0.25);
    if (!world.contactEvents().empty()) return start + world.contactEvents()[0].time;
  }
  return std::nullopt;
}

void expectFirstContactAt(World& world, double until, double expected) {
  const auto met = firstContact(world, until);
  ASSERT_TRUE(met.has_value());
  EXPECT_NEAR(*met, expected, 1e-12);
}

TEST(HybridFixtureChanges, AFilterChangedAfterAStepDecidesWhetherTheDisksMeet) {
  // Same negative group: they pass through each other; a group of 0 set after the first step lets them
  // meet when 10 - 2 * 0.5 = 9 units have closed, at t = 4.5.
  Pair p;
  makeSteppedPair(p, 0.5, filterOf(0x0001, 0xFFFFFFFF, -1));
  p.world.setFilter(p.leftDisk, filterOf());
  expectFirstContactAt(p.world, 6, 4.5);
  EXPECT_NEAR(p.world.velocity(p.left).x, -1, 1e-12);
  EXPECT_NEAR(p.world.velocity(p.right).x, 1, 1e-12);

  // And the other way: put into the same negative group after a step, they pass through.
  Pair q;
  makeSteppedPair(q, 0.5);
  q.world.setFilter(q.leftDisk, filterOf(0x0001, 0xFFFFFFFF, -3));
  q.world.setFilter(q.rightDisk, filterOf(0x0001, 0xFFFFFFFF, -3));
  EXPECT_FALSE(firstContact(q.world, 6).has_value());
  EXPECT_NEAR(q.world.position(q.left).x, 1, 1e-12);  // -5 + 6 s at 1 unit/s: through and past
}

TEST(HybridFixtureChanges, AFixtureReplacedAfterAStepCollidesWithItsOwnRadius) {
  // The left disk's radius 0.5 circle replaced by one of radius 2: contact when 10 - 2.5 = 7.5 units
  // have closed, at t = 3.75 (3.75 s after the start; the step before the change moved both).
  Pair p;
  makeSteppedPair(p, 0.5);
  p.world.destroyFixture(p.leftDisk);
  p.world.createFixture(p.left, diskDef(2));
  expectFirstContactAt(p.world, 6, 3.75);
}

TEST(HybridFixtureChanges, AFixtureDestroyedAfterAStepIsGone) {
  // The left body's only fixture destroyed after a step: nothing is left of it to meet the right disk.
  // A static disk made next takes the freed fixture's slot, at x = -2 in the right disk's way: they meet
  // when the right disk's centre, at 4.75 after the first step, reaches -1, at t = 6.
  Pair p;
  makeSteppedPair(p, 0.5);
  p.world.destroyFixture(p.leftDisk);
  const BodyId post = p.world.createBody(bodyDef(BodyType::Static, {-2, 0}));
  const FixtureId postDisk = p.world.createFixture(post, diskDef(0.5));
  EXPECT_EQ(postDisk.index, p.leftDisk.index);
  expectFirstContactAt(p.world, 7, 6);
  EXPECT_NEAR(p.world.velocity(p.right).x, 1, 1e-12);
  EXPECT_NEAR(p.world.velocity(p.left).x, 1, 1e-12);  // it passed through where the right disk was
}

TEST(HybridFixtureChanges, ASecondFixtureAddedAfterAStepCollides) {
  // A larger circle (radius 1.5) added to the left body: it meets the right disk when 10 - 2 = 8 units
  // have closed, at t = 4. (No sensor here: a world with sensors sets every box again after the step.)
  Pair p;
  makeSteppedPair(p, 0.5);
  p.world.createFixture(p.left, diskDef(1.5));
  expectFirstContactAt(p.world, 6, 4);
}

TEST(HybridFixtureChanges, ASensorAddedAfterAStepDoesNotCollide) {
  // A sensor of radius 3 added to the right body: the disks still meet at t = 4.5, and the sensor
  // reports the left disk when it comes within 3.5 (t = 3.25).
  Pair p;
  makeSteppedPair(p, 0.5);
  const FixtureId sight = p.world.createFixture(p.right, diskDef(3, {}, true));
  std::optional<double> sensed, met;
  while (p.world.time() < 6 - 1e-12 && !met) {
    const double start = p.world.time();
    p.world.step(0.25);
    for (const SensorEvent& e : p.world.sensorEvents()) {
      if (!sensed && e.begin && e.sensor.index == sight.index) sensed = start + e.time;
    }
    if (!p.world.contactEvents().empty()) met = start + p.world.contactEvents()[0].time;
  }
  ASSERT_TRUE(sensed.has_value());
  EXPECT_NEAR(*sensed, 3.25, 1e-12);
  ASSERT_TRUE(met.has_value());
  EXPECT_NEAR(*met, 4.5, 1e-12);
}

TEST(HybridFixtureChanges, ABodyCreatedInAFreedSlotHasItsOwnShape) {
  // The right body destroyed after a step and a new one made (in its slot) with a radius of 1 and a
  // group that keeps it from the left disk; then a third body, in no group, with a radius of 2.5.
  Pair p;
  makeSteppedPair(p, 0.5);
  const double x = p.world.position(p.right).x;
  p.world.destroyBody(p.right);
  const BodyId ghost = p.world.createBody(bodyDef(BodyType::Dynamic, {x, 0}, {-1, 0}));
  EXPECT_EQ(ghost.index, p.right.index);  // the freed slot, which the step had learnt the shape of
  FixtureDef def = diskDef(1, filterOf(0x0001, 0xFFFFFFFF, -2));
  p.world.createFixture(ghost, def);
  p.world.setFilter(p.leftDisk, filterOf(0x0001, 0xFFFFFFFF, -2));
  p.world.step(0.25);
  p.world.destroyBody(ghost);
  const BodyId wide = p.world.createBody(bodyDef(BodyType::Dynamic, {x - 0.25, 0}, {-1, 0}));
  p.world.createFixture(wide, diskDef(2.5));
  p.world.setFilter(p.leftDisk, filterOf());
  // At t = 0.5 the centres are 9 apart; they meet when 9 - 3 = 6 more units have closed, at t = 3.5.
  expectFirstContactAt(p.world, 6, 3.5);
}

}  // namespace
