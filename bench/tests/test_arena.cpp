// The benchmark's arena scene (bench/arena.h, bench/arena_measure.h, suite BenchArena): the measures
// against hand-worked geometry (a path through a wall, overlaps at chosen distances, begins counted per
// pair), then short games of the demo: the exact hybrid mode tunnels no projectile, overlaps no unit
// beyond round-off and reports every sensor begin the positions show, while the discrete mode, whose
// projectiles pass walls (rattle-demo --help says so), is caught doing it. Times are not tested here;
// the benchmark measures them.
#include <gtest/gtest.h>

#include <filesystem>

#include "arena.h"
#include "arena_measure.h"

namespace {

using rattle::Vec2;
using rattle_bench::ArenaWalls;
using rattle_bench::BeginTally;
using rattle_bench::UnitDisk;

// A map with a thin vertical wall at x = 10 (y 0..10), a square building [20, 22] x [0, 2] and a gate,
// a square [30, 31] x [0, 1] when closed.
rts::Map testMap() {
  rts::Map m;
  m.width = 40;
  m.height = 20;
  rts::MapWall wall;
  wall.origin = {10, 0};
  wall.shape = rattle::Polyline{{{0, 0}, {0, 10}}};
  m.walls.push_back(wall);
  rts::MapWall building;
  building.origin = {20, 0};
  building.shape = rattle::Polygon{{{0, 0}, {2, 0}, {2, 2}, {0, 2}}};
  building.building = true;
  m.walls.push_back(building);
  rts::MapGate gate;
  gate.origin = {30, 0};
  gate.polygon = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  gate.openOffset = {0, 5};
  m.gates.push_back(gate);
  return m;
}

TEST(BenchArena, APathThroughAWallOrABuildingIsBlocked) {
  ArenaWalls walls(testMap());
  EXPECT_TRUE(walls.pathBlocked({9, 5}, {11, 5}));      // across the thin wall
  EXPECT_FALSE(walls.pathBlocked({8, 5}, {9.85, 5}));   // stops short of it, as an exact engine stops a shot
  EXPECT_FALSE(walls.pathBlocked({9, 11}, {11, 11}));   // past its end
  EXPECT_TRUE(walls.pathBlocked({19, 1}, {21, 1}));     // into the building
  EXPECT_TRUE(walls.pathBlocked({21, 1}, {21.5, 1.5})); // inside it (a shot already in there)
  EXPECT_TRUE(walls.pathBlocked({29, 0.5}, {32, 0.5})); // through the closed gate
  walls.placeGate(0, {30, 0}, false);                   // the same place, but it moved during the tick
  EXPECT_FALSE(walls.pathBlocked({29, 0.5}, {32, 0.5}));
  walls.placeGate(0, {30, 5}, true);                    // open, standing
  EXPECT_FALSE(walls.pathBlocked({29, 0.5}, {32, 0.5}));
  EXPECT_TRUE(walls.pathBlocked({29, 5.5}, {32, 5.5}));
}

TEST(BenchArena, OverlapsOfUnitsAreMeasuredAgainstUnitsAndWalls) {
  ArenaWalls walls(testMap());
  rattle_bench::OverlapStats stats;
  const std::vector<UnitDisk> units = {
      {{3, 3}, 0.5}, {{3.7, 3}, 0.5},  // 0.7 apart: (1 - 0.7) / 0.5 = 0.6
      {{9.55, 5}, 0.5},                // 0.45 from the wall: (0.5 - 0.45) / 0.5 = 0.1
      {{5, 15}, 0.5}, {{6, 15}, 0.5},  // touching exactly: not an overlap
      {{15, 15}, 0.25},                // alone
  };
  rattle_bench::measureUnitOverlaps(units, walls, stats);
  EXPECT_EQ(stats.count, 2);
  EXPECT_NEAR(stats.max, 0.6, 1e-12);
  EXPECT_NEAR(stats.mean(), 0.35, 1e-12);
}

TEST(BenchArena, BeginsAreCountedPerPair) {
  BeginTally t;
  const uint64_t a = rattle_bench::sightKey(1, 2), b = rattle_bench::doorwayKey(0, 2), c = rattle_bench::sightKey(3, 4);
  t.tick({a, b}, {a});      // a begins and is reported; b begins, not reported
  t.tick({a, b}, {b});      // b reported a tick late: counted as reported, not missed
  t.tick({a}, {c});         // c visited inside the tick, never seen at a tick end: no miss, not negative
  t.tick({a, b}, {});       // b again, not reported this time
  EXPECT_EQ(t.seen(), 3);
  EXPECT_EQ(t.reported(), 3);
  EXPECT_EQ(t.missed(), 1);
}

rattle_bench::ArenaTotals play(rattle::StepMode mode, int units, int ticks) {
  rattle_bench::ArenaParams p;
  p.unitsPerTeam = units;
  p.seed = 1;
  p.mode = mode;
  rattle_bench::ArenaGame game(p);
  for (int k = 0; k < ticks; ++k) game.tick();
  EXPECT_EQ(game.game().stats().stepCpuSeconds.size(), size_t(ticks));
  return game.totals();
}

TEST(BenchArena, TheDefaultMapIsFound) { EXPECT_TRUE(std::filesystem::exists(rattle_bench::defaultArenaMap())); }

// 20 s of game time: the armies meet after about 15 s, so projectiles fly in the last seconds.
TEST(BenchArena, TheHybridModeTunnelsNoShotOverlapsNoUnitAndMissesNoBegin) {
  const rattle_bench::ArenaTotals t = play(rattle::StepMode::Hybrid, 100, 600);
  EXPECT_EQ(t.ticks, 600);
  EXPECT_GT(t.shotsFired, 50);  // there was a fight, so the tunnelling check had shots to look at
  EXPECT_GT(t.contacts, 0);
  EXPECT_EQ(t.tunnelledShots, 0);
  EXPECT_LT(t.overlaps.max, 1e-9);  // round-off only
  EXPECT_GT(t.sensorBeginsSeen, 100);
  EXPECT_GE(t.sensorBeginsReported, t.sensorBeginsSeen);  // the engine also reports visits inside a tick
  EXPECT_EQ(t.sensorMissed, 0);
}

TEST(BenchArena, TheDiscreteModeIsCaughtShootingThroughWalls) {
  const rattle_bench::ArenaTotals t = play(rattle::StepMode::Discrete, 100, 600);
  EXPECT_GT(t.shotsFired, 50);
  EXPECT_GT(t.tunnelledShots, 0);
  EXPECT_LE(t.tunnelledShots, t.shotsFired);
  EXPECT_GT(t.overlaps.max, 0.01);  // pushed apart only after the step: units overlap in a crowd
}

}  // namespace
