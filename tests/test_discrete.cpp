// Discrete mode (StepMode::Discrete) tests: step and check, the cheap baseline. A single collision
// matches the closed form; a large gas stays in its box with overlaps pushed apart; and the mode's known
// failures, which the hybrid mode does not have, are asserted as its documented behaviour: tunnelling
// through thin walls, at most one collision per pair per step, sensors that see only where a step ends.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "rattle/rattle.h"
#include "world_test_support.h"

namespace {

using namespace rattle_test;
using rattle::Circle;
using rattle::ContactEvent;
using rattle::Segment;
using rattle::SensorEvent;
using rattle::StepMode;
using rattle::WorldDef;

using LD = long double;

WorldDef modeDef(StepMode mode) {
  WorldDef d;
  d.mode = mode;
  return d;
}

FixtureId addWall(World& world, BodyId body, Vec2 a, Vec2 b, double restitution) {
  FixtureDef fd;
  fd.geometry = Segment{a, b};
  fd.restitution = restitution;
  return world.createFixture(body, fd);
}

// ------------------------------------------------------------------------------------------------
// One collision against the closed form.

void checkHeadOn(double e) {
  SCOPED_TRACE("restitution " + std::to_string(e));
  World world(modeDef(StepMode::Discrete));
  // Radii 0.5 and 0.3, densities 1 and 2; they first touch at t = 0.3 (gap 1.2 closing at 4), inside the
  // third step of 0.125, which ends with them overlapping by 4 * 0.075 = 0.3.
  const Disk d1 = addDisk(world, DiskSpec{{-1, 0}, {3, 0}, 0.5, 1.0, e});
  const Disk d2 = addDisk(world, DiskSpec{{1, 0}, {-1, 0}, 0.3, 2.0, 0.0});
  const double dt = 0.125;
  world.step(dt);
  world.step(dt);
  EXPECT_TRUE(world.contactEvents().empty());
  const Vec2 p1 = world.position(d1.body), p2 = world.position(d2.body);
  world.step(dt);

  const LD m1 = std::numbers::pi_v<LD> * 0.25L, m2 = 2 * std::numbers::pi_v<LD> * 0.09L;
  // Before the response: both moved a whole step.
  const LD x1 = LD(p1.x) + 3 * 0.125L, x2 = LD(p2.x) - 0.125L;
  const LD depth = 0.8L - (x2 - x1);
  ASSERT_NEAR(static_cast<double>(depth), 0.3, 1e-12);
  // Newton's law along the normal (+x from 1 to 2): relative normal speed u = v1 - v2 = 4 becomes -e u.
  const LD u = 4, j = (1 + e) * u / (1 / m1 + 1 / m2);
  const LD v1 = 3 - j / m1, v2 = -1 + j / m2;
  EXPECT_NEAR(world.velocity(d1.body).x, static_cast<double>(v1), 1e-12);
  EXPECT_NEAR(world.velocity(d2.body).x, static_cast<double>(v2), 1e-12);
  EXPECT_EQ(world.velocity(d1.body).y, 0.0);
  EXPECT_EQ(world.velocity(d2.body).y, 0.0);
  // Momentum always; energy with e = 1.
  const LD pBefore = m1 * 3 + m2 * -1;
  const LD pAfter = m1 * world.velocity(d1.body).x + m2 * world.velocity(d2.body).x;
  EXPECT_NEAR(static_cast<double>(pAfter - pBefore), 0.0, 1e-12);
  const LD eBefore = m1 * 9 / 2 + m2 * 1 / 2;
  const LD eAfter = m1 * v1 * v1 / 2 + m2 * v2 * v2 / 2;
  const LD measured = LD(0.5) * m1 * world.velocity(d1.body).x * world.velocity(d1.body).x +
                      LD(0.5) * m2 * world.velocity(d2.body).x * world.velocity(d2.body).x;
  EXPECT_NEAR(static_cast<double>(measured - eAfter), 0.0, 1e-12);
  if (e == 1.0) {
    EXPECT_NEAR(static_cast<double>(eAfter - eBefore), 0.0, 1e-12);
  }
  // Pushed apart, in inverse proportion to the masses.
  const LD share1 = (1 / m1) / (1 / m1 + 1 / m2);
  EXPECT_NEAR(world.position(d1.body).x, static_cast<double>(x1 - depth * share1), 1e-12);
  EXPECT_NEAR(world.position(d2.body).x, static_cast<double>(x2 + depth * (1 - share1)), 1e-12);
  EXPECT_NEAR(world.position(d2.body).x - world.position(d1.body).x, 0.8, 1e-12);
  // Reported once, at the end of the step.
  const auto events = world.contactEvents();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].time, dt);
  EXPECT_NEAR(events[0].impulse, static_cast<double>(j), 1e-12);
  EXPECT_EQ(events[0].fixtureA, d1.fixture);
  EXPECT_EQ(events[0].fixtureB, d2.fixture);
  EXPECT_NEAR(events[0].normal.x, 1.0, 1e-15);  // from A toward B
  EXPECT_EQ(events[0].normal.y, 0.0);
  EXPECT_EQ(events[0].point.y, 0.0);
  // With e > 0 they separate: never again. (e = 0: see PerfectlyInelasticPairIsNotHitAgainByRoundOff.)
  if (e > 0) {
    for (int i = 0; i < 10; ++i) {
      world.step(dt);
      EXPECT_TRUE(world.contactEvents().empty()) << "step " << i + 4;
    }
  }
}

TEST(DiscreteCollision, HeadOnMatchesClosedForm) {
  checkHeadOn(1.0);
  checkHeadOn(0.5);
  checkHeadOn(0.0);
}

// ContactEvent::point is "the world position of the contact at `time`"; in discrete mode `time` is the
// end of the step, where the two are pushed apart and touch at one point. ENGINE BUG (reported): the
// point is taken on the other disk's surface before the push-apart (x = 0.325 here, where d2 was while
// overlapping), 0.174 away from where they touch after it.
TEST(DiscreteCollision, ContactPointIsWhereTheDisksTouchAfterPushApart) {
  World world(modeDef(StepMode::Discrete));
  const Disk d1 = addDisk(world, DiskSpec{{-1, 0}, {3, 0}, 0.5, 1.0, 1.0});
  const Disk d2 = addDisk(world, DiskSpec{{1, 0}, {-1, 0}, 0.3, 2.0, 0.0});
  for (int i = 0; i < 3; ++i) world.step(0.125);
  ASSERT_EQ(world.contactEvents().size(), 1u);
  const Vec2 point = world.contactEvents()[0].point;
  // After the push-apart d1's right edge and d2's left edge coincide.
  EXPECT_NEAR(world.position(d1.body).x + 0.5, world.position(d2.body).x - 0.3, 1e-12);
  EXPECT_NEAR(point.x, world.position(d2.body).x - 0.3, 1e-12) << "point on d2 after the push-apart";
  EXPECT_NEAR(point.x, world.position(d1.body).x + 0.5, 1e-12) << "point on d1 after the push-apart";
}

// With restitution 0 the pair leaves with equal normal speeds, up to round-off. ENGINE BUG (reported):
// discrete mode has none of the hybrid mode's round-off guards, so the 4e-16 approach left over makes the
// next step report a second collision with an impulse of ~1e-16. (Hybrid: resolve() removes any
// leftover approach after a restitution-0 response, and approaches below its tolerance are no event.)
TEST(DiscreteCollision, PerfectlyInelasticPairIsNotHitAgainByRoundOff) {
  World world(modeDef(StepMode::Discrete));
  const Disk d1 = addDisk(world, DiskSpec{{-1, 0}, {3, 0}, 0.5, 1.0, 0.0});
  const Disk d2 = addDisk(world, DiskSpec{{1, 0}, {-1, 0}, 0.3, 2.0, 0.0});
  for (int i = 0; i < 3; ++i) world.step(0.125);
  ASSERT_EQ(world.contactEvents().size(), 1u);
  EXPECT_NEAR(world.velocity(d1.body).x, world.velocity(d2.body).x, 1e-15);
  EXPECT_GE(world.velocity(d2.body).x - world.velocity(d1.body).x, 0.0) << "left approaching after e = 0";
  for (int i = 0; i < 10; ++i) {
    world.step(0.125);
    for (const ContactEvent& c : world.contactEvents())
      ADD_FAILURE() << "step " << i + 4 << ": a second collision, impulse " << c.impulse;
  }
}

// ------------------------------------------------------------------------------------------------
// Known failures, asserted as the discrete mode's documented behaviour.

struct WallRun {
  int contacts = 0;
  double finalX = 0;
  Vec2 finalVelocity;
};

WallRun fastDiskAgainstWall(StepMode mode) {
  World world(modeDef(mode));
  const BodyId wallBody = world.createBody(bodyDef(BodyType::Static));
  addWall(world, wallBody, {0, -1}, {0, 1}, 1.0);
  // Radius 0.1 at x = -1, 30 units per second, steps of 0.1: 3 units per step, far more than its
  // diameter: the first step ends at x = 2, clear of the wall.
  const Disk d = addDisk(world, DiskSpec{{-1, 0}, {30, 0}, 0.1, 1, 1.0});
  WallRun run;
  for (int i = 0; i < 3; ++i) {
    world.step(0.1);
    run.contacts += static_cast<int>(world.contactEvents().size());
  }
  run.finalX = world.position(d.body).x;
  run.finalVelocity = world.velocity(d.body);
  return run;
}

// Resting and the collapse guard are rules of the hybrid and predictive modes (types.h, README "Gravity
// and resting"): a discrete step pushes pairs apart and reflects them with their restitution as it is.
// A disk at rest on a floor never sleeps, and collapseTime changes nothing: a disk bouncing between two
// walls 2 apart (restitution 0.5, collapseTime 1 s, far longer than its flights) ends every step where
// and as fast as without it, its speed halving at each wall, 10 -> 5 -> 2.5.
TEST(DiscreteRules, NoRestingAndNoCollapseGuard) {
  {
    WorldDef def = modeDef(StepMode::Discrete);
    def.gravity = {0, -10};
    World world(def);
    addWall(world, world.createBody(bodyDef(BodyType::Static)), {-5, 0}, {5, 0}, 0.0);
    const Disk d = addDisk(world, DiskSpec{{0, 0.5}, {0, 0}, 0.5, 1, 0});
    for (int step = 0; step < 300; ++step) {
      world.step(1.0 / 60);
      ASSERT_FALSE(world.isAsleep(d.body)) << "step " << step;
    }
    EXPECT_EQ(world.stats().sleeping, 0);
  }
  std::vector<Vec2> velocities[2];
  for (int guard = 0; guard < 2; ++guard) {
    WorldDef def = modeDef(StepMode::Discrete);
    def.collapseTime = guard ? 1.0 : 0.0;
    World world(def);
    const BodyId walls = world.createBody(bodyDef(BodyType::Static));
    addWall(world, walls, {-1, -5}, {-1, 5}, 0.5);
    addWall(world, walls, {1, -5}, {1, 5}, 0.5);
    const Disk d = addDisk(world, DiskSpec{{0, 0}, {10, 0}, 0.1, 1, 0.5});
    for (int step = 0; step < 60; ++step) {
      world.step(0.01);
      velocities[guard].push_back(world.velocity(d.body));
    }
  }
  EXPECT_EQ(velocities[0], velocities[1]);
  std::vector<double> speeds;  // each speed the disk had, in turn
  for (Vec2 v : velocities[1])
    if (speeds.empty() || std::fabs(v.x) != speeds.back()) speeds.push_back(std::fabs(v.x));
  EXPECT_EQ(speeds, (std::vector<double>{10, 5, 2.5}));
}

TEST(DiscreteKnownFailures, FastDiskTunnelsThroughThinWall) {
  // Discrete: it never overlaps the wall at the end of a step, so it passes through. (Hybrid: the exact
  // time of impact inside the step stops it.)
  const WallRun discrete = fastDiskAgainstWall(StepMode::Discrete);
  EXPECT_EQ(discrete.contacts, 0);
  EXPECT_GT(discrete.finalX, 0.1);
  EXPECT_EQ(discrete.finalVelocity, Vec2(30, 0));
  EXPECT_NEAR(discrete.finalX, -1 + 30 * 0.3, 1e-12);

  const WallRun hybrid = fastDiskAgainstWall(StepMode::Hybrid);
  EXPECT_EQ(hybrid.contacts, 1);
  EXPECT_LT(hybrid.finalX, -0.1);
  EXPECT_NEAR(hybrid.finalVelocity.x, -30, 1e-12);
  // Bounced at x = -0.1 (t = 0.03): ends at -0.1 - 30 * 0.27.
  EXPECT_NEAR(hybrid.finalX, -0.1 - 30 * 0.27, 1e-12);
}

struct RattleRun {
  int contacts = 0;
  int maxPerWallPerStep = 0;
  double finalX = 0;
};

// A disk of radius 0.5 between walls x = 0 and x = 1.5 (three radii apart), starting in the middle at
// `speed` along x, restitution 1.
RattleRun rattle(StepMode mode, double speed, double dt, int steps) {
  World world(modeDef(mode));
  const BodyId wallBody = world.createBody(bodyDef(BodyType::Static));
  const FixtureId left = addWall(world, wallBody, {0, -10}, {0, 10}, 1.0);
  const FixtureId right = addWall(world, wallBody, {1.5, -10}, {1.5, 10}, 1.0);
  const Disk d = addDisk(world, DiskSpec{{0.75, 0}, {speed, 0}, 0.5, 1, 1.0});
  RattleRun run;
  for (int i = 0; i < steps; ++i) {
    world.step(dt);
    int perWall[2] = {0, 0};
    for (const ContactEvent& c : world.contactEvents()) {
      ++run.contacts;
      if (c.fixtureA == left || c.fixtureB == left) ++perWall[0];
      if (c.fixtureA == right || c.fixtureB == right) ++perWall[1];
    }
    run.maxPerWallPerStep = std::max({run.maxPerWallPerStep, perWall[0], perWall[1]});
  }
  run.finalX = world.position(d.body).x;
  return run;
}

TEST(DiscreteKnownFailures, RattlingBetweenCloseWallsGetsOneCollisionPerWallPerStep) {
  // 0.6 per step against a free path of 0.5 between bounces: hybrid resolves every bounce (the first
  // after 0.25, then one every 0.5: 120 in 60 units of travel); discrete responds at most once per pair per
  // step and, pushing the disk back to the wall instead of reflecting its path, gets one bounce per step.
  const RattleRun hybrid = rattle(StepMode::Hybrid, 60, 0.01, 100);
  const RattleRun discrete = rattle(StepMode::Discrete, 60, 0.01, 100);
  std::printf("[ rattle   ] 0.6 per step: hybrid %d collisions (max %d per wall per step), discrete %d (max %d)\n",
              hybrid.contacts, hybrid.maxPerWallPerStep, discrete.contacts, discrete.maxPerWallPerStep);
  EXPECT_EQ(hybrid.contacts, 120);
  EXPECT_LE(discrete.maxPerWallPerStep, 1);
  EXPECT_LE(discrete.contacts, 100);
  EXPECT_LT(discrete.contacts, hybrid.contacts);
  EXPECT_GE(hybrid.finalX, 0.5 - 1e-9);
  EXPECT_LE(hybrid.finalX, 1.0 + 1e-9);
  EXPECT_GE(discrete.finalX, 0.5 - 1e-9);
  EXPECT_LE(discrete.finalX, 1.0 + 1e-9);

  // 5 per step, ten free paths: hybrid resolves ten bounces a step (200 in 100 units of travel); discrete
  // never even sees the walls (the first step ends 4.25 past the right one) and the disk escapes.
  const RattleRun hybridFast = rattle(StepMode::Hybrid, 500, 0.01, 20);
  const RattleRun discreteFast = rattle(StepMode::Discrete, 500, 0.01, 20);
  std::printf("[ rattle   ] 5 per step: hybrid %d collisions (max %d per wall per step), discrete %d (max %d)\n",
              hybridFast.contacts, hybridFast.maxPerWallPerStep, discreteFast.contacts,
              discreteFast.maxPerWallPerStep);
  EXPECT_EQ(hybridFast.contacts, 200);
  EXPECT_EQ(hybridFast.maxPerWallPerStep, 5);
  EXPECT_GE(hybridFast.finalX, 0.5 - 1e-9);
  EXPECT_LE(hybridFast.finalX, 1.0 + 1e-9);
  EXPECT_LE(discreteFast.maxPerWallPerStep, 1);
  EXPECT_LT(discreteFast.contacts, hybridFast.contacts);
  EXPECT_GT(discreteFast.finalX, 1.5);  // escaped through the right wall
}

// ------------------------------------------------------------------------------------------------
// A large gas.

/// Largest overlap r_i + r_j - |c_i - c_j| over all pairs of disks (negative: none), by a sweep along x.
double maxOverlap(const World& world, const std::vector<Disk>& disks) {
  struct Item {
    Vec2 p;
    double r;
  };
  std::vector<Item> items;
  double rMax = 0;
  for (const Disk& d : disks) {
    items.push_back({world.position(d.body), d.radius});
    rMax = std::max(rMax, d.radius);
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.p.x < b.p.x; });
  double worst = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < items.size(); ++i) {
    for (size_t j = i + 1; j < items.size() && items[j].p.x - items[i].p.x <= items[i].r + rMax; ++j) {
      worst = std::max(worst, items[i].r + items[j].r - rattle::length(items[i].p - items[j].p));
    }
  }
  return worst;
}

TEST(DiscreteGas, ThousandDisksStayInTheBoxWithOverlapsPushedApart) {
  World world(modeDef(StepMode::Discrete));
  const ClosedBox box = makeClosedBox(world, 0, 0, 45, 45, 1.0);
  RandomDiskOptions opt;
  opt.count = 1000;
  opt.seed = 2024;
  opt.xmin = 0, opt.ymin = 0, opt.xmax = 45, opt.ymax = 45;
  opt.minRadius = 0.3, opt.maxRadius = 0.6;
  opt.minSpeed = 0, opt.maxSpeed = 2;
  opt.minRestitution = 1, opt.maxRestitution = 1;
  const std::vector<Disk> disks = addDisks(world, randomDisks(opt));
  const long double e0 = kineticEnergy(world, disks);

  const double dt = 0.005;
  const int steps = 400;
  double worstOverlap = -1, worstWall = -1, fastest = 0;
  long contacts = 0;
  for (int s = 0; s < steps; ++s) {
    world.step(dt);
    contacts += static_cast<long>(world.contactEvents().size());
    for (const ContactEvent& c : world.contactEvents()) ASSERT_EQ(c.time, dt);
    for (const Disk& d : disks) {
      const Vec2 p = world.position(d.body);
      ASSERT_TRUE(centreInside(p, box)) << "disk outside the box after step " << s;
      fastest = std::max(fastest, rattle::length(world.velocity(d.body)));
    }
    worstOverlap = std::max(worstOverlap, maxOverlap(world, disks));
    worstWall = std::max(worstWall, maxRelativeWallPenetration(world, disks, box));
    // Bound: in one step a pair closes by at most 2 * fastest * dt; the push-apart removes each pair's
    // overlap, and what is left comes from chains (a disk pushed out of one pair into another handled
    // earlier in the same pass), a fraction of one step's approach. So the overlap left after a step
    // stays below 2 * fastest * dt (measured with this seed: 0.0019 against 0.045).
    ASSERT_LT(worstOverlap, 2 * fastest * dt) << "step " << s;
  }
  ASSERT_TRUE(allFinite(world, disks));
  const long double e1 = kineticEnergy(world, disks);
  const double drift = static_cast<double>((e1 - e0) / e0);
  std::printf("[ gas      ] 1000 disks, %d steps of %g: %ld contacts, worst overlap left %.3g (bound 2 vmax dt = %.3g), "
              "worst wall penetration %.3g r, relative energy drift %.3g\n",
              steps, dt, contacts, worstOverlap, 2 * fastest * dt, worstWall, drift);
  EXPECT_GT(contacts, 100);
  // Kinetic energy: push-apart moves positions only, and every response is an elastic impulse along the
  // normal with e = 1, which keeps the pair's kinetic energy in exact arithmetic. What drifts is round-off
  // (measured ~1e-17 relative); 1e-10 leaves ample room while still catching any non-elastic response.
  EXPECT_LT(std::fabs(drift), 1e-10);
  // Walls: a disk is pushed back out of a wall it overlaps, and a later disk-disk push can move it in by
  // at most a step's approach: well under a radius.
  EXPECT_LT(worstWall, 0.1);
}

// ------------------------------------------------------------------------------------------------
// Sensors see only where the steps end.

std::vector<SensorEvent> stepEvents(World& world, double dt) {
  world.step(dt);
  return {world.sensorEvents().begin(), world.sensorEvents().end()};
}

TEST(DiscreteSensors, OnlyEndOfStepOverlapsAreSeen) {
  for (StepMode mode : {StepMode::Discrete, StepMode::Hybrid}) {
    SCOPED_TRACE(mode == StepMode::Discrete ? "discrete" : "hybrid");
    World world(modeDef(mode));
    // A thin sensor: the strip 0 <= x <= 0.05.
    const BodyId holder = world.createBody(bodyDef(BodyType::Static));
    FixtureDef fd;
    fd.geometry = rattle::Polygon{{{0, -1}, {0.05, -1}, {0.05, 1}, {0, 1}}};
    fd.sensor = true;
    const FixtureId strip = world.createFixture(holder, fd);
    // Fast (y = 0.5): 1 per step from x = -0.5, crossing the strip inside the first step (0.4 to 0.65).
    const Disk fast = addDisk(world, DiskSpec{{-0.5, 0.5}, {10, 0}, 0.1, 1, 0});
    // Slow (y = -0.5): 0.1 per step from x = -0.555; its step ends are -0.455, ..., -0.055 (step 5,
    // overlapping: -0.055 + 0.1 > 0), 0.045, 0.145 (step 7, still overlapping: 0.145 - 0.1 < 0.05) and
    // 0.245 (step 8, clear). The true crossing is t in [0.455, 0.705].
    const Disk slow = addDisk(world, DiskSpec{{-0.555, -0.5}, {1, 0}, 0.1, 1, 0});
    const double dt = 0.1;
    std::vector<std::pair<int, SensorEvent>> all;
    for (int step = 1; step <= 12; ++step)
      for (const SensorEvent& e : stepEvents(world, dt)) all.push_back({step, e});

    std::vector<std::pair<int, SensorEvent>> ofFast, ofSlow;
    for (const auto& [step, e] : all) {
      EXPECT_EQ(e.sensor, strip);
      if (e.visitor == fast.fixture) {
        ofFast.push_back({step, e});
      } else {
        EXPECT_EQ(e.visitor, slow.fixture);
        ofSlow.push_back({step, e});
      }
    }
    if (mode == StepMode::Discrete) {
      // Documented miss: the fast disk never ends a step on the strip, so no events at all. (Hybrid sees
      // it: below.)
      EXPECT_TRUE(ofFast.empty());
      // The slow one: begin and end at the ends of steps 5 and 8.
      ASSERT_EQ(ofSlow.size(), 2u);
      EXPECT_TRUE(ofSlow[0].second.begin);
      EXPECT_EQ(ofSlow[0].first, 5);
      EXPECT_EQ(ofSlow[0].second.time, dt);
      EXPECT_FALSE(ofSlow[1].second.begin);
      EXPECT_EQ(ofSlow[1].first, 8);
      EXPECT_EQ(ofSlow[1].second.time, dt);
    } else {
      ASSERT_EQ(ofFast.size(), 2u);
      EXPECT_EQ(ofFast[0].first, 1);
      EXPECT_EQ(ofFast[1].first, 1);
      EXPECT_NEAR(ofFast[0].second.time, 0.04, 1e-12);
      EXPECT_NEAR(ofFast[1].second.time, 0.065, 1e-12);
      ASSERT_EQ(ofSlow.size(), 2u);
      EXPECT_EQ(ofSlow[0].first, 5);
      EXPECT_NEAR(ofSlow[0].second.time, 0.055, 1e-12);
      EXPECT_EQ(ofSlow[1].first, 8);
      EXPECT_NEAR(ofSlow[1].second.time, 0.005, 1e-12);
    }
    EXPECT_TRUE(world.sensorOverlaps(strip).empty());
    EXPECT_EQ(world.velocity(fast.body), Vec2(10, 0));
  }
}

TEST(DiscreteSensors, DestroyEndsAtTimeZeroOfTheNextStep) {
  World world(modeDef(StepMode::Discrete));
  const BodyId holder = world.createBody(bodyDef(BodyType::Static));
  FixtureDef fd;
  fd.geometry = Circle{{0, 0}, 2.0};
  fd.sensor = true;
  const FixtureId zone = world.createFixture(holder, fd);
  const Disk d = addDisk(world, DiskSpec{{0.5, 0}, {0.1, 0}, 0.2, 1, 0});
  auto ev = stepEvents(world, 0.1);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].begin);
  EXPECT_EQ(ev[0].time, 0.0);  // created inside: at time 0, as in every mode (sensorEvents())
  EXPECT_EQ(world.sensorOverlaps(zone), std::vector<FixtureId>{d.fixture});
  world.destroyBody(d.body);
  EXPECT_TRUE(world.sensorOverlaps(zone).empty());
  ev = stepEvents(world, 0.1);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_FALSE(ev[0].begin);
  EXPECT_EQ(ev[0].time, 0.0);
  EXPECT_EQ(ev[0].visitor, d.fixture);
}

// sensorEvents(): a body created inside a sensor begins at time 0 of the next step, in every mode. The
// discrete step sees overlaps where the step ends, and one that held where it began too begins at 0; one
// that began within the step is reported at its end. The events are in time order (a begin at 0 of a
// later fixture before one at dt of an earlier), as contact events are.
TEST(DiscreteSensors, ABeginThatHeldWhereTheStepBeganIsAtTimeZero) {
  World world(modeDef(StepMode::Discrete));
  const BodyId holder = world.createBody(bodyDef(BodyType::Static, {5, 0}));
  FixtureDef fd;
  fd.geometry = Circle{{0, 0}, 1.0};
  fd.sensor = true;
  const FixtureId zone = world.createFixture(holder, fd);
  const Disk entering = addDisk(world, DiskSpec{{3.5, 0}, {2, 0}, 0.2, 1, 0});  // reaches 3.7: x + r = 3.9 < 4
  const Disk inside = addDisk(world, DiskSpec{{5, 0}, {1, 0}, 0.2, 1, 0});      // created inside, moving
  auto ev = stepEvents(world, 0.1);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].begin);
  EXPECT_EQ(ev[0].visitor, inside.fixture);
  EXPECT_EQ(ev[0].time, 0.0);
  ev = stepEvents(world, 0.1);  // entering ends at 3.9: x + r = 4.1, inside
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].visitor, entering.fixture);
  EXPECT_EQ(ev[0].time, 0.1);
  // Both leave the zone and come back by setPosition, then one is inside where the step begins (time
  // 0) and the other enters within it (at the step's end); the earlier fixture's event is the later one.
  world.setPosition(entering.body, {3.5, 0});
  world.setPosition(inside.body, {20, 0});
  ev = stepEvents(world, 0.1);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_FALSE(ev[0].begin);
  EXPECT_FALSE(ev[1].begin);
  EXPECT_TRUE(world.sensorOverlaps(zone).empty());
  world.setPosition(entering.body, {3.7, 0});  // ends the step at 3.9: inside
  world.setPosition(inside.body, {5, 0});
  ev = stepEvents(world, 0.1);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].visitor, inside.fixture);
  EXPECT_EQ(ev[0].time, 0.0);
  EXPECT_EQ(ev[1].visitor, entering.fixture);
  EXPECT_EQ(ev[1].time, 0.1);
  ASSERT_LT(entering.fixture.index, inside.fixture.index);  // so the order is by time, not by id
}

TEST(DiscreteSensors, ABodyPushedIntoASensorBeginsThere) {
  // Sensors see where the step ends, and that is after the push-apart: disk B (radius 0.5, at x = -0.65,
  // speed 5) ends its step at x = -0.15, overlapping disk A (radius 0.5, at rest at x = 0.4) by 0.45; A
  // takes half the push, 0.225, to x = 0.625, which is 0.375 from the sensor segment at x = 1, inside its
  // radius. The sensor must report A's begin, and list it.
  World world(modeDef(StepMode::Discrete));
  const BodyId door = world.createBody(bodyDef(BodyType::Static, {1, 0}));
  FixtureDef fd;
  fd.geometry = Segment{{0, -1}, {0, 1}};
  fd.sensor = true;
  const FixtureId sensor = world.createFixture(door, fd);
  const Disk a = addDisk(world, DiskSpec{{0.4, 0}, {0, 0}, 0.5, 1, 0});
  addDisk(world, DiskSpec{{-0.65, 0}, {5, 0}, 0.5, 1, 0});
  const auto ev = stepEvents(world, 0.1);
  EXPECT_NEAR(world.position(a.body).x, 0.625, 1e-12);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].begin);
  EXPECT_EQ(ev[0].visitor, a.fixture);
  EXPECT_EQ(world.sensorOverlaps(sensor), std::vector<FixtureId>{a.fixture});
}

}  // namespace
