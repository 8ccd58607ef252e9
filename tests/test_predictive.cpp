// Predictive mode tests: the same answers as the hybrid mode where the physics is exact (one collision,
// Newton's cradle, a short run of a gas, mixed shapes with sensors, changes made between steps, static and
// kinematic shapes changed on a large map), conservation and no overlaps over a long run, frames that are
// only times to look at, a ball bouncing under gravity at the analytic times and coming to rest, a ball
// thrown up against a ceiling, a pile, sparse far-apart clusters with fast bodies, the event budget,
// determinism, and a 10^5-disk gas at packing fraction 0.5.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "rattle/rattle.h"
#include "world_test_support.h"

namespace {

using namespace rattle_test;
using rattle::ContactEvent;
using rattle::StepMode;
using rattle::WorldDef;

WorldDef defOf(StepMode mode, Vec2 gravity = {}, int budget = 1'000'000) {
  WorldDef d;
  d.mode = mode;
  d.gravity = gravity;
  d.maxEventsPerStep = budget;
  return d;
}

std::string str(Vec2 v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g)", v.x, v.y);
  return buf;
}

::testing::AssertionResult vecNear(const char* what, Vec2 a, Vec2 e, double tol) {
  const double dx = std::fabs(a.x - e.x), dy = std::fabs(a.y - e.y);
  if (dx <= tol && dy <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << " = " << str(a) << ", expected " << str(e) << " (difference " << dx
                                       << ", " << dy << ", tolerance " << tol << ")";
}
#define EXPECT_VEC_NEAR(actual, expected, tol) EXPECT_TRUE(vecNear(#actual, (actual), (expected), (tol)))

// A scene built the same way in two worlds.
struct Scene {
  World world;
  std::vector<Disk> disks;
  BodyId paddle;
  explicit Scene(const WorldDef& d) : world(d) {}
};

// Every body's position and velocity, and every step's events, agree between two worlds.
void expectSameState(const World& a, const World& b, const std::vector<Disk>& da, const std::vector<Disk>& db,
                     double tol) {
  ASSERT_EQ(da.size(), db.size());
  for (size_t i = 0; i < da.size(); ++i) {
    SCOPED_TRACE("disk " + std::to_string(i));
    EXPECT_VEC_NEAR(a.position(da[i].body), b.position(db[i].body), tol);
    EXPECT_VEC_NEAR(a.velocity(da[i].body), b.velocity(db[i].body), tol);
  }
}

void expectSameEvents(std::span<const ContactEvent> a, std::span<const ContactEvent> b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    SCOPED_TRACE("event " + std::to_string(k));
    EXPECT_EQ(a[k].fixtureA, b[k].fixtureA);
    EXPECT_EQ(a[k].fixtureB, b[k].fixtureB);
    EXPECT_NEAR(a[k].time, b[k].time, tol);
    EXPECT_VEC_NEAR(a[k].point, b[k].point, tol);
    EXPECT_VEC_NEAR(a[k].normal, b[k].normal, tol);
    EXPECT_NEAR(a[k].impulse, b[k].impulse, tol * std::max(1.0, std::fabs(b[k].impulse)));
  }
}

// ------------------------------------------------------------------------------------------------
// Exact cases: the same answer as the hybrid mode.

TEST(PredictiveExact, SingleCollisionMatchesHybrid) {
  // `scale`: the size of the coordinates; far from the origin a coordinate's round-off is that much larger.
  struct Case {
    DiskSpec a, b;
    double scale;
  };
  const Case cases[] = {
      {{{0, 0}, {3, 0}, 1.0, 2.0, 1.0}, {{5, 0}, {-1, 0}, 0.5, 0.75, 1.0}, 1},
      {{{0, 0}, {3, 0}, 1.0, 2.0, 0.5}, {{5, 0.8}, {-1, 0.25}, 0.5, 0.75, 0.5}, 1},
      {{{-2.5, 1.25}, {1.75, -0.5}, 0.5, 3.0, 0.0}, {{1.5, -0.75}, {-0.25, 0.625}, 1.0, 0.5, 0.0}, 1},
      {{{1e6, -1e6}, {2, 0}, 0.5, 1.0, 1.0}, {{1e6 + 3.07, -1e6}, {0, 0}, 0.5, 1.0, 1.0}, 1e6},
  };
  for (const Case& c : cases) {
    for (double dt : {2.0, 0.1, 1.0 / 60}) {
      SCOPED_TRACE("dt " + std::to_string(dt) + ", scale " + std::to_string(c.scale));
      Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
      for (Scene* s : {&h, &p}) s->disks = {addDisk(s->world, c.a), addDisk(s->world, c.b)};
      int events = 0;
      for (int k = 0; k * dt < 3.0; ++k) {
        h.world.step(dt);
        p.world.step(dt);
        events += static_cast<int>(p.world.contactEvents().size());
        expectSameEvents(p.world.contactEvents(), h.world.contactEvents(), 1e-12 * c.scale);
        expectSameState(p.world, h.world, p.disks, h.disks, 1e-12 * c.scale);
        EXPECT_EQ(p.world.time(), h.world.time());
      }
      EXPECT_EQ(events, 1);
    }
  }
}

TEST(PredictiveExact, NewtonsCradleMatchesHybrid) {
  // Five equal disks in a row, touching, restitution 1. A sixth (the striker), or the first of the row
  // (already touching its neighbour), moves into the row: only the last disk moves afterwards, at the
  // incoming speed.
  for (bool striker : {true, false}) {
    for (double dt : {5.0, 0.25}) {
      SCOPED_TRACE(std::string(striker ? "striker" : "first disk moving") + ", dt " + std::to_string(dt));
      Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
      for (Scene* s : {&h, &p}) {
        if (striker) s->disks.push_back(addDisk(s->world, {{-3, 0}, {1.5, 0}, 0.5, 1.0, 1.0}));
        for (int k = 0; k < 5; ++k) {
          const Vec2 v = (!striker && k == 0) ? Vec2{1.5, 0} : Vec2{0, 0};
          s->disks.push_back(addDisk(s->world, {{static_cast<double>(k), 0}, v, 0.5, 1.0, 1.0}));
        }
      }
      int events = 0;
      for (int k = 0; k * dt < 5.0; ++k) {
        h.world.step(dt);
        p.world.step(dt);
        events += static_cast<int>(p.world.contactEvents().size());
        expectSameEvents(p.world.contactEvents(), h.world.contactEvents(), 1e-12);
        expectSameState(p.world, h.world, p.disks, h.disks, 1e-12);
      }
      EXPECT_EQ(events, striker ? 5 : 4);
      const size_t n = p.disks.size();
      for (size_t k = 0; k + 1 < n; ++k) EXPECT_VEC_NEAR(p.world.velocity(p.disks[k].body), (Vec2{0, 0}), 1e-12);
      EXPECT_VEC_NEAR(p.world.velocity(p.disks[n - 1].body), (Vec2{1.5, 0}), 1e-12);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// A gas of 1000 disks in a closed box.

RandomDiskOptions gasOptions(int count, double size) { return gasDiskOptions(count, size); }

// Compares two worlds' contact events step by step: same pairs in the same order, times within `tol`.
void expectSamePairs(const World& p, const World& h, int step, double tol) {
  const auto ep = p.contactEvents();
  const auto eh = h.contactEvents();
  ASSERT_EQ(ep.size(), eh.size()) << "step " << step;
  for (size_t e = 0; e < ep.size(); ++e) {
    ASSERT_EQ(ep[e].fixtureA, eh[e].fixtureA) << "step " << step << " event " << e;
    ASSERT_EQ(ep[e].fixtureB, eh[e].fixtureB) << "step " << step << " event " << e;
    EXPECT_NEAR(ep[e].time, eh[e].time, tol) << "step " << step << " event " << e;
  }
}

TEST(PredictiveGas, ThousandDisksSameCollisionsAsHybridForAShortRun) {
  const auto specs = randomDisks(gasOptions(1000, 50));
  Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
  ClosedBox boxes[2];
  int k = 0;
  for (Scene* s : {&h, &p}) {
    boxes[k++] = makeClosedBox(s->world, 0, 0, 50, 50, 1.0);
    s->disks = addDisks(s->world, specs);
  }
  const double dt = 0.05;
  size_t compared = 0;
  for (int step = 0; step < 40; ++step) {
    h.world.step(dt);
    p.world.step(dt);
    expectSamePairs(p.world, h.world, step, 1e-9);
    if (::testing::Test::HasFatalFailure()) return;
    compared += p.world.contactEvents().size();
  }
  EXPECT_GT(compared, 1000u);
  expectSameState(p.world, h.world, p.disks, h.disks, 1e-8);
}

TEST(PredictiveGas, ThousandDisksInClosedBoxConserveEnergy) {
  const auto specs = randomDisks(gasOptions(1000, 50));
  World world(defOf(StepMode::Predictive));
  const ClosedBox box = makeClosedBox(world, 0, 0, 50, 50, 1.0);
  const auto disks = addDisks(world, specs);
  const long double e0 = kineticEnergy(world, disks);
  const double dt = 0.1;
  const auto start = std::chrono::steady_clock::now();
  long long collisions = 0;
  int steps = 0;
  double worstEnergyError = 0;
  while (collisions < 200000 && steps < 20000) {
    world.step(dt);
    ++steps;
    collisions += static_cast<long long>(world.contactEvents().size());
    ASSERT_FALSE(world.stats().eventBudgetReached);
    const double err = static_cast<double>(std::fabs(kineticEnergy(world, disks) - e0) / e0);
    worstEnergyError = std::max(worstEnergyError, err);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "[ Predictive ] 1000 disks in a box: %lld collisions in %d steps in %.2f s; worst relative energy "
      "error %.3g\n",
      collisions, steps, seconds, worstEnergyError);
  EXPECT_LE(worstEnergyError, 1e-12);
  EXPECT_TRUE(allFinite(world, disks));
  EXPECT_LE(maxRelativeOverlap(world, disks), 1e-9);
  EXPECT_LE(maxRelativeWallPenetration(world, disks, box), 1e-9);
  for (const Disk& d : disks) EXPECT_TRUE(centreInside(world.position(d.body), box));
}

TEST(PredictiveGas, OneLongStepEqualsManyShortOnes) {
  // Frames are only times to look at: one step of 2 s and 40 steps of 0.05 s see the same collisions
  // (up to round-off in the times, which the gas's chaos amplifies over time).
  const auto specs = randomDisks(gasOptions(300, 30));
  Scene a(defOf(StepMode::Predictive)), b(defOf(StepMode::Predictive));
  for (Scene* s : {&a, &b}) {
    makeClosedBox(s->world, 0, 0, 30, 30, 1.0);
    s->disks = addDisks(s->world, specs);
  }
  a.world.step(2.0);
  std::vector<ContactEvent> many;
  for (int k = 0; k < 40; ++k) {
    b.world.step(0.05);
    for (ContactEvent e : b.world.contactEvents()) {
      e.time += 0.05 * k;
      many.push_back(e);
    }
  }
  const auto one = a.world.contactEvents();
  ASSERT_GT(one.size(), 200u);
  ASSERT_EQ(one.size(), many.size());
  for (size_t k = 0; k < one.size(); ++k) {
    ASSERT_EQ(one[k].fixtureA, many[k].fixtureA) << "event " << k;
    ASSERT_EQ(one[k].fixtureB, many[k].fixtureB) << "event " << k;
    EXPECT_NEAR(one[k].time, many[k].time, 1e-9);
  }
  expectSameState(a.world, b.world, a.disks, b.disks, 1e-8);
}

// ------------------------------------------------------------------------------------------------
// Gravity.

TEST(PredictiveGravity, BallBouncesAtAnalyticTimesAndComesToRest) {
  const double g = 9.81, h0 = 2.0, e = 0.7, r = 0.25;
  Scene h(defOf(StepMode::Hybrid, {0, -g})), p(defOf(StepMode::Predictive, {0, -g}));
  for (Scene* s : {&h, &p}) {
    const BodyId floor = s->world.createBody(bodyDef(BodyType::Static));
    FixtureDef fd;
    fd.geometry = rattle::Segment{{-10, 0}, {10, 0}};
    s->world.createFixture(floor, fd);
    s->disks.push_back(addDisk(s->world, {{0.5, h0 + r}, {0, 0}, r, 1.0, e}));
  }
  const double dt = 1.0 / 60;
  std::vector<double> times;
  for (int step = 0; step < 600; ++step) {
    h.world.step(dt);
    p.world.step(dt);
    expectSameEvents(p.world.contactEvents(), h.world.contactEvents(), 1e-9);
    expectSameState(p.world, h.world, p.disks, h.disks, 1e-9);
    for (const ContactEvent& ev : p.world.contactEvents()) times.push_back(step * dt + ev.time);
    EXPECT_EQ(p.world.isAsleep(p.disks[0].body), h.world.isAsleep(h.disks[0].body)) << "step " << step;
  }
  // t1 = sqrt(2 h / g), v1 = g t1, then t_{k+1} = t_k + 2 e^k v1 / g while the bounces are faster than
  // the resting speed (0.01).
  const double t1 = std::sqrt(2 * h0 / g), v1 = g * t1;
  double t = t1;
  int checked = 0;
  for (size_t k = 0; k < times.size(); ++k) {
    const double speed = std::pow(e, static_cast<double>(k)) * v1;
    if (speed * e < 0.02) break;
    EXPECT_NEAR(times[k], t, 1e-9 * (1 + k)) << "bounce " << k;
    ++checked;
    t += 2 * std::pow(e, static_cast<double>(k + 1)) * v1 / g;
  }
  EXPECT_GE(checked, 10);
  EXPECT_TRUE(p.world.isAsleep(p.disks[0].body));
  EXPECT_NEAR(p.world.position(p.disks[0].body).y, r, 1e-9);
  EXPECT_EQ(p.world.stats().sleeping, 1);
}

TEST(PredictiveGravity, BallThrownUpMeetsACeilingBelowItsPeak) {
  // Thrown up at 10 under g = 10, the ball's centre would peak at y = 5 and be back at 0 at t = 2; a
  // ceiling at y = 4.5 stops it when its centre reaches 4, at 10 t - 5 t^2 = 4: t = 1 - sqrt(0.2), at a
  // speed of 10 sqrt(0.2). Between two instants at which the ball is low (a prediction's start and its
  // horizon) the path rises above both: a test of whether the ball can reach the ceiling must take the
  // peak into account, not only the ends.
  World world(defOf(StepMode::Predictive, {0, -10}));
  const BodyId ceiling = world.createBody(bodyDef(BodyType::Static));
  FixtureDef fd;
  fd.restitution = 1.0;
  fd.geometry = rattle::Segment{{-5, 4.5}, {5, 4.5}};
  const FixtureId wall = world.createFixture(ceiling, fd);
  const Disk ball = addDisk(world, {{0, 0}, {0, 10}, 0.5, 1.0, 1.0});
  const double dt = 1.0 / 60;
  double met = -1;
  for (int step = 0; step < 60; ++step) {
    world.step(dt);
    for (const ContactEvent& e : world.contactEvents()) {
      if (met < 0 && (e.fixtureA == wall || e.fixtureB == wall)) met = step * dt + e.time;
    }
  }
  EXPECT_NEAR(met, 1 - std::sqrt(0.2), 1e-12);
  // Back down from the ceiling at 10 sqrt(0.2), under g, from t = 1 - sqrt(0.2) to t = 1.
  const double since = 1 - met;
  EXPECT_NEAR(world.velocity(ball.body).y, -10 * std::sqrt(0.2) - 10 * since, 1e-9);
  EXPECT_NEAR(world.position(ball.body).y, 4 - 10 * std::sqrt(0.2) * since - 5 * since * since, 1e-9);
}

TEST(PredictiveGravity, PileInABoxSettlesWithoutSinking) {
  WorldDef d = defOf(StepMode::Predictive, {0, -10});
  d.collapseTime = 1e-3;
  World world(d);
  const ClosedBox box = makeClosedBox(world, 0, 0, 10, 20, 0.5);
  auto o = gasOptions(60, 10);
  o.ymax = 20;
  o.minRestitution = o.maxRestitution = 0.5;
  const auto disks = addDisks(world, randomDisks(o));
  for (int step = 0; step < 300; ++step) {
    world.step(1.0 / 60);
    ASSERT_TRUE(allFinite(world, disks));
    ASSERT_FALSE(world.stats().eventBudgetReached);
  }
  // The resting rules let a body go to sleep within restingSpeed^2 / g of its supports (README,
  // "Resting"), 1e-5 here; anything near a radius would be a missed collision.
  EXPECT_LE(maxRelativeOverlap(world, disks), 1e-4);
  EXPECT_LE(maxRelativeWallPenetration(world, disks, box), 1e-4);
  for (const Disk& disk : disks) EXPECT_TRUE(centreInside(world.position(disk.body), box));
}

// ------------------------------------------------------------------------------------------------
// Changes between steps, static shapes, kinematic bodies, the budget.

// A scene with every kind of static shape, a kinematic paddle and disks, changed between steps.
void buildMixedScene(Scene& s) {
  makeClosedBox(s.world, 0, 0, 40, 30, 1.0);
  const BodyId statics = s.world.createBody(bodyDef(BodyType::Static, {20, 15}));
  FixtureDef fd;
  fd.restitution = 1.0;
  fd.geometry = rattle::Polygon{{{-2, -1}, {2, -1}, {0, 2}}};
  s.world.createFixture(statics, fd);
  fd.geometry = rattle::Polyline{{{-15, -10}, {-10, -12}, {-5, -10}}};
  s.world.createFixture(statics, fd);
  fd.geometry = rattle::Segment{{5, 5}, {15, 12}};
  s.world.createFixture(statics, fd);
  fd.geometry = rattle::Point{{-12, 8}};
  s.world.createFixture(statics, fd);
  const BodyId paddle = s.world.createBody(bodyDef(BodyType::Kinematic, {30, 5}, {0, 1.5}));
  fd.geometry = rattle::Polygon{{{-2, -0.25}, {2, -0.25}, {2, 0.25}, {-2, 0.25}}};
  s.world.createFixture(paddle, fd);
  s.paddle = paddle;
  auto o = gasOptions(150, 40);
  o.ymax = 30;
  o.maxSpeed = 3;
  std::vector<DiskSpec> specs = randomDisks(o);
  // Keep them clear of the static shapes and the paddle.
  std::vector<DiskSpec> kept;
  for (const DiskSpec& d : specs) {
    if (!s.world.overlapCircle(d.position, d.radius + 0.01).empty()) continue;
    if (rattle::length(d.position - Vec2{30, 5}) < 3) continue;
    kept.push_back(d);
  }
  s.disks = addDisks(s.world, kept);
}

void mutate(Scene& s, int step) {
  if (step == 10) s.world.setVelocity(s.disks[3].body, {-4, 2});
  if (step == 20) s.world.setPosition(s.disks[5].body, {1.5, 28.5});
  if (step == 30) s.world.destroyBody(s.disks[7].body);
  if (step == 40) s.disks.push_back(addDisk(s.world, {{38, 28}, {-2, -2}, 0.5, 1.0, 1.0}));
  if (step == 50) {
    const auto f = s.world.fixtures(s.disks[9].body)[0];
    s.world.setFilter(f, filterOf(0x0002, 0xFFFFFFFD));
  }
  if (step == 60) s.world.setVelocity(s.paddle, {0, -1.5});  // the paddle turns back
  if (step == 70) s.world.setDensity(s.world.fixtures(s.disks[11].body)[0], 8.0);  // a heavier disk
}

TEST(PredictiveChanges, ChangesBetweenStepsMatchHybrid) {
  Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
  buildMixedScene(h);
  buildMixedScene(p);
  ASSERT_GT(p.disks.size(), 100u);
  const double dt = 1.0 / 30;
  for (int step = 0; step < 90; ++step) {
    mutate(h, step);
    mutate(p, step);
    h.world.step(dt);
    p.world.step(dt);
    expectSamePairs(p.world, h.world, step, 1e-9);
    if (::testing::Test::HasFatalFailure()) return;
  }
  std::vector<Disk> alive;
  for (const Disk& d : p.disks)
    if (p.world.isValid(d.body)) alive.push_back(d);
  std::vector<Disk> aliveH;
  for (const Disk& d : h.disks)
    if (h.world.isValid(d.body)) aliveH.push_back(d);
  expectSameState(p.world, h.world, alive, aliveH, 1e-8);
}

// A large map with fast disks and a crowd in a corner (the predictive grid's table then covers the walls'
// region and is mostly empty), whose static and kinematic shapes change between steps in each way that
// can change the predictive mode's listing of static fixtures by cell, with changes among dynamic bodies
// (which keep that listing) in between. The hybrid mode keeps no such listing: any listing kept too long, or not
// kept right, shows up as a missed or an extra collision.
struct ChangingMap {
  BodyId wall, mover;
  FixtureId segment;
  std::vector<FixtureId> wallFixtures;  // the segment, the block, the kinematic body's
};

// A crowd at rest in a pen of its own in the corner of a 400 x 200 map: it keeps the predictive grid's
// cells near a diameter wide, so that the table covering the map is mostly empty (the predictive mode
// then orders its bodies from the occupied entries alone) and a wall is listed only in the cells near
// it. (Walled off: a fast disk running into a crowd sets off a cascade that turns round-off into large
// differences between the two modes.)
void addRestingCrowd(Scene& s) {
  makeClosedBox(s.world, 364, 164, 382, 182, 1.0);
  auto crowd = gasOptions(60, 14);
  crowd.xmin = 366;
  crowd.ymin = 166;
  crowd.xmax = 380;
  crowd.ymax = 180;
  crowd.minSpeed = crowd.maxSpeed = 0;
  for (const DiskSpec& d : randomDisks(crowd)) s.disks.push_back(addDisk(s.world, d));
}

void buildChangingMap(Scene& s) {
  makeClosedBox(s.world, 0, 0, 400, 200, 1.0);
  for (int k = 0; k < 40; ++k) {
    const Vec2 velocity{(k % 2 ? 1 : -1) * (20.0 + k), (k % 3 - 1) * (10.0 + k)};
    s.disks.push_back(addDisk(s.world, {{10 + 9.0 * k, 10 + 4.5 * k}, velocity, 0.5, 1.0, 1.0}));
  }
  addRestingCrowd(s);
}

void changeMap(Scene& s, ChangingMap& m, int step) {
  FixtureDef fd;
  fd.restitution = 1.0;
  if (step == 3) {  // a static body and a wall across the map
    m.wall = s.world.createBody(bodyDef(BodyType::Static, {60, 100}));
    fd.geometry = rattle::Segment{{0, -99}, {0, 99}};
    m.segment = s.world.createFixture(m.wall, fd);
    m.wallFixtures.push_back(m.segment);
  }
  if (step == 12) s.disks.push_back(addDisk(s.world, {{300, 150}, {-3, 1}, 0.5, 1.0, 1.0}));  // keeps the listing
  if (step == 20) s.world.setPosition(m.wall, {150, 100});  // the wall moves
  if (step == 28) s.world.destroyBody(s.disks[4].body);     // keeps the listing
  if (step == 35) {  // a second fixture on the static body
    fd.geometry = rattle::Polygon{{{-40, -5}, {-20, -5}, {-20, 5}, {-40, 5}}};
    m.wallFixtures.push_back(s.world.createFixture(m.wall, fd));
  }
  if (step == 50) s.world.destroyFixture(m.segment);  // the wall goes, the block stays
  if (step == 65) {  // a moving kinematic body
    m.mover = s.world.createBody(bodyDef(BodyType::Kinematic, {110, 60}, {2, 0}));
    fd.geometry = rattle::Polygon{{{-3, -30}, {3, -30}, {3, 30}, {-3, 30}}};
    m.wallFixtures.push_back(s.world.createFixture(m.mover, fd));
  }
  if (step == 80) s.world.setVelocity(m.mover, {-3, 0});
  if (step == 95) s.world.destroyBody(m.wall);
}

TEST(PredictiveChanges, StaticAndKinematicChangesOnALargeMapMatchHybrid) {
  Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
  ChangingMap mh, mp;
  buildChangingMap(h);
  buildChangingMap(p);
  const double dt = 1.0 / 30;
  std::vector<size_t> contacts(3, 0);  // with the segment, the block, the kinematic body
  for (int step = 0; step < 120; ++step) {
    changeMap(h, mh, step);
    changeMap(p, mp, step);
    h.world.step(dt);
    p.world.step(dt);
    expectSamePairs(p.world, h.world, step, 1e-9);
    if (::testing::Test::HasFatalFailure()) return;
    for (const ContactEvent& e : p.world.contactEvents()) {
      for (size_t k = 0; k < mp.wallFixtures.size(); ++k) {
        if (e.fixtureA == mp.wallFixtures[k] || e.fixtureB == mp.wallFixtures[k]) ++contacts[k];
      }
    }
  }
  // Each changed shape was met: the comparison above is about them.
  for (size_t k = 0; k < contacts.size(); ++k) EXPECT_GT(contacts[k], 0u) << "shape " << k;
  std::printf("[ Predictive ] changing map: %zu, %zu and %zu contacts with the segment, the block and the "
              "kinematic body\n",
              contacts[0], contacts[1], contacts[2]);
  std::vector<Disk> alive, aliveH;
  for (const Disk& d : p.disks)
    if (p.world.isValid(d.body)) alive.push_back(d);
  for (const Disk& d : h.disks)
    if (h.world.isValid(d.body)) aliveH.push_back(d);
  expectSameState(p.world, h.world, alive, aliveH, 1e-8);
}

// Four disks, each heading for a static shape that a change between steps moves or puts in its way, or
// takes out of it, a few steps before it gets there, while another body is made and unmade at every
// step far from them (a change of structure among dynamic bodies, after which the predictive mode keeps
// its listing of static fixtures if nothing static changed). Each disk meets its shape, or passes where
// it was, as the hybrid mode has it and at the analytic time.
TEST(PredictiveChanges, EveryStaticChangeIsSeenWhileDynamicBodiesComeAndGo) {
  struct Run {
    Scene s;
    BodyId added, doomed, moved, churn;
    FixtureId removed, movedWall;
    explicit Run(const WorldDef& d) : s(d) {}
  };
  FixtureDef wall;
  wall.restitution = 1.0;
  wall.geometry = rattle::Segment{{0, -10}, {0, 10}};
  // Disk k starts at x = 10 at 60 units a second toward a shape at x = 60 + 20 k, which its edge reaches
  // at (49.5 + 20 k) / 60 s: steps 24.75, 34.75 and 44.75 of 1/30 s. The changes come at steps 20, 30
  // and 40. A fourth disk, at y = 25, meets a static body moved into its way at step 8, at x = 30: its
  // edge gets there at 19.5 / 60 s, step 9.75.
  auto build = [&](Run& r) {
    makeClosedBox(r.s.world, 0, 0, 400, 200, 1.0);
    for (int k = 0; k < 3; ++k) r.s.disks.push_back(addDisk(r.s.world, {{10, 50.0 + 50 * k}, {60, 0}, 0.5, 1.0, 1.0}));
    r.s.disks.push_back(addDisk(r.s.world, {{10, 25}, {60, 0}, 0.5, 1.0, 1.0}));
    addRestingCrowd(r.s);  // small cells: each wall is listed only near where it is
    r.moved = r.s.world.createBody(bodyDef(BodyType::Static, {300, 25}));
    r.movedWall = r.s.world.createFixture(r.moved, wall);
    r.added = r.s.world.createBody(bodyDef(BodyType::Static, {60, 50}));  // its wall comes at step 20
    const BodyId kept = r.s.world.createBody(bodyDef(BodyType::Static, {80, 100}));
    r.removed = r.s.world.createFixture(kept, wall);  // goes at step 30
    r.doomed = r.s.world.createBody(bodyDef(BodyType::Static, {100, 150}));
    r.s.world.createFixture(r.doomed, wall);  // its body goes at step 40
  };
  auto change = [&](Run& r, int step) {
    if (r.s.world.isValid(r.churn)) {
      r.s.world.destroyBody(r.churn);
    } else {
      r.churn = r.s.world.createBody(bodyDef(BodyType::Dynamic, {390, 190}));
      FixtureDef fd;
      fd.geometry = rattle::Circle{{0, 0}, 0.5};
      r.s.world.createFixture(r.churn, fd);
    }
    if (step == 8) r.s.world.setPosition(r.moved, {30, 25});
    if (step == 20) r.s.world.createFixture(r.added, wall);
    if (step == 30) r.s.world.destroyFixture(r.removed);
    if (step == 40) r.s.world.destroyBody(r.doomed);
  };
  Run h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
  build(h);
  build(p);
  const double dt = 1.0 / 30;
  const int steps = 50;
  double metMoved = -1;  // when the fourth disk met the moved wall
  for (int step = 0; step < steps; ++step) {
    change(h, step);
    change(p, step);
    h.s.world.step(dt);
    p.s.world.step(dt);
    expectSamePairs(p.s.world, h.s.world, step, 1e-9);
    if (::testing::Test::HasFatalFailure()) return;
    for (const ContactEvent& e : p.s.world.contactEvents()) {
      if (metMoved < 0 && (e.fixtureA == p.movedWall || e.fixtureB == p.movedWall)) metMoved = step * dt + e.time;
    }
  }
  EXPECT_NEAR(metMoved, 19.5 / 60, 1e-12);
  const double at = steps * dt;
  EXPECT_NEAR(p.s.world.velocity(p.s.disks[0].body).x, -60, 1e-9);
  EXPECT_NEAR(p.s.world.position(p.s.disks[0].body).x, 59.5 - 60 * (at - 49.5 / 60), 1e-9);
  for (int k : {1, 2}) {
    EXPECT_NEAR(p.s.world.velocity(p.s.disks[k].body).x, 60, 1e-9);
    EXPECT_NEAR(p.s.world.position(p.s.disks[k].body).x, 10 + 60 * at, 1e-9);
  }
}

// Compares two worlds' sensor events of a step: each (sensor, visitor) pair has the same begins and ends
// in the same order, at times within `tol`; each list is in time order.
void expectSameSensorEvents(const World& p, const World& h, int step, double tol) {
  using Key = std::pair<uint32_t, uint32_t>;
  auto byPair = [](std::span<const rattle::SensorEvent> events) {
    std::map<Key, std::vector<rattle::SensorEvent>> out;
    for (const auto& e : events) out[{e.sensor.index, e.visitor.index}].push_back(e);
    return out;
  };
  for (const World* w : {&p, &h}) {
    const auto ev = w->sensorEvents();
    for (size_t e = 1; e < ev.size(); ++e) EXPECT_LE(ev[e - 1].time, ev[e].time) << "step " << step << " event " << e;
  }
  const auto a = byPair(p.sensorEvents()), b = byPair(h.sensorEvents());
  ASSERT_EQ(a.size(), b.size()) << "step " << step << ": pairs with sensor events";
  for (const auto& [key, list] : a) {
    const auto it = b.find(key);
    ASSERT_TRUE(it != b.end()) << "step " << step << ": sensor " << key.first << ", visitor " << key.second;
    ASSERT_EQ(list.size(), it->second.size()) << "step " << step << ": sensor " << key.first << ", visitor "
                                               << key.second;
    for (size_t e = 0; e < list.size(); ++e) {
      EXPECT_EQ(list[e].begin, it->second[e].begin) << "step " << step;
      EXPECT_NEAR(list[e].time, it->second[e].time, tol) << "step " << step;
    }
  }
}

TEST(PredictiveShapes, SeveralCirclesAndSensorsOnDynamicBodiesMatchHybrid) {
  // Dynamic bodies made of two concentric physical circles, of one small circle, or of a circle with a
  // larger sensor circle (a sight range: it never collides); a static polygon, polyline and segment.
  auto build = [](Scene& s) {
    makeClosedBox(s.world, 0, 0, 30, 30, 1.0);
    const BodyId statics = s.world.createBody(bodyDef(BodyType::Static, {15, 15}));
    FixtureDef fd;
    fd.restitution = 1.0;
    fd.geometry = rattle::Polygon{{{-2, -2}, {2, -2}, {0, 1}}};
    s.world.createFixture(statics, fd);
    fd.geometry = rattle::Polyline{{{-10, 8}, {-6, 10}, {-2, 8}}};
    s.world.createFixture(statics, fd);
    fd.geometry = rattle::Segment{{5, -10}, {10, -6}};
    s.world.createFixture(statics, fd);
    // Static sensors: a room and a doorway.
    fd.sensor = true;
    fd.geometry = rattle::Polygon{{{-13, -13}, {-5, -13}, {-5, -5}, {-13, -5}}};
    s.world.createFixture(statics, fd);
    fd.geometry = rattle::Segment{{0, 3}, {0, 13}};
    s.world.createFixture(statics, fd);
    std::mt19937_64 rng(11);
    auto uniform = [&rng](double lo, double hi) {
      return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
    };
    for (int k = 0; k < 60; ++k) {
      const Vec2 p{2 + (k % 8) * 3.5, 2 + (k / 8) * 3.5};
      if (!s.world.overlapCircle(p, 1.0).empty()) continue;
      const BodyId b = s.world.createBody(bodyDef(BodyType::Dynamic, p, {uniform(-3, 3), uniform(-3, 3)}));
      FixtureDef c;
      c.restitution = 1.0;
      switch (k % 3) {
        case 0:
          c.geometry = rattle::Circle{{0, 0}, 0.3};
          s.world.createFixture(b, c);
          c.geometry = rattle::Circle{{0, 0}, 0.6};
          s.world.createFixture(b, c);
          break;
        case 1:
          // (A Point would do here too, but the hybrid step, the reference, can storm when a point lands
          // exactly on a segment's line.)
          c.geometry = rattle::Circle{{0, 0}, 0.2};
          s.world.createFixture(b, c);
          break;
        default:
          c.geometry = rattle::Circle{{0, 0}, 0.45};
          s.world.createFixture(b, c);
          c.geometry = rattle::Circle{{0, 0}, 2.5};
          c.sensor = true;
          s.world.createFixture(b, c);
          break;
      }
      s.disks.push_back(Disk{b, s.world.fixtures(b)[0], 0, s.world.mass(b)});
    }
  };
  Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
  build(h);
  build(p);
  ASSERT_GT(p.disks.size(), 40u);
  int events = 0, sensorEvents = 0;
  for (int step = 0; step < 150; ++step) {
    h.world.step(1.0 / 30);
    p.world.step(1.0 / 30);
    expectSamePairs(p.world, h.world, step, 1e-9);
    expectSameSensorEvents(p.world, h.world, step, 1e-9);
    if (::testing::Test::HasFatalFailure()) return;
    events += static_cast<int>(p.world.contactEvents().size());
    sensorEvents += static_cast<int>(p.world.sensorEvents().size());
  }
  std::printf("[ shapes   ] %d contacts, %d sensor events\n", events, sensorEvents);
  EXPECT_GT(events, 80);
  EXPECT_GT(sensorEvents, 200);
  expectSameState(p.world, h.world, p.disks, h.disks, 1e-8);
}

TEST(PredictiveSparse, FastBodiesBetweenFarClustersMatchHybrid) {
  // Two clusters a hundred thousand units apart, and fast small disks flying from one to the other: cells
  // of one diameter would make the fast disks cross hundreds of thousands of cells, and a grid over the
  // whole region would be mostly empty. Also advanceTo and a step of zero. Until the fast disks arrive
  // (t = 2.5) the collisions are the hybrid mode's; after that they stir the far cluster chaotically, so
  // only the invariants are checked.
  auto build = [](Scene& s) {
    for (double cx : {0.0, 1e5}) {
      auto o = gasOptions(80, 20);
      o.xmin = cx;
      o.xmax = cx + 20;
      o.seed = cx == 0 ? 3 : 4;
      for (const DiskSpec& d : randomDisks(o)) s.disks.push_back(addDisk(s.world, d));
    }
    for (int k = 0; k < 5; ++k) {
      s.disks.push_back(addDisk(s.world, {{25.0 + k, 10.0 + 2 * k}, {4e4, 1.0 * k}, 0.1, 1.0, 1.0}));
      s.disks.push_back(addDisk(s.world, {{1e5 - 5.0 - k, 3.0 + 3 * k}, {-4e4, -1.0 * k}, 0.1, 1.0, 1.0}));
    }
  };
  Scene h(defOf(StepMode::Hybrid)), p(defOf(StepMode::Predictive));
  build(h);
  build(p);
  const long double e0 = kineticEnergy(p.world, p.disks);
  const auto start = std::chrono::steady_clock::now();
  int events = 0, fastHits = 0;
  for (int step = 0; step < 20; ++step) {
    const double t = (step + 1) * 0.25;
    h.world.advanceTo(t);
    p.world.advanceTo(t);
    // Coordinates near 1e5 carry round-off of 1e-11, which the gas's chaos amplifies.
    if (t < 2.4) {
      expectSamePairs(p.world, h.world, step, 1e-7);
      // The clusters' disks; the fast ones graze each other at 8e4 halfway, where a coordinate's
      // round-off (1e-11) turns the contact normal by 1e-10 and their speed makes that 1e-5.
      const std::vector<Disk> slowP(p.disks.begin(), p.disks.begin() + 160);
      const std::vector<Disk> slowH(h.disks.begin(), h.disks.begin() + 160);
      expectSameState(p.world, h.world, slowP, slowH, 1e-6);
    }
    for (const ContactEvent& e : p.world.contactEvents()) {
      ++events;
      for (size_t k = 160; k < p.disks.size(); ++k)
        fastHits += (e.bodyA == p.disks[k].body || e.bodyB == p.disks[k].body);
    }
    p.world.step(0);
    EXPECT_TRUE(p.world.contactEvents().empty());
    EXPECT_NEAR(static_cast<double>(kineticEnergy(p.world, p.disks) / e0), 1.0, 1e-12) << "step " << step;
    EXPECT_LE(maxRelativeOverlap(p.world, p.disks), 1e-9) << "step " << step;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 10.0);
  EXPECT_GT(events, 200);
  EXPECT_GT(fastHits, 5);
  EXPECT_EQ(p.world.time(), 5.0);
}

TEST(PredictiveBudget, StopsAtBudgetAndReportsIt) {
  World world(defOf(StepMode::Predictive, {}, 25));
  const ClosedBox box = makeClosedBox(world, 0, 0, 30, 30, 1.0);
  auto o = gasOptions(300, 30);
  o.minSpeed = 2;
  o.maxSpeed = 4;
  const auto disks = addDisks(world, randomDisks(o));
  int cutShort = 0;
  for (int step = 0; step < 40; ++step) {
    world.step(0.25);
    EXPECT_LE(world.stats().eventsProcessed, 25);
    EXPECT_LE(world.contactEvents().size(), static_cast<size_t>(world.stats().eventsProcessed));
    cutShort += world.stats().eventBudgetReached ? 1 : 0;
    ASSERT_TRUE(allFinite(world, disks));
    EXPECT_LE(maxRelativeOverlap(world, disks), 1e-9) << "after step " << step;
    EXPECT_LE(maxRelativeWallPenetration(world, disks, box), 1e-9) << "after step " << step;
  }
  EXPECT_GT(cutShort, 30);
  EXPECT_DOUBLE_EQ(world.time(), 10.0);
}

// ------------------------------------------------------------------------------------------------
// Determinism.

TEST(PredictiveDeterminism, TwoRunsGiveTheSameHashEveryStep) {
  auto run = [](std::vector<uint64_t>& hashes) {
    WorldDef d = defOf(StepMode::Predictive, {0, -5});
    World world(d);
    makeClosedBox(world, 0, 0, 30, 30, 0.9);
    auto o = gasOptions(400, 30);
    o.minRestitution = 0.8;
    o.maxRestitution = 1.0;
    o.maxSpeed = 4;
    const auto disks = addDisks(world, randomDisks(o));
    for (int step = 0; step < 120; ++step) {
      if (step == 60) world.setVelocity(disks[0].body, {10, 10});
      world.step(1.0 / 60);
      hashes.push_back(world.stateHash());
    }
  };
  std::vector<uint64_t> a, b;
  run(a);
  run(b);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << "step " << k;
}

// ------------------------------------------------------------------------------------------------
// Scale: 10^5 disks at packing fraction 0.5.

// n disks of radius r on a square lattice filling an L x L box at the given packing fraction, random
// directions, the given speed.
std::vector<DiskSpec> latticeGas(int n, double r, double packing, double speed, uint64_t seed, double& L) {
  L = std::sqrt(n * std::numbers::pi * r * r / packing);
  const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  const double a = L / side;
  std::mt19937_64 rng(seed);
  auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
  };
  std::vector<DiskSpec> specs;
  specs.reserve(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int ix = k % side, iy = k / side;
    DiskSpec d;
    d.radius = r;
    d.position = {(ix + 0.5) * a, (iy + 0.5) * a};
    const double angle = uniform(0, 2 * std::numbers::pi);
    d.velocity = {speed * std::cos(angle), speed * std::sin(angle)};
    d.restitution = 1.0;
    specs.push_back(d);
  }
  return specs;
}

// Largest pair overlap relative to the radius, through a cell grid (the O(N^2) helper is too slow).
double maxOverlapOnGrid(const World& world, const std::vector<Disk>& disks, double r, double L) {
  const int n = std::max(1, static_cast<int>(L / (2 * r)));
  const double cell = L / n;
  std::vector<std::vector<int>> cells(static_cast<size_t>(n) * n);
  std::vector<Vec2> p(disks.size());
  auto index = [&](double x) { return std::clamp(static_cast<int>(std::floor(x / cell)), 0, n - 1); };
  for (size_t i = 0; i < disks.size(); ++i) {
    p[i] = world.position(disks[i].body);
    cells[static_cast<size_t>(index(p[i].y)) * n + index(p[i].x)].push_back(static_cast<int>(i));
  }
  double worst = -1;
  for (size_t i = 0; i < disks.size(); ++i) {
    const int x = index(p[i].x), y = index(p[i].y);
    for (int yy = std::max(0, y - 1); yy <= std::min(n - 1, y + 1); ++yy)
      for (int xx = std::max(0, x - 1); xx <= std::min(n - 1, x + 1); ++xx)
        for (int j : cells[static_cast<size_t>(yy) * n + xx])
          if (static_cast<size_t>(j) > i) worst = std::max(worst, (2 * r - rattle::length(p[i] - p[j])) / r);
  }
  return worst;
}

TEST(PredictiveScale, HundredThousandDisksAtPackingHalf) {
  // 10^5 disks of radius 0.5 in a walled box at packing fraction 0.5, speed 10, 0.2 s simulated in four
  // steps. The first step also builds the grid and the queue; the rate is printed for the other three.
  const int n = 100000;
  const double r = 0.5;
  double L = 0;
  const auto specs = latticeGas(n, r, 0.5, 10.0, 7, L);
  World world(defOf(StepMode::Predictive));
  const ClosedBox box = makeClosedBox(world, 0, 0, L, L, 1.0);
  const auto disks = addDisks(world, specs);
  const long double e0 = kineticEnergy(world, disks);
  long long collisions = 0, first = 0;
  double firstSeconds = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int step = 0; step < 4; ++step) {
    world.step(0.05);
    ASSERT_FALSE(world.stats().eventBudgetReached);
    if (step == 0) {
      first = static_cast<long long>(world.contactEvents().size());
      firstSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    } else {
      collisions += static_cast<long long>(world.contactEvents().size());
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "[ Predictive ] %d disks, packing 0.5, box %.1f: first step (grid, queue, %lld collisions) %.2f s; "
      "then %lld collisions in %.2f s: %.3g collisions/s\n",
      n, L, first, firstSeconds, collisions, seconds - firstSeconds, collisions / (seconds - firstSeconds));
  EXPECT_GT(collisions, 100000);
  const double err = static_cast<double>(std::fabs(kineticEnergy(world, disks) - e0) / e0);
  EXPECT_LE(err, 1e-12);
  // No disk into another, into a wall or through it.
  EXPECT_LE(maxOverlapOnGrid(world, disks, r, L), 1e-9);
  EXPECT_LE(maxRelativeWallPenetration(world, disks, box), 1e-9);
  for (const Disk& d : disks) ASSERT_TRUE(centreInside(world.position(d.body), box));
}

// README, Geometry: a disk whose centre is inside a Polygon moves on freely until its centre is out;
// from then on the polygon holds it. Made with its centre 0.2 deep in a floor block and thrown up, its
// centre leaves the block and rises to y0 + v^2 / 2g; falling back, the block's top face holds it there
// (still overlapping it) or, when the disk cleared the block, where it lands (centre at its radius).
// The predictive mode keeps predictions across steps, and the disk's, made while its centre was inside,
// saw no face: it fell through the block (fuzz/regressions/world_api/inside-predictive-disk-rises-out-of-
// a-block-and-falls-back).
TEST(PredictiveGravity, ADiskRisingOutOfABlockIsHeldByItsTopFace) {
  constexpr double r = 0.13, y0 = -0.2, g = 9.81;
  for (const StepMode mode : {StepMode::Hybrid, StepMode::Predictive}) {
    for (const double speed : {2.0, 2.5, 2.575, 2.8}) {
      World world(defOf(mode, {0, -g}));
      const BodyId block = world.createBody(bodyDef(rattle::BodyType::Static));
      rattle::FixtureDef fd;
      fd.geometry = rattle::Polygon{{{-5, -0.5}, {5, -0.5}, {5, 0}, {-5, 0}}};
      world.createFixture(block, fd);
      const Disk disk = addDisk(world, {{0, y0}, {0, speed}, r, 1.0, 0.0});
      const double apex = y0 + speed * speed / (2 * g);
      const double held = std::min(apex, r);
      double lowestAfterApex = 1e300;
      for (int step = 0; step < 40; ++step) {
        world.step(0.05);
        if (world.time() > speed / g) lowestAfterApex = std::min(lowestAfterApex, world.position(disk.body).y);
      }
      EXPECT_GE(lowestAfterApex, held - 0.01 * r) << "mode " << static_cast<int>(mode) << ", speed " << speed;
      EXPECT_LE(world.position(disk.body).y, std::max(apex, r) + 1e-9) << "mode " << static_cast<int>(mode);
    }
  }
}

}  // namespace
