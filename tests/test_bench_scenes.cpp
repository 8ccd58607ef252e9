// The benchmark's shared scenes (scenes/scenes.h, suite BenchScenes): what each scene promises about its
// start (the packing fraction asked for, no disk overlapping another or a wall, speeds as stated, valid
// geometry), that one seed gives one scene bit for bit, and that bad parameters are refused with a message
// naming them. Checked by brute force against the scene's own numbers, not against the scene code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "rattle/geometry.h"
#include "rattle/world.h"
#include "scenes.h"

namespace {

using rattle_bench::buildScene;
using rattle_bench::Scene;
using rattle_bench::SceneError;
using rattle_bench::SceneParams;
using rattle_bench::Vec2;

SceneParams params(const std::string& name, int n, uint64_t seed = 1, double packing = std::nan(""),
                   double speed = std::nan("")) {
  SceneParams p;
  p.name = name;
  p.n = n;
  p.seed = seed;
  p.packing = packing;
  p.speed = speed;
  return p;
}

double distanceToSegment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double t = std::clamp(rattle::dot(p - a, ab) / rattle::dot(ab, ab), 0.0, 1.0);
  return rattle::length(p - (a + t * ab));
}

// Every disk inside the container and clear of every wall; no two disks that collide overlapping or touching.
void expectValidStart(const Scene& s) {
  for (size_t i = 0; i < s.disks.size(); ++i) {
    const rattle_bench::DiskStart& d = s.disks[i];
    ASSERT_GT(d.radius, 0);
    ASSERT_TRUE(d.position.x - d.radius > s.bounds.min.x && d.position.x + d.radius < s.bounds.max.x &&
                d.position.y - d.radius > s.bounds.min.y && d.position.y + d.radius < s.bounds.max.y)
        << s.name << ": disk " << i << " not inside the container";
    for (const rattle_bench::Wall& w : s.walls)
      ASSERT_GT(distanceToSegment(d.position, w.a, w.b), d.radius) << s.name << ": disk " << i << " touches a wall";
  }
  if (!s.disksCollide) return;
  size_t touching = 0;
  for (size_t i = 0; i < s.disks.size(); ++i)
    for (size_t j = i + 1; j < s.disks.size(); ++j) {
      const double gap = rattle::length(s.disks[i].position - s.disks[j].position) - s.disks[i].radius -
                         s.disks[j].radius;
      // The cradle's rows touch exactly (centres 1 apart, radius 0.5: a gap of exactly 0); nothing overlaps.
      ASSERT_GE(gap, 0.0) << s.name << ": disks " << i << " and " << j << " overlap";
      if (gap == 0) ++touching;
    }
  if (s.name != "cradle") {
    EXPECT_EQ(touching, 0u) << s.name;
  }
}

TEST(BenchScenes, EveryScenesStartIsValid) {
  for (const std::string& name : rattle_bench::sceneNames()) {
    SCOPED_TRACE(name);
    const Scene s = buildScene(params(name, rattle_bench::defaultDiskCount(name)));
    EXPECT_EQ(s.name, name);
    EXPECT_EQ(static_cast<int>(s.disks.size()), rattle_bench::defaultDiskCount(name));
    expectValidStart(s);
    for (const rattle_bench::SensorStrip& st : s.sensors) {
      const rattle::Geometry g = rattle::Polygon{st.points};
      EXPECT_FALSE(rattle::validationError(g).has_value());
      EXPECT_GT(rattle::areaOf(g), 0.0);
    }
  }
}

TEST(BenchScenes, GasHasThePackingFractionAskedForAndNoOverlapsEvenAt06) {
  for (int n : {1, 7, 100, 2000, 10000})
    for (double packing : {0.1, 0.3, 0.5, 0.6}) {
      SCOPED_TRACE("n " + std::to_string(n) + ", packing " + std::to_string(packing));
      const Scene s = buildScene(params("gas", n, 3, packing));
      const Vec2 size = s.bounds.max - s.bounds.min;
      double area = 0;
      for (const auto& d : s.disks) area += std::numbers::pi * d.radius * d.radius;
      EXPECT_NEAR(area / (size.x * size.y), packing, 1e-12 * packing);
      EXPECT_DOUBLE_EQ(s.packing, packing);
      if (n <= 2000 || packing == 0.6) expectValidStart(s);
    }
}

TEST(BenchScenes, SpeedsAreAsStated) {
  const Scene gas = buildScene(params("gas", 500, 1, 0.3, 2.5));
  for (const auto& d : gas.disks) EXPECT_NEAR(rattle::length(d.velocity), 2.5, 1e-14);
  const Scene bullets = buildScene(params("bullets", 8));
  for (size_t i = 0; i < bullets.disks.size(); ++i)
    EXPECT_NEAR(rattle::length(bullets.disks[i].velocity), std::pow(10.0, 1 + static_cast<int>(i % 4)), 1e-9);
  const Scene sensors = buildScene(params("sensors", 100));
  for (const auto& d : sensors.disks) {
    EXPECT_GE(rattle::length(d.velocity), 10.0 - 1e-12);
    EXPECT_LE(rattle::length(d.velocity), 40.0 + 1e-12);
  }
  const Scene cradle = buildScene(params("cradle", 12));
  for (size_t i = 0; i < cradle.disks.size(); ++i) {
    EXPECT_EQ(cradle.disks[i].velocity.y, 0.0);
    if (i % 6 != 0) {
      EXPECT_EQ(cradle.disks[i].velocity.x, 0.0) << "only the striker moves";
    }
  }
}

TEST(BenchScenes, OneSeedGivesOneSceneBitForBit) {
  for (const std::string& name : rattle_bench::sceneNames()) {
    SCOPED_TRACE(name);
    const int n = name == "cradle" ? 60 : 300;  // (crowd: 300 disks)
    const uint64_t a = rattle_bench::sceneHash(buildScene(params(name, n, 42)));
    EXPECT_EQ(a, rattle_bench::sceneHash(buildScene(params(name, n, 42))));
    EXPECT_NE(a, rattle_bench::sceneHash(buildScene(params(name, n, 43))));
  }
  // The same scene on every build: the generator, the placement and the directions use no std
  // distribution and no libm function but sqrt. If this changes, every benchmark result changes with it.
  const uint64_t gas = rattle_bench::sceneHash(buildScene(params("gas", 100, 1)));
  EXPECT_EQ(gas, 0x7ebe0577d88fb1eaull) << "gas, 100 disks, seed 1: hash 0x" << std::hex << gas;
}

TEST(BenchScenes, BadParametersAreRefusedNamingThem) {
  auto message = [](const SceneParams& p) {
    try {
      buildScene(p);
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message(params("cradle", 50)).find("--n 50"), std::string::npos);
  EXPECT_NE(message(params("gas", 100, 1, 0.95)).find("--packing 0.95"), std::string::npos);
  EXPECT_NE(message(params("pile", 100, 1, 0.3)).find("--packing"), std::string::npos);
  EXPECT_NE(message(params("marbles", 100)).find("--scene marbles"), std::string::npos);
  EXPECT_NE(message(params("gas", 0)).find("--n 0"), std::string::npos);
  EXPECT_NE(message(params("sensors", 10, 1, std::nan(""), -1)).find("--speed -1"), std::string::npos);
}

// The crowd: two rooms side by side, the wall between them open only at its two doorways, the disks all in
// the first room; the steering checked against directions worked out here from the scene's own numbers.
TEST(BenchScenes, CrowdStartsInTheFirstRoomBehindAWallWithTwoDoorways) {
  for (int n : {1, 100, 1000, 10000}) {
    SCOPED_TRACE("n " + std::to_string(n));
    const Scene s = buildScene(params("crowd", n));
    const rattle_bench::Steering& st = s.steering;
    ASSERT_TRUE(st.enabled);
    EXPECT_EQ(st.speed, 3.0);
    EXPECT_EQ(s.restitution, 0.0);
    EXPECT_TRUE((s.gravity == Vec2{0, 0}));
    const double L = st.wallX;
    EXPECT_TRUE((s.bounds.min == Vec2{0, 0}));
    EXPECT_TRUE((s.bounds.max == Vec2{2 * L, L}));
    // The first room holds the disks at packing 0.35 (or is 16 wide, for few disks).
    EXPECT_NEAR(L, std::max(16.0, std::sqrt(n * std::numbers::pi * 0.25 / 0.35)), 1e-12 * L);
    for (const auto& d : s.disks) {
      EXPECT_EQ(d.radius, 0.5);
      EXPECT_LT(d.position.x + d.radius, L);
    }
    if (n <= 1000) expectValidStart(s);
    // Walk up the dividing wall in small steps: open exactly at the two doorways, 4 wide.
    std::vector<std::pair<double, double>> gaps;
    bool open = false;
    const double h = 1e-3;
    for (double y = h / 2; y < L; y += h) {
      bool blocked = false;
      for (const rattle_bench::Wall& w : s.walls)
        if (w.a.x == L && w.b.x == L && y >= std::min(w.a.y, w.b.y) && y <= std::max(w.a.y, w.b.y)) {
          blocked = true;
          EXPECT_TRUE(w.solidEnds);
        }
      if (!blocked && !open) gaps.push_back({y, y});
      if (!blocked) gaps.back().second = y;
      open = !blocked;
    }
    ASSERT_EQ(gaps.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
      EXPECT_NEAR(gaps[k].second - gaps[k].first, 4.0, 2 * h);
      EXPECT_NEAR(0.5 * (gaps[k].first + gaps[k].second), (k == 0 ? 0.25 : 0.75) * L, 2 * h);
      EXPECT_NEAR(st.doorwayY[k], (k == 0 ? 0.25 : 0.75) * L, 1e-12 * L);
    }
    // The start's velocities are the steering's.
    for (const auto& d : s.disks) EXPECT_NEAR(rattle::length(d.velocity), 3.0, 1e-12);
  }
}

TEST(BenchScenes, CrowdSteersAtTheNearerDoorwayThenAtTheGoal) {
  const Scene s = buildScene(params("crowd", 1000, 1, std::nan(""), 2.0));
  const double L = s.steering.wallX;
  const std::vector<Vec2> at = {{1, 0.1 * L}, {L - 1, 0.45 * L}, {L - 1, 0.55 * L}, {0.5 * L, 0.9 * L},
                                {L + 3, 0.25 * L}, {1.9 * L, 0.9 * L}, {1.5 * L, 0.5 * L}};
  const std::vector<Vec2> aim = {{L + 1, 0.25 * L}, {L + 1, 0.25 * L}, {L + 1, 0.75 * L}, {L + 1, 0.75 * L},
                                 {1.5 * L, 0.5 * L}, {1.5 * L, 0.5 * L}, {1.5 * L, 0.5 * L}};
  std::vector<Vec2> v;
  rattle_bench::steerCrowd(s, at, v);
  ASSERT_EQ(v.size(), at.size());
  for (size_t i = 0; i + 1 < at.size(); ++i) {
    SCOPED_TRACE(i);
    const Vec2 to = aim[i] - at[i];
    EXPECT_NEAR(rattle::length(v[i]), 2.0, 1e-12);
    EXPECT_NEAR(rattle::cross(v[i], to), 0.0, 1e-9 * rattle::length(to));
    EXPECT_GT(rattle::dot(v[i], to), 0.0);
  }
  EXPECT_TRUE((v.back() == Vec2{0, 0})) << "a disk on the goal itself stands still";
  // The goal region is the second room, a radius past the wall; crossing the wall counts only outside the
  // doorways.
  EXPECT_FALSE(rattle_bench::inGoalRegion(s, 0, {L + 0.4, 0.5 * L}));
  EXPECT_TRUE(rattle_bench::inGoalRegion(s, 0, {L + 0.5, 0.5 * L}));
  EXPECT_FALSE(rattle_bench::inGoalRegion(s, 0, {2 * L + 0.1, 0.5 * L}));
  EXPECT_FALSE(rattle_bench::crossedWallOutsideDoorways(s, {L - 0.1, 0.25 * L + 1.9}, {L + 0.1, 0.25 * L + 1.9}));
  EXPECT_TRUE(rattle_bench::crossedWallOutsideDoorways(s, {L - 0.1, 0.25 * L + 2.1}, {L + 0.1, 0.25 * L + 2.1}));
  EXPECT_TRUE(rattle_bench::crossedWallOutsideDoorways(s, {L + 0.1, 0.5 * L}, {L - 0.1, 0.5 * L}));
  EXPECT_FALSE(rattle_bench::crossedWallOutsideDoorways(s, {L - 0.3, 0.5 * L}, {L - 0.1, 0.5 * L}));
}

}  // namespace

namespace {

// The benchmark's pile (400 disks poured into a box under gravity, restitution 0.5) with the TC model it
// runs with (collapseTime 1e-3), in the predictive mode at 1/30 s frames for 5 s. The predictive mode's
// Zeno guard lets a body caught in a Zeno sequence sleep after 64 collisions in a step; it once ran before
// the contact's wakes instead of after them, and this pile then reached a million-event budget every
// frame from about 3.7 s on (found by make bench). With the guard in place it needs at most 13,859
// events in a frame (measured); the budget here is 50,000.
TEST(BenchScenesPhysics, PredictivePileSettlesWithinItsEventBudget) {
  const Scene s = buildScene(params("pile", 400));
  rattle::WorldDef def;
  def.mode = rattle::StepMode::Predictive;
  def.gravity = s.gravity;
  def.collapseTime = 1e-3;
  def.maxEventsPerStep = 50'000;
  rattle::World world(def);
  rattle_bench::addToWorld(world, s);
  int worst = 0;
  for (int frame = 0; frame < 150; ++frame) {
    world.step(1.0 / 30);
    ASSERT_FALSE(world.stats().eventBudgetReached) << "frame " << frame << ": the event budget was reached";
    worst = std::max(worst, world.stats().eventsProcessed);
  }
  std::printf("[ predictive pile of 400 ] at most %d events in a frame\n", worst);
}

}  // namespace
