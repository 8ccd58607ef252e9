// Bodies a game drives (World::setVelocity every tick) into one another without gravity: a crowd steered
// through a doorway and a body pushing a row. Their pressed contacts are held by the islands' solve
// (jam.cpp, island.cpp) with the overlap the README states (1% of a radius), not by endless events.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "rattle/rattle.h"

using namespace rattle;

namespace {

constexpr double kRadius = 0.5;

// With `withPoint`, the body also holds a point at its circle's centre (a dynamic body's circles and points
// share one centre), which the circle keeps a radius from anything it meets.
BodyId addDisk(World& world, Vec2 position, bool withPoint = false) {
  const BodyId b = world.createBody({.type = BodyType::Dynamic, .position = position});
  world.createFixture(b, {.geometry = Circle{{0, 0}, kRadius}, .density = 1, .restitution = 0});
  if (withPoint) world.createFixture(b, {.geometry = Point{{0, 0}}, .density = 1, .restitution = 0});
  return b;
}

double kineticEnergy(const World& world, const std::vector<BodyId>& bodies) {
  double e = 0;
  for (BodyId b : bodies) {
    const Vec2 v = world.velocity(b);
    e += 0.5 * world.mass(b) * dot(v, v);
  }
  return e;
}

// The deepest overlap between any two of the disks, by brute force over all pairs.
double deepestOverlap(const World& world, const std::vector<BodyId>& disks) {
  double deepest = 0;
  for (size_t i = 0; i < disks.size(); ++i)
    for (size_t j = i + 1; j < disks.size(); ++j)
      deepest = std::max(deepest, 2 * kRadius - length(world.position(disks[i]) - world.position(disks[j])));
  return deepest;
}

}  // namespace

class DrivenCrowd : public ::testing::TestWithParam<StepMode> {};

// The hybrid and the predictive mode (which hands a driven jam to the hybrid step); the discrete mode has no
// contact solve (README).
INSTANTIATE_TEST_SUITE_P(Modes, DrivenCrowd, ::testing::Values(StepMode::Hybrid, StepMode::Predictive),
                         [](const auto& info) { return info.param == StepMode::Hybrid ? "Hybrid" : "Predictive"; });

// The rooms of the crowd below, as a world with 200 disks in a grid in the first room.
struct Rooms {
  World world;
  std::vector<BodyId> disks;
  Rooms(StepMode mode, bool withPoints) : world({.mode = mode}) {
    const BodyId walls = world.createBody({.type = BodyType::Static});
    world.createFixture(walls, {.geometry = Polyline{{{0, 0}, {30, 0}, {30, 20}, {0, 20}, {0, 0}}}});
    world.createFixture(walls, {.geometry = Polyline{{{20, 0}, {20, 8}}}});
    world.createFixture(walls, {.geometry = Polyline{{{20, 12}, {20, 20}}}});
    for (int i = 0; i < 200; ++i) disks.push_back(addDisk(world, {1 + 1.1 * (i % 16), 1 + 1.1 * (i / 16)}, withPoints));
  }
  // Every disk's velocity at `speed` toward `goal` (still within half a unit of it).
  void steer(Vec2 goal, double speed) {
    for (BodyId b : disks) {
      const Vec2 d = goal - world.position(b);
      const double l = length(d);
      world.setVelocity(b, l > 0.5 ? d * (speed / l) : Vec2{});
    }
  }
};

// A point at the centre of a body's circle never touches anything first: the circle keeps it a radius
// away. So a crowd of disks that also hold such points jams at the doorway as the plain disks do, in a
// contact solve, instead of being left to exact events, which a cluster the game keeps pressing together
// takes thousands of a step (it reached the event budget by tick 12 when such a body counted as a point).
// A crowd is chaotic, and the two take different paths through the engine (a plain disk's fast path, a
// general body's), so their positions part at round-off; what they do is compared instead.
TEST_P(DrivenCrowd, PointsAtTheCirclesCentresChangeNothing) {
  Rooms plain(GetParam(), false), pointed(GetParam(), true);
  int plainMost = 0, pointedMost = 0;
  double worstOverlap = 0;
  for (int tick = 0; tick < 150; ++tick) {
    plain.steer({27, 10}, 3);
    pointed.steer({27, 10}, 3);
    plain.world.step(1.0 / 30);
    pointed.world.step(1.0 / 30);
    ASSERT_FALSE(pointed.world.stats().eventBudgetReached) << "tick " << tick;
    plainMost = std::max(plainMost, plain.world.stats().eventsProcessed);
    pointedMost = std::max(pointedMost, pointed.world.stats().eventsProcessed);
    worstOverlap = std::max(worstOverlap, deepestOverlap(pointed.world, pointed.disks));
  }
  int plainThrough = 0, pointedThrough = 0;
  for (BodyId b : plain.disks) plainThrough += plain.world.position(b).x > 20;
  for (BodyId b : pointed.disks) pointedThrough += pointed.world.position(b).x > 20;
  std::printf("[ points at the centres, %s ] most events in a step %d (plain disks %d), through %d (%d), deepest "
              "overlap %.3g of a radius\n",
              GetParam() == StepMode::Hybrid ? "hybrid" : "predictive", pointedMost, plainMost, pointedThrough,
              plainThrough, worstOverlap / kRadius);
  EXPECT_LE(pointedMost, 2 * plainMost);
  EXPECT_LE(worstOverlap, 0.01 * kRadius);
  EXPECT_NEAR(pointedThrough, plainThrough, 0.2 * plainThrough + 5);
}

// Two rooms, [0, 20] x [0, 20] and [20, 30] x [0, 20], joined by a doorway 4 wide (y in 8..12) in the wall
// x = 20; 200 disks in a grid in the first room steered at 3 units/s toward (27, 10) every tick of 1/30 s
// (naive steering: nothing keeps them apart). They jam at the doorway, which is what a game copied from the
// demo does at once.
TEST_P(DrivenCrowd, PushedThroughADoorwayStaysApartAndInsideWithoutGainingEnergy) {
  Rooms rooms(GetParam(), false);  // no gravity
  World& world = rooms.world;
  const std::vector<BodyId>& disks = rooms.disks;
  const double dt = 1.0 / 30;
  double worstOverlap = 0;
  int worstEvents = 0;
  for (int tick = 0; tick < 600; ++tick) {
    std::vector<Vec2> before;
    for (BodyId b : disks) before.push_back(world.position(b));
    rooms.steer({27, 10}, 3);
    const double commanded = kineticEnergy(world, disks);
    world.step(dt);
    ASSERT_FALSE(world.stats().eventBudgetReached) << "tick " << tick;
    worstEvents = std::max(worstEvents, world.stats().eventsProcessed);
    // The step never adds energy to what the game commanded.
    ASSERT_LE(kineticEnergy(world, disks), commanded * (1 + 1e-12)) << "tick " << tick;
    for (size_t i = 0; i < disks.size(); ++i) {
      const Vec2 p = world.position(disks[i]);
      ASSERT_TRUE(p.x >= kRadius * 0.99 && p.x <= 30 - kRadius * 0.99 && p.y >= kRadius * 0.99 &&
                  p.y <= 20 - kRadius * 0.99)
          << "tick " << tick << ": disk " << i << " left the rooms at (" << p.x << ", " << p.y << ")";
      // Into the second room only through the doorway.
      const Vec2 q = before[i];
      if ((q.x < 20) != (p.x < 20)) {
        const double y = q.y + (p.y - q.y) * (20 - q.x) / (p.x - q.x);
        ASSERT_TRUE(y > 8 && y < 12) << "tick " << tick << ": disk " << i << " passed the wall at y = " << y;
      }
    }
    worstOverlap = std::max(worstOverlap, deepestOverlap(world, disks));
  }
  int through = 0;
  for (BodyId b : disks) through += world.position(b).x > 20;
  std::printf("[ crowd of 200, %s ] through the doorway %d, deepest overlap %.3g of a radius, most events in a step %d\n",
              GetParam() == StepMode::Hybrid ? "hybrid" : "predictive", through, worstOverlap / kRadius, worstEvents);
  EXPECT_LE(worstOverlap, 0.01 * kRadius);
  // A jam the engine froze lets a handful by (the bench's crowd let 5 of 1000 through before the contact
  // solve); this one let 105 (predictive) and 99 (hybrid) by when it was written.
  EXPECT_GE(through, 60);
}

// A disk driven at 2 units/s along x (its velocity set every tick) runs into a row of five touching disks
// at rest, in open space: it pushes the whole row ahead of it, and none passes another.
TEST_P(DrivenCrowd, ADrivenBodyPushesARowAheadOfIt) {
  World world({.mode = GetParam()});
  const BodyId pusher = addDisk(world, {-1, 0});
  std::vector<BodyId> row;
  for (int i = 0; i < 5; ++i) row.push_back(addDisk(world, {2.0 * kRadius * i, 0}));
  std::vector<BodyId> all{pusher};
  all.insert(all.end(), row.begin(), row.end());
  const double dt = 1.0 / 30;
  for (int tick = 0; tick < 120; ++tick) {
    world.setVelocity(pusher, {2, 0});
    world.step(dt);
    ASSERT_FALSE(world.stats().eventBudgetReached) << "tick " << tick;
    ASSERT_LE(deepestOverlap(world, all), 0.01 * kRadius) << "tick " << tick;
    for (size_t i = 0; i + 1 < all.size(); ++i)
      ASSERT_LT(world.position(all[i]).x, world.position(all[i + 1]).x) << "tick " << tick << ": order lost";
  }
  // Head-on along one line: nothing turns the row aside.
  for (BodyId b : all) EXPECT_NEAR(world.position(b).y, 0.0, 1e-9);
  // The pusher went at least half its free distance (8 units in 4 s), and the row ahead of it moved with
  // it: the front disk is still about one row's length ahead.
  const double pusherX = world.position(pusher).x;
  EXPECT_GT(pusherX, -1 + 4.0);
  const double front = world.position(row.back()).x;
  EXPECT_GT(front - pusherX, 5 * 2 * kRadius * (1 - 0.01));
}

// A column of 60 disks driven head-on into a wall at 3 units/s every tick, deeper than the sweeps at a
// step's start carry a push (about one disk a sweep, 25 sweeps; island.cpp). Whether a step's solve meets
// the column's contacts or stops the bodies it leaves pressing (trimIsland), the column ends packed against
// the wall, disk i at r (2 i + 1), with no contact deeper than 1% of a radius and no energy beyond what
// the game commanded. (The crowd at the doorway above is where the stops matter: without them its disks
// overlapped by 2 to 4% of a radius.)
TEST_P(DrivenCrowd, AColumnDrivenIntoAWallPacksAgainstIt) {
  World world({.mode = GetParam()});
  const BodyId wall = world.createBody({.type = BodyType::Static});
  world.createFixture(wall, {.geometry = Segment{{0, -10}, {0, 10}}});
  std::vector<BodyId> column;
  for (int i = 0; i < 60; ++i) column.push_back(addDisk(world, {2 + 1.05 * 2 * kRadius * i, 0}));
  const double dt = 1.0 / 30;
  for (int tick = 0; tick < 150; ++tick) {
    for (BodyId b : column) world.setVelocity(b, {-3, 0});
    const double commanded = kineticEnergy(world, column);
    world.step(dt);
    ASSERT_FALSE(world.stats().eventBudgetReached) << "tick " << tick;
    ASSERT_LE(kineticEnergy(world, column), commanded * (1 + 1e-12)) << "tick " << tick;
    ASSERT_LE(deepestOverlap(world, column), 0.01 * kRadius) << "tick " << tick;
    ASSERT_GE(world.position(column[0]).x, kRadius * 0.99) << "tick " << tick;
  }
  double worstPlace = 0;
  for (size_t i = 0; i < column.size(); ++i) {
    const double packed = kRadius * (2.0 * static_cast<double>(i) + 1);
    worstPlace = std::max(worstPlace, std::fabs(world.position(column[i]).x - packed));
    EXPECT_NEAR(world.position(column[i]).y, 0.0, 1e-9);
  }
  std::printf("[ column of 60, %s ] farthest from its packed place %.3g of a radius, last step %d events\n",
              GetParam() == StepMode::Hybrid ? "hybrid" : "predictive", worstPlace / kRadius,
              world.stats().eventsProcessed);
  EXPECT_LE(worstPlace, 0.01 * kRadius * static_cast<double>(column.size()));
}
