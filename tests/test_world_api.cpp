// World API tests: determinism of the state hash, rejection of every invalid input (with the world left
// unchanged), handles, mass and collision filters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
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
using rattle::Error;
using rattle::Filter;
using rattle::Point;
using rattle::Polygon;
using rattle::Polyline;
using rattle::Segment;
using rattle::WorldDef;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ------------------------------------------------------------------------------------------------
// Determinism.

std::vector<Disk> buildGas(World& world, uint64_t seed) {
  makeClosedBox(world, 0, 0, 30, 30, 0.5);
  RandomDiskOptions o;
  o.count = 200;
  o.seed = seed;
  o.xmin = 0;
  o.ymin = 0;
  o.xmax = 30;
  o.ymax = 30;
  o.minRadius = 0.3;
  o.maxRadius = 0.7;
  o.minDensity = 0.5;
  o.maxDensity = 2;
  o.minSpeed = 1;
  o.maxSpeed = 6;
  o.minRestitution = 0.3;
  o.maxRestitution = 1;
  return addDisks(world, randomDisks(o));
}

bool sameEvent(const ContactEvent& a, const ContactEvent& b) {
  return a.time == b.time && a.fixtureA == b.fixtureA && a.fixtureB == b.fixtureB && a.bodyA == b.bodyA &&
         a.bodyB == b.bodyB && a.point == b.point && a.normal == b.normal && a.impulse == b.impulse;
}

TEST(WorldDeterminism, SameSceneGivesSameHashAfterEveryStep) {
  World a, b;
  const auto disksA = buildGas(a, 77);
  const auto disksB = buildGas(b, 77);
  ASSERT_EQ(a.stateHash(), b.stateHash());
  long long events = 0;
  for (int step = 0; step < 200; ++step) {
    a.step(1.0 / 60.0);
    b.step(1.0 / 60.0);
    ASSERT_EQ(a.stateHash(), b.stateHash()) << "diverged at step " << step;
    const auto ea = a.contactEvents(), eb = b.contactEvents();
    ASSERT_EQ(ea.size(), eb.size()) << "at step " << step;
    for (size_t i = 0; i < ea.size(); ++i) ASSERT_TRUE(sameEvent(ea[i], eb[i])) << "step " << step << " event " << i;
    events += static_cast<long long>(ea.size());
  }
  EXPECT_GT(events, 200);  // the scene does collide
  EXPECT_EQ(a.time(), b.time());
  // A different scene hashes differently.
  World c;
  buildGas(c, 78);
  EXPECT_NE(c.stateHash(), World().stateHash());
  World d;
  buildGas(d, 77);
  EXPECT_NE(c.stateHash(), d.stateHash());
}

TEST(WorldDeterminism, OneBitChangesTheHash) {
  World world;
  const auto disks = buildGas(world, 5);
  world.step(0.1);
  const uint64_t h0 = world.stateHash();
  EXPECT_EQ(world.stateHash(), h0);  // reading does not change it
  const BodyId body = disks[17].body;
  const Vec2 v = world.velocity(body), p = world.position(body);

  world.setVelocity(body, {std::nextafter(v.x, kInf), v.y});
  EXPECT_NE(world.stateHash(), h0) << "one bit of velocity.x";
  world.setVelocity(body, v);
  EXPECT_EQ(world.stateHash(), h0);

  world.setVelocity(body, {v.x, std::nextafter(v.y, -kInf)});
  EXPECT_NE(world.stateHash(), h0) << "one bit of velocity.y";
  world.setVelocity(body, v);

  world.setPosition(body, {p.x, std::nextafter(p.y, kInf)});
  EXPECT_NE(world.stateHash(), h0) << "one bit of position.y";
  world.setPosition(body, p);
  EXPECT_EQ(world.stateHash(), h0);

  // The sign of zero is a bit too (if the world keeps it).
  const BodyId still = world.createBody(bodyDef(BodyType::Kinematic));
  const uint64_t h1 = world.stateHash();
  EXPECT_NE(h1, h0);
  world.setVelocity(still, {-0.0, 0.0});
  if (std::signbit(world.velocity(still).x)) {
    EXPECT_NE(world.stateHash(), h1) << "velocity -0.0 vs +0.0";
  }
  world.setVelocity(still, {0.0, 0.0});
  EXPECT_EQ(world.stateHash(), h1);

  // Time is part of the state.
  World empty, later;
  later.step(0.5);
  EXPECT_NE(empty.stateHash(), later.stateHash());
  EXPECT_EQ(later.time(), 0.5);
}

// ------------------------------------------------------------------------------------------------
// Invalid input.

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Everything observable about the world that invalid input must not change.
struct Snapshot {
  uint64_t hash = 0;
  int bodyCount = 0;
  double time = 0;
  std::vector<std::vector<FixtureId>> fixtures;
  std::vector<double> densities, restitutions, masses;
  std::vector<Vec2> positions, velocities;
  bool operator==(const Snapshot&) const = default;
};

Snapshot snapshot(const World& w, const std::vector<BodyId>& bodies) {
  Snapshot s;
  s.hash = w.stateHash();
  s.bodyCount = w.bodyCount();
  s.time = w.time();
  for (BodyId b : bodies) {
    s.fixtures.push_back(w.fixtures(b));
    s.masses.push_back(w.mass(b));
    s.positions.push_back(w.position(b));
    s.velocities.push_back(w.velocity(b));
    for (FixtureId f : s.fixtures.back()) {
      s.densities.push_back(w.density(f));
      s.restitutions.push_back(w.restitution(f));
    }
  }
  return s;
}

/// Runs `op`, which must throw rattle::Error whose message contains every token (case-insensitive), and
/// checks that the world is unchanged.
void expectRejected(const std::string& what, World& world, const std::vector<BodyId>& bodies,
                    const std::function<void()>& op, const std::vector<std::string>& tokens) {
  SCOPED_TRACE(what);
  const Snapshot before = snapshot(world, bodies);
  try {
    op();
    ADD_FAILURE() << "accepted: " << what;
  } catch (const Error& e) {
    const std::string message = lower(e.what());
    for (const std::string& token : tokens)
      EXPECT_NE(message.find(lower(token)), std::string::npos)
          << "message \"" << e.what() << "\" does not name \"" << token << "\"";
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than rattle::Error: " << e.what();
  }
  const Snapshot after = snapshot(world, bodies);
  EXPECT_TRUE(before == after) << "the world changed";
}

FixtureDef fixtureOf(rattle::Geometry g, double density = 1.0, double restitution = 0.0) {
  FixtureDef fd;
  fd.geometry = std::move(g);
  fd.density = density;
  fd.restitution = restitution;
  return fd;
}

/// The valid scene both worlds of the invalid-input test are built from.
struct ApiScene {
  BodyId walls, disk, kinematic;
  FixtureId diskFixture, wallFixture;
  std::vector<BodyId> bodies() const { return {walls, disk, kinematic}; }
};

ApiScene buildApiScene(World& w) {
  ApiScene s;
  s.walls = w.createBody(bodyDef(BodyType::Static));
  s.wallFixture = w.createFixture(s.walls, fixtureOf(Segment{{-10, -5}, {10, -5}}));
  w.createFixture(s.walls, fixtureOf(Polygon{{{20, 0}, {24, 0}, {24, 4}, {20, 4}}}));
  s.disk = w.createBody(bodyDef(BodyType::Dynamic, Vec2{0, 0}, Vec2{1, -2}));
  s.diskFixture = w.createFixture(s.disk, fixtureOf(Circle{{0, 0}, 0.5}, 2.0, 0.5));
  s.kinematic = w.createBody(bodyDef(BodyType::Kinematic, Vec2{-20, 0}, Vec2{0.5, 0}));
  w.createFixture(s.kinematic, fixtureOf(Polyline{{{0, 0}, {1, 1}, {2, 0}}}));
  return s;
}

TEST(WorldInvalidInput, EveryInvalidDefinitionIsRejectedAndLeavesTheWorldUnchanged) {
  World world;
  const ApiScene scene = buildApiScene(world);
  world.step(0.25);
  const auto bodies = scene.bodies();
  auto reject = [&](const std::string& what, const std::function<void()>& op,
                    const std::vector<std::string>& tokens) { expectRejected(what, world, bodies, op, tokens); };
  auto dynamicBody = [](Vec2 p, Vec2 v) { return bodyDef(BodyType::Dynamic, p, v); };

  // Body definitions.
  reject("position NaN", [&] { world.createBody(dynamicBody({kNaN, 0}, {0, 0})); }, {"position", "nan"});
  reject("position inf", [&] { world.createBody(dynamicBody({0, kInf}, {0, 0})); }, {"position", "inf"});
  reject("static position -inf", [&] { world.createBody(bodyDef(BodyType::Static, Vec2{-kInf, 1})); }, {"position", "inf"});
  reject("velocity NaN", [&] { world.createBody(dynamicBody({0, 0}, {kNaN, 0})); }, {"velocity", "nan"});
  reject("velocity -inf", [&] { world.createBody(dynamicBody({0, 0}, {0, -kInf})); }, {"velocity", "inf"});
  reject("kinematic velocity inf",
         [&] { world.createBody(bodyDef(BodyType::Kinematic, Vec2{}, Vec2{kInf, 0})); }, {"velocity", "inf"});

  // Geometry, on a static body (which accepts every kind).
  const BodyId st = scene.walls;
  auto onStatic = [&](rattle::Geometry g) { return [&world, st, g] { world.createFixture(st, fixtureOf(g)); }; };
  reject("circle centre NaN", onStatic(Circle{{kNaN, 0}, 1}), {"cent", "nan"});
  reject("circle radius negative", onStatic(Circle{{0, 0}, -2.75}), {"radius", "-2.75"});
  reject("circle radius NaN", onStatic(Circle{{0, 0}, kNaN}), {"radius", "nan"});
  reject("circle radius inf", onStatic(Circle{{0, 0}, kInf}), {"radius", "inf"});
  reject("point inf", onStatic(Point{{kInf, 2}}), {"point", "inf"});
  reject("segment NaN", onStatic(Segment{{0, 0}, {kNaN, 1}}), {"segment", "nan"});
  reject("segment inf", onStatic(Segment{{-kInf, 0}, {1, 1}}), {"segment", "inf"});
  reject("segment zero length", onStatic(Segment{{3.25, -7.5}, {3.25, -7.5}}), {"segment", "3.25", "-7.5"});
  reject("polyline empty", onStatic(Polyline{}), {"polyline", "points"});
  reject("polyline one point", onStatic(Polyline{{{1, 2}}}), {"polyline", "points"});
  reject("polyline repeated point", onStatic(Polyline{{{0, 0}, {1.5, 2.5}, {1.5, 2.5}, {4, 0}}}),
         {"polyline", "1.5", "2.5"});
  reject("polyline two equal points", onStatic(Polyline{{{1.5, 2.5}, {1.5, 2.5}}}), {"polyline", "1.5"});
  reject("polyline NaN", onStatic(Polyline{{{0, 0}, {1, kNaN}, {4, 0}}}), {"polyline", "nan"});
  reject("polyline inf", onStatic(Polyline{{{0, 0}, {kInf, 1}}}), {"polyline", "inf"});
  reject("polygon two points", onStatic(Polygon{{{0, 0}, {1, 0}}}), {"polygon", "points"});
  reject("polygon empty", onStatic(Polygon{}), {"polygon", "points"});
  reject("polygon collinear", onStatic(Polygon{{{0, 0}, {1, 1}, {2, 2}}}), {"polygon"});
  reject("polygon three consecutive on a line", onStatic(Polygon{{{0, 0}, {1, 0}, {2, 0}, {2, 2}, {0, 2}}}),
         {"polygon"});
  reject("polygon repeated point", onStatic(Polygon{{{0, 0}, {2, 0}, {2, 0}, {0, 2}}}), {"polygon"});
  reject("polygon non-convex", onStatic(Polygon{{{0, 0}, {4, 0}, {4, 4}, {2, 1.5}, {0, 4}}}), {"polygon"});
  reject("polygon self-intersecting", onStatic(Polygon{{{0, 0}, {2, 2}, {2, 0}, {0, 2}}}), {"polygon"});
  {
    // A pentagram: every turn goes the same way, but it winds twice and crosses itself.
    std::vector<Vec2> star;
    for (int k : {0, 2, 4, 1, 3}) {
      const double angle = std::numbers::pi / 2 + 2 * std::numbers::pi * k / 5;
      star.push_back({std::cos(angle), std::sin(angle)});
    }
    reject("polygon pentagram", onStatic(Polygon{star}), {"polygon"});
  }
  reject("polygon NaN", onStatic(Polygon{{{0, 0}, {1, 0}, {kNaN, 1}}}), {"polygon", "nan"});
  reject("polygon inf", onStatic(Polygon{{{0, 0}, {kInf, 0}, {1, 1}}}), {"polygon", "inf"});

  // Fixture values.
  const BodyId dyn = scene.disk;
  auto onDynamic = [&](FixtureDef fd) { return [&world, dyn, fd] { world.createFixture(dyn, fd); }; };
  reject("dynamic density 0", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, 0.0)), {"density", "0"});
  reject("dynamic density negative", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, -0.375)), {"density", "-0.375"});
  reject("dynamic density NaN", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, kNaN)), {"density", "nan"});
  reject("dynamic density inf", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, kInf)), {"density", "inf"});
  reject("restitution negative", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, 1, -0.25)), {"restitution", "-0.25"});
  reject("restitution above 1", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, 1, 1.625)), {"restitution", "1.625"});
  reject("restitution NaN", onDynamic(fixtureOf(Circle{{0, 0}, 0.25}, 1, kNaN)), {"restitution", "nan"});
  reject("static restitution above 1", [&] { world.createFixture(st, fixtureOf(Circle{{5, 5}, 1}, 1, 1.625)); },
         {"restitution", "1.625"});
  reject("dynamic segment", onDynamic(fixtureOf(Segment{{0, 0}, {1, 0}})), {"segment"});
  reject("dynamic polygon", onDynamic(fixtureOf(Polygon{{{0, 0}, {1, 0}, {0, 1}}})), {"polygon"});
  reject("dynamic polyline", onDynamic(fixtureOf(Polyline{{{0, 0}, {1, 0}}})), {"polyline"});
  reject("dynamic second circle off centre", onDynamic(fixtureOf(Circle{{0.5, 0}, 0.25})), {"cent", "0.5"});
  reject("dynamic second circle off centre in y", onDynamic(fixtureOf(Circle{{0, -0.75}, 2})), {"cent", "-0.75"});
  reject("dynamic point off centre", onDynamic(fixtureOf(Point{{0.5, 0.5}})), {"0.5"});
  reject("fixture on a null body", [&] { world.createFixture(BodyId{}, fixtureOf(Circle{})); }, {});

  // Setters.
  reject("setVelocity NaN", [&] { world.setVelocity(dyn, {kNaN, 0}); }, {"velocity", "nan"});
  reject("setVelocity inf", [&] { world.setVelocity(dyn, {0, kInf}); }, {"velocity", "inf"});
  reject("setVelocity on static", [&] { world.setVelocity(st, {1.5, 0}); }, {"velocity", "1.5"});
  reject("setPosition NaN", [&] { world.setPosition(dyn, {0, kNaN}); }, {"position", "nan"});
  reject("setPosition inf", [&] { world.setPosition(scene.kinematic, {-kInf, 0}); }, {"position", "inf"});
  reject("setRestitution above 1", [&] { world.setRestitution(scene.diskFixture, 1.625); }, {"restitution", "1.625"});
  reject("setRestitution negative", [&] { world.setRestitution(scene.wallFixture, -0.25); }, {"restitution", "-0.25"});
  reject("setRestitution NaN", [&] { world.setRestitution(scene.diskFixture, kNaN); }, {"restitution", "nan"});
  reject("setDensity 0 on dynamic", [&] { world.setDensity(scene.diskFixture, 0.0); }, {"density", "0"});
  reject("setDensity negative", [&] { world.setDensity(scene.diskFixture, -0.375); }, {"density", "-0.375"});
  reject("setDensity NaN", [&] { world.setDensity(scene.diskFixture, kNaN); }, {"density", "nan"});

  // Steps.
  reject("step NaN", [&] { world.step(kNaN); }, {"dt", "nan"});
  reject("step -1", [&] { world.step(-1.0); }, {"dt", "-1"});
  reject("step inf", [&] { world.step(kInf); }, {"dt", "inf"});
  reject("step -0.375", [&] { world.step(-0.375); }, {"dt", "-0.375"});

  // World definitions.
  for (int budget : {0, -5}) {
    try {
      World bad(worldDefWithBudget(budget));
      ADD_FAILURE() << "maxEventsPerStep = " << budget << " accepted";
    } catch (const Error& e) {
      const std::string message = lower(e.what());
      EXPECT_NE(message.find("maxeventsperstep"), std::string::npos) << e.what();
      EXPECT_NE(message.find(std::to_string(budget)), std::string::npos) << e.what();
    }
  }

  // Nothing of all that left a trace: a twin world built from valid input alone behaves identically.
  World twin;
  const ApiScene twinScene = buildApiScene(twin);
  twin.step(0.25);
  EXPECT_EQ(world.stateHash(), twin.stateHash());
  const BodyId nb = world.createBody(dynamicBody({3, 3}, {-1, 0}));
  const BodyId tb = twin.createBody(dynamicBody({3, 3}, {-1, 0}));
  EXPECT_EQ(nb, tb);
  const FixtureId nf = world.createFixture(nb, fixtureOf(Circle{{0, 0}, 0.5}));
  const FixtureId tf = twin.createFixture(tb, fixtureOf(Circle{{0, 0}, 0.5}));
  EXPECT_EQ(nf, tf);
  for (int i = 0; i < 20; ++i) {
    world.step(0.1);
    twin.step(0.1);
    ASSERT_EQ(world.stateHash(), twin.stateHash()) << "step " << i;
  }
  (void)twinScene;
}

TEST(WorldInvalidInput, BoundaryValuesAreAccepted) {
  World world;
  const BodyId st = world.createBody(bodyDef(BodyType::Static));
  EXPECT_NO_THROW(world.setVelocity(st, {0, 0}));
  EXPECT_NO_THROW(world.createFixture(st, fixtureOf(Circle{{1, 1}, 0.0})));  // radius 0 behaves as a point
  EXPECT_NO_THROW(world.createFixture(st, fixtureOf(Polyline{{{0, 0}, {1, 0}, {0, 0}}})));  // revisits a point
  const BodyId dyn = world.createBody(bodyDef(BodyType::Dynamic));
  FixtureId f;
  EXPECT_NO_THROW(f = world.createFixture(dyn, fixtureOf(Circle{{0.25, 0}, 0.5}, 1e-300, 1.0)));
  EXPECT_NO_THROW(world.createFixture(dyn, fixtureOf(Circle{{0.25, 0}, 2.0}, 1.0, 0.0)));  // same centre
  EXPECT_NO_THROW(world.createFixture(dyn, fixtureOf(Point{{0.25, 0}})));                   // same centre
  EXPECT_NO_THROW(world.setRestitution(f, 0.0));
  EXPECT_NO_THROW(world.setRestitution(f, 1.0));
  EXPECT_EQ(world.restitution(f), 1.0);
  EXPECT_NO_THROW(world.step(0.0));
  EXPECT_EQ(world.time(), 0.0);
  // Polygons are stored counter-clockwise whichever way they were given.
  const FixtureId cw = world.createFixture(st, fixtureOf(Polygon{{{0, 0}, {0, 1}, {1, 1}, {1, 0}}}));
  const auto& stored = std::get<Polygon>(world.geometry(cw)).points;
  ASSERT_EQ(stored.size(), 4u);
  double area2 = 0;
  for (size_t i = 0; i < stored.size(); ++i) area2 += rattle::cross(stored[i], stored[(i + 1) % stored.size()]);
  EXPECT_GT(area2, 0);
}

TEST(WorldInvalidInput, StaticBodyDefVelocityIsRejected) {
  // types.h: BodyDef::velocity "must be zero for a static body".
  World world;
  const uint64_t before = world.stateHash();
  try {
    world.createBody(bodyDef(BodyType::Static, Vec2{1, 2}, Vec2{3, 4}));
    ADD_FAILURE() << "a static body with a velocity was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("BodyDef.velocity"), std::string::npos) << message;
    EXPECT_NE(message.find("(3, 4)"), std::string::npos) << message;
  }
  EXPECT_EQ(world.bodyCount(), 0);
  EXPECT_EQ(world.stateHash(), before);
}

// ------------------------------------------------------------------------------------------------
// Handles.

void expectBodyHandleRejected(World& world, BodyId id) {
  SCOPED_TRACE("body {" + std::to_string(id.index) + ", " + std::to_string(id.generation) + "}");
  EXPECT_FALSE(world.isValid(id));
  EXPECT_THROW(world.type(id), Error);
  EXPECT_THROW(world.position(id), Error);
  EXPECT_THROW(world.velocity(id), Error);
  EXPECT_THROW(world.mass(id), Error);
  EXPECT_THROW(world.isAsleep(id), Error);
  EXPECT_THROW(world.wake(id), Error);
  EXPECT_THROW(world.userData(id), Error);
  EXPECT_THROW(world.fixtures(id), Error);
  EXPECT_THROW(world.setPosition(id, {1, 1}), Error);
  EXPECT_THROW(world.setVelocity(id, {0, 0}), Error);
  EXPECT_THROW(world.createFixture(id, FixtureDef{}), Error);
  EXPECT_THROW(world.destroyBody(id), Error);
}

void expectFixtureHandleRejected(World& world, FixtureId id) {
  SCOPED_TRACE("fixture {" + std::to_string(id.index) + ", " + std::to_string(id.generation) + "}");
  EXPECT_FALSE(world.isValid(id));
  EXPECT_THROW(world.body(id), Error);
  EXPECT_THROW(world.geometry(id), Error);
  EXPECT_THROW(world.density(id), Error);
  EXPECT_THROW(world.restitution(id), Error);
  EXPECT_THROW(world.isSensor(id), Error);
  EXPECT_THROW(world.filter(id), Error);
  EXPECT_THROW(world.setDensity(id, 1.0), Error);
  EXPECT_THROW(world.setRestitution(id, 0.5), Error);
  EXPECT_THROW(world.setFilter(id, Filter{}), Error);
  EXPECT_THROW(world.destroyFixture(id), Error);
}

TEST(WorldHandles, DestroyedNullAndForeignHandlesAreRejected) {
  World world;
  const BodyId a = world.createBody(bodyDef(BodyType::Dynamic, Vec2{1, 2}, Vec2{}, 42));
  const FixtureId fa = world.createFixture(a, fixtureOf(Circle{{0, 0}, 0.5}));
  const BodyId b = world.createBody(bodyDef(BodyType::Static));
  const FixtureId fb = world.createFixture(b, fixtureOf(Segment{{0, 0}, {1, 0}}));
  EXPECT_FALSE(a.isNull());
  EXPECT_TRUE(world.isValid(a));
  EXPECT_TRUE(world.isValid(fa));
  EXPECT_EQ(world.userData(a), 42u);
  EXPECT_EQ(world.body(fa), a);
  EXPECT_EQ(world.bodyCount(), 2);

  world.destroyBody(a);
  EXPECT_EQ(world.bodyCount(), 1);
  expectBodyHandleRejected(world, a);
  expectFixtureHandleRejected(world, fa);  // the body's fixtures went with it
  EXPECT_TRUE(world.isValid(b));
  EXPECT_TRUE(world.isValid(fb));
  EXPECT_NO_THROW(world.step(0.1));

  // Slot reuse: same index, new generation; the old handle stays dead.
  const BodyId c = world.createBody(bodyDef(BodyType::Kinematic, Vec2{}, Vec2{}, 7));
  EXPECT_EQ(c.index, a.index);
  EXPECT_NE(c.generation, a.generation);
  EXPECT_FALSE(c.isNull());
  EXPECT_TRUE(world.isValid(c));
  EXPECT_EQ(world.userData(c), 7u);
  expectBodyHandleRejected(world, a);
  const FixtureId fc = world.createFixture(c, fixtureOf(Circle{{0, 0}, 1}));
  EXPECT_EQ(fc.index, fa.index);
  EXPECT_NE(fc.generation, fa.generation);
  expectFixtureHandleRejected(world, fa);
  EXPECT_EQ(world.body(fc), c);

  // Null handles.
  expectBodyHandleRejected(world, BodyId{});
  expectFixtureHandleRejected(world, FixtureId{});
  EXPECT_TRUE(BodyId{}.isNull());
  // A slot that never existed, and a live slot with a wrong generation.
  expectBodyHandleRejected(world, BodyId{123456, 1});
  expectFixtureHandleRejected(world, FixtureId{123456, 1});
  expectBodyHandleRejected(world, BodyId{b.index, b.generation + 1});
  expectFixtureHandleRejected(world, FixtureId{fb.index, fb.generation + 1});

  // Destroying a fixture alone.
  world.destroyFixture(fc);
  expectFixtureHandleRejected(world, fc);
  EXPECT_TRUE(world.isValid(c));
  EXPECT_TRUE(world.fixtures(c).empty());

  // Latest freed first.
  const BodyId d = world.createBody(bodyDef(BodyType::Static));
  const BodyId e = world.createBody(bodyDef(BodyType::Static));
  world.destroyBody(d);
  world.destroyBody(e);
  const BodyId e2 = world.createBody(bodyDef(BodyType::Static));
  const BodyId d2 = world.createBody(bodyDef(BodyType::Static));
  EXPECT_EQ(e2.index, e.index);
  EXPECT_EQ(d2.index, d.index);
  EXPECT_NE(e2, e);
  EXPECT_NE(d2, d);
  EXPECT_EQ(world.bodyCount(), 4);
}

// ------------------------------------------------------------------------------------------------
// Mass.

TEST(WorldMass, DensityTimesAreaPointsOneStaticInfinite) {
  const double pi = std::numbers::pi;
  World world;
  auto near = [](double actual, double expected) { EXPECT_NEAR(actual, expected, 1e-14 * expected); };

  const BodyId a = world.createBody(bodyDef(BodyType::Dynamic));
  const FixtureId fa = world.createFixture(a, fixtureOf(Circle{{0, 0}, 1.5}, 2.0));
  near(world.mass(a), 2.0 * pi * 2.25);
  world.setDensity(fa, 0.5);
  near(world.mass(a), 0.5 * pi * 2.25);
  // A second concentric circle adds its mass; a sensor adds nothing.
  const FixtureId fa2 = world.createFixture(a, fixtureOf(Circle{{0, 0}, 0.5}, 4.0));
  near(world.mass(a), 0.5 * pi * 2.25 + 4.0 * pi * 0.25);
  FixtureDef sensor = fixtureOf(Circle{{0, 0}, 5.0}, 3.0);
  sensor.sensor = true;
  const FixtureId fs = world.createFixture(a, sensor);
  EXPECT_TRUE(world.isSensor(fs));
  near(world.mass(a), 0.5 * pi * 2.25 + 4.0 * pi * 0.25);
  world.destroyFixture(fa2);
  near(world.mass(a), 0.5 * pi * 2.25);

  // Off-centre circle on its own body: the offset does not change the mass.
  const BodyId off = world.createBody(bodyDef(BodyType::Dynamic));
  world.createFixture(off, fixtureOf(Circle{{3, -4}, 0.75}, 1.25));
  near(world.mass(off), 1.25 * pi * 0.5625);

  // Points only: mass 1.
  const BodyId p = world.createBody(bodyDef(BodyType::Dynamic));
  world.createFixture(p, fixtureOf(Point{{0, 0}}, 7.0));
  EXPECT_EQ(world.mass(p), 1.0);
  world.createFixture(p, fixtureOf(Point{{0, 0}}, 3.0));
  EXPECT_EQ(world.mass(p), 1.0);
  // A point and a circle: the circle's mass.
  world.createFixture(p, fixtureOf(Circle{{0, 0}, 0.5}, 3.0));
  near(world.mass(p), 3.0 * pi * 0.25);

  // Static and kinematic bodies have infinite mass.
  const BodyId s = world.createBody(bodyDef(BodyType::Static));
  world.createFixture(s, fixtureOf(Circle{{0, 0}, 1}, 5.0));
  world.createFixture(s, fixtureOf(Polygon{{{0, 0}, {1, 0}, {0, 1}}}, 5.0));
  EXPECT_EQ(world.mass(s), std::numeric_limits<double>::infinity());
  const BodyId k = world.createBody(bodyDef(BodyType::Kinematic));
  world.createFixture(k, fixtureOf(Circle{{0, 0}, 1}, 5.0));
  EXPECT_EQ(world.mass(k), std::numeric_limits<double>::infinity());
  EXPECT_EQ(world.type(s), BodyType::Static);
  EXPECT_EQ(world.type(k), BodyType::Kinematic);
  EXPECT_EQ(world.type(a), BodyType::Dynamic);
}

// ------------------------------------------------------------------------------------------------
// Collision filters.

/// Two disks of radius 0.5 approaching head-on; they touch at t = 1 when they collide. Returns the number
/// of contacts over a step of 2 s; checks the free flight when there are none.
int headOnContacts(const Filter& fa, const Filter& fb) {
  World world;
  const Disk a = addDisk(world, {{0, 0}, {1, 0}, 0.5, 1.0, 1.0});
  const Disk b = addDisk(world, {{3, 0}, {-1, 0}, 0.5, 1.0, 1.0});
  world.setFilter(a.fixture, fa);
  world.setFilter(b.fixture, fb);
  EXPECT_EQ(world.filter(a.fixture).group, fa.group);
  EXPECT_EQ(world.filter(b.fixture).maskBits, fb.maskBits);
  world.step(2.0);
  const int n = static_cast<int>(world.contactEvents().size());
  if (n == 0) {
    EXPECT_EQ(world.position(a.body), (Vec2{2, 0}));
    EXPECT_EQ(world.position(b.body), (Vec2{1, 0}));
  } else {
    EXPECT_NEAR(world.position(a.body).x, 0, 1e-12);  // exchanged velocities
    EXPECT_NEAR(world.position(b.body).x, 3, 1e-12);
  }
  return n;
}

TEST(WorldFilter, CategoryMaskAndGroupDecideWhoCollides) {
  const Filter plain{};
  EXPECT_EQ(headOnContacts(plain, plain), 1);
  // Category not in the other's mask, either way round.
  EXPECT_EQ(headOnContacts(filterOf(0x2), filterOf(0x1, ~0x2u)), 0);
  EXPECT_EQ(headOnContacts(filterOf(0x1, ~0x2u), filterOf(0x2)), 0);
  EXPECT_EQ(headOnContacts(filterOf(0x1, 0x4), plain), 0);
  EXPECT_EQ(headOnContacts(filterOf(0x4, 0x8), filterOf(0x8, 0x4)), 1);
  EXPECT_EQ(headOnContacts(filterOf(0), plain), 0);
  // Same nonzero group: never.
  EXPECT_EQ(headOnContacts(filterOf(1, ~0u, 7), filterOf(1, ~0u, 7)), 0);
  EXPECT_EQ(headOnContacts(filterOf(1, ~0u, -3), filterOf(1, ~0u, -3)), 0);
  // Different groups, or one in no group: they collide.
  EXPECT_EQ(headOnContacts(filterOf(1, ~0u, 7), filterOf(1, ~0u, 8)), 1);
  EXPECT_EQ(headOnContacts(filterOf(1, ~0u, 7), filterOf(1, ~0u, 0)), 1);
  EXPECT_EQ(headOnContacts(filterOf(1, ~0u, -3), filterOf(1, ~0u, 3)), 1);
  // A different group does not override the mask.
  EXPECT_EQ(headOnContacts(filterOf(0x2, ~0u, 1), filterOf(0x1, 0x1, 2)), 0);
}

TEST(WorldFilter, FilteredDiskPassesThroughWall) {
  World world;
  const BodyId wall = world.createBody(bodyDef(BodyType::Static));
  FixtureDef wd = fixtureOf(Segment{{5, -10}, {5, 10}});
  wd.filter = filterOf(0x4);
  world.createFixture(wall, wd);
  const Disk ghost = addDisk(world, {{0, 0}, {10, 0}, 0.5, 1.0, 1.0});
  world.setFilter(ghost.fixture, filterOf(0x1, ~0x4u));
  const Disk solid = addDisk(world, {{0, 3}, {10, 0}, 0.5, 1.0, 1.0});
  world.step(1.0);
  ASSERT_EQ(world.contactEvents().size(), 1u);
  EXPECT_EQ(world.contactEvents()[0].bodyB, solid.body);
  EXPECT_EQ(world.position(ghost.body), (Vec2{10, 0}));
  EXPECT_NEAR(world.position(solid.body).x, 4.5 - 5.5, 1e-12);
  // Changing the filter mid-run takes effect at the next step.
  world.setFilter(ghost.fixture, Filter{});
  world.setVelocity(ghost.body, {-10, 0});
  world.step(1.0);
  ASSERT_EQ(world.contactEvents().size(), 1u);
  EXPECT_EQ(world.contactEvents()[0].bodyB, ghost.body);
  EXPECT_NEAR(world.position(ghost.body).x, 5.5 + 5.5, 1e-12);
}

}  // namespace
