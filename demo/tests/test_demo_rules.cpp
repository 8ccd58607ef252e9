// The game rules against what they promise: doorway crossings, projectiles and walls, sight against a
// brute-force check, gates, commands from untrusted sources, and determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <variant>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "game/rng.h"
#include "map/map_loader.h"

namespace {

using rts::Command;
using rts::CommandType;
using rts::Game;
using rts::GameConfig;
using rts::Map;
using rts::Vec2;

std::string assetPath(const std::string& name) { return std::string(RATTLE_SOURCE_DIR) + "/assets/maps/" + name; }

GameConfig config(int units, bool weapons = true) {
  GameConfig c;
  c.unitsPerTeam = units;
  c.weapons = weapons;
  return c;
}

Command move(uint8_t team, std::vector<uint32_t> units, Vec2 target, uint32_t tick = 0) {
  Command c;
  c.tick = tick;
  c.team = team;
  c.type = CommandType::Move;
  c.units = std::move(units);
  c.target = target;
  return c;
}

// Runs ticks until the unit's order is done (or a limit); returns the ticks run.
int runUntilArrived(Game& g, uint32_t unit, int limit = 600) {
  int t = 0;
  while (g.units()[unit].order.active && t < limit) {
    g.tick();
    ++t;
  }
  return t;
}

TEST(DemoRules, OneUnitThroughADoorwayIsOneCrossingOfItsTeam) {
  // small.json: a wall at x = 20 with a doorway from y = 8 to 12 and a closed gate lower down. Unit 0
  // is blue (team 0), spawned in the west room.
  Game g(rts::loadMap(assetPath("small.json")), config(1, false));
  ASSERT_EQ(g.units()[0].team, 0);
  ASSERT_LT(g.units()[0].position.x, 20);
  ASSERT_TRUE(g.apply(move(0, {0}, {26, 10})));
  runUntilArrived(g, 0);
  EXPECT_GT(g.units()[0].position.x, 21) << "the unit did not get through";
  EXPECT_EQ(g.doorways()[0].crossings[0], 1);
  EXPECT_EQ(g.doorways()[0].crossings[1], 0);
  EXPECT_EQ(g.stats().crossings, 1);
  EXPECT_EQ(g.doorways()[0].lastCrossTeam, 0);

  // And back: one more, still team 0.
  ASSERT_TRUE(g.apply(move(0, {0}, {10, 10})));
  runUntilArrived(g, 0);
  EXPECT_LT(g.units()[0].position.x, 19);
  EXPECT_EQ(g.doorways()[0].crossings[0], 2);
  EXPECT_EQ(g.stats().crossings, 2);

  // The red unit crossing counts for red.
  ASSERT_TRUE(g.apply(move(1, {1}, {12, 6})));
  runUntilArrived(g, 1);
  EXPECT_LT(g.units()[1].position.x, 19);
  EXPECT_EQ(g.doorways()[0].crossings[1], 1);
  EXPECT_EQ(g.doorways()[0].lastCrossTeam, 1);
}

TEST(DemoRules, SteppingIntoADoorwayAndBackIsNoCrossing) {
  Game g(rts::loadMap(assetPath("small.json")), config(1, false));
  // Walk onto the doorway line (the unit's disk overlaps the sensor), then back to where it came from.
  ASSERT_TRUE(g.apply(move(0, {0}, {19.9, 10})));
  runUntilArrived(g, 0);
  ASSERT_TRUE(g.apply(move(0, {0}, {12, 10})));
  runUntilArrived(g, 0);
  EXPECT_EQ(g.doorways()[0].crossings[0], 0);
  EXPECT_EQ(g.stats().crossings, 0);
}

TEST(DemoRules, RoomIsHeldByTheTeamInside) {
  Game g(rts::loadMap(assetPath("small.json")), config(1, false));
  // The west room holds blue's spawn; red's unit is outside. (Sensors see new bodies from the first step.)
  g.tick();
  EXPECT_EQ(g.rooms()[0].holder, 0);
  EXPECT_EQ(g.rooms()[0].inside[0], 1);
  ASSERT_TRUE(g.apply(move(1, {1}, {14, 16})));
  runUntilArrived(g, 1);
  EXPECT_EQ(g.rooms()[0].holder, 2) << "both teams inside: contested";
  ASSERT_TRUE(g.apply(move(0, {0}, {30, 12})));
  runUntilArrived(g, 0);
  EXPECT_EQ(g.rooms()[0].holder, 1);
}

TEST(DemoRules, GateOpensAndClosesOnCommand) {
  Game g(rts::loadMap(assetPath("small.json")), config(1, false));
  EXPECT_EQ(g.gates()[0].openness, 0);
  Command toggle;
  toggle.type = CommandType::ToggleGate;
  toggle.gate = 0;
  ASSERT_TRUE(g.apply(toggle));
  for (int t = 0; t < 60; ++t) g.tick();
  EXPECT_EQ(g.gates()[0].openness, 1);
  EXPECT_EQ(g.gateOutline(0)[0], (Vec2{19.5, 16 + 3.5})) << "the gate lands exactly on its open position";
  ASSERT_TRUE(g.apply(toggle));
  for (int t = 0; t < 60; ++t) g.tick();
  EXPECT_EQ(g.gates()[0].openness, 0);
  EXPECT_EQ(g.gateOutline(0)[0], (Vec2{19.5, 16}));
}

TEST(DemoRules, UnitsGoThroughTheGateOnlyWhenItIsOpen) {
  Game g(rts::loadMap(assetPath("small.json")), config(1, false));
  Command toggle;
  toggle.type = CommandType::ToggleGate;
  ASSERT_TRUE(g.apply(toggle));
  for (int t = 0; t < 60; ++t) g.tick();
  // Through the open gate (y 16..19) rather than the doorway: the doorway counts nothing.
  ASSERT_TRUE(g.apply(move(0, {0}, {24, 17.5})));
  runUntilArrived(g, 0);
  EXPECT_GT(g.units()[0].position.x, 21);
  EXPECT_EQ(g.stats().crossings, 0);
}

TEST(DemoRules, CommandsFromUntrustedSourcesAreChecked) {
  Game g(rts::loadMap(assetPath("small.json")), config(1, false));
  const uint64_t before = g.stateHash();
  EXPECT_FALSE(g.apply(move(0, {1}, {10, 10}))) << "unit 1 is red";
  EXPECT_FALSE(g.apply(move(0, {99999}, {10, 10})));
  EXPECT_FALSE(g.apply(move(0, {0}, {std::nan(""), 10})));
  EXPECT_FALSE(g.apply(move(0, {0}, {INFINITY, 10})));
  EXPECT_FALSE(g.apply(move(7, {0}, {10, 10})));
  Command gate;
  gate.type = CommandType::ToggleGate;
  gate.gate = 5;
  EXPECT_FALSE(g.apply(gate));
  Command unknown;
  unknown.type = static_cast<CommandType>(200);
  EXPECT_FALSE(g.apply(unknown));
  EXPECT_EQ(g.stateHash(), before);
  EXPECT_EQ(g.stats().commandsIgnored, 7);
  // A target off the map is clamped onto it.
  EXPECT_TRUE(g.apply(move(0, {0}, {-1e9, 1e9})));
  EXPECT_EQ(g.units()[0].order.target, (Vec2{0, 24}));
}

// Every projectile is stopped by the first wall in its way, at its top speed and at ten times that.
// The box (0..20 square) is split by a thin wall at x = 10; shots start in the left half in every
// direction and must end in it.
TEST(DemoRules, NoProjectileCrossesAWallIn10000Shots) {
  Map map;
  map.width = map.height = 20;
  map.walls.push_back({1, {0, 0}, rattle::Polyline{{{0, 0}, {20, 0}, {20, 20}, {0, 20}, {0, 0}}}, false});
  map.walls.push_back({2, {10, 0}, rattle::Polyline{{{0, 0}, {0, 20}}}, false});
  map.walls.push_back({3, {4, 14}, rattle::Polygon{{{0, 0}, {2, 0}, {2, 0.3}, {0, 0.3}}}, true});  // a thin slab
  rts::Physics physics(map);
  const rts::UnitType& type = rts::kUnitTypes[0];
  rts::Rng rng(12345);
  int shots = 0, wallHits = 0;
  for (double speed : {type.shotSpeed, 10 * type.shotSpeed}) {
    for (int batch = 0; batch < 10; ++batch) {
      struct Flying {
        rattle::BodyId body;
        Vec2 start;
        bool hit = false;
      };
      std::vector<Flying> flying;
      for (int i = 0; i < 500; ++i) {
        Vec2 start{rng.between(0.5, 9.5), rng.between(0.5, 19.5)};
        if (!physics.freeOfWalls(start, type.shotRadius * 1.01)) {
          --i;
          continue;
        }
        const double a = rng.between(0, 2 * 3.141592653589793);
        const uint32_t id = uint32_t(shots++);
        flying.push_back({physics.addShot(id, 0, start, Vec2{std::cos(a), std::sin(a)} * speed, type.shotRadius), start});
      }
      for (int step = 0; step < 30; ++step) {
        const rts::StepEvents& events = physics.step(rts::Game::kTickSeconds);
        for (const rts::ShotContact& c : events.shotContacts) {
          EXPECT_NE(c.other, rts::Tag::Unit);
          Flying& f = flying[c.shot - uint32_t(shots - 500)];
          if (!f.hit) {
            f.hit = true;
            ++wallHits;
          }
        }
        for (const Flying& f : flying) {
          const Vec2 p = physics.position(f.body);
          ASSERT_LE(p.x, 10.0) << "shot from (" << f.start.x << ", " << f.start.y << ") at speed " << speed
                               << " crossed the wall at x = 10";
          ASSERT_GE(p.x, 0.0);
          ASSERT_GE(p.y, 0.0);
          ASSERT_LE(p.y, 20.0);
        }
      }
      for (const Flying& f : flying) {
        EXPECT_TRUE(f.hit) << "no wall contact for the shot from (" << f.start.x << ", " << f.start.y << ")";
        physics.remove(f.body);
      }
    }
  }
  EXPECT_EQ(shots, 10000);
  EXPECT_EQ(wallHits, 10000);
}

// The line-of-sight rule done the slow way: distance, then a ray against every wall, building and
// gate geometry with the geometry layer alone.
bool bruteForceSees(const Game& g, const rts::Unit& o, const rts::Unit& t) {
  const double reach = rts::kUnitTypes[o.type].sight + rts::kUnitTypes[t.type].radius;
  if (rattle::length(t.position - o.position) > reach) return false;  // outside the sight sensor
  const Vec2 ray = t.position - o.position;
  for (const rts::MapWall& w : g.map().walls) {
    if (rattle::rayCast(w.shape, w.origin, o.position, ray)) return false;
  }
  for (size_t k = 0; k < g.map().gates.size(); ++k) {
    if (rattle::rayCast(rattle::Polygon{g.gateOutline(k)}, {0, 0}, o.position, ray)) return false;
  }
  return true;
}

TEST(DemoRules, SightAgreesWithABruteForceCheckEveryTick) {
  Game g(rts::loadMap(assetPath("arena.json")), config(50));
  rts::ScriptedOpponent opponent(3);
  rts::TickLoop loop(g);
  loop.add(opponent);
  long seen = 0, hiddenByWalls = 0, checked = 0;
  for (int tick = 0; tick < 600; ++tick) {
    loop.tick();
    for (const rts::Unit& o : g.units()) {
      if (!o.alive) continue;
      for (const rts::Unit& t : g.units()) {
        if (!t.alive || t.team == o.team) continue;
        const double gap = rattle::length(t.position - o.position) - (rts::kUnitTypes[o.type].sight + rts::kUnitTypes[t.type].radius);
        if (std::fabs(gap) < 1e-9) continue;  // exactly on the sensor's edge: either answer is right
        const bool expected = bruteForceSees(g, o, t);
        ASSERT_EQ(g.sees(o.id, t.id), expected)
            << "tick " << g.tickCount() << ": unit " << o.id << " at (" << o.position.x << ", " << o.position.y << ") and unit "
            << t.id << " at (" << t.position.x << ", " << t.position.y << ")";
        ++checked;
        seen += expected;
        hiddenByWalls += !expected && gap < 0;
      }
    }
  }
  EXPECT_GT(checked, 100000);
  EXPECT_GT(seen, 100) << "the game never got the teams within sight of each other";
  EXPECT_GT(hiddenByWalls, 100) << "no pair was in range but behind a wall";
  EXPECT_GT(g.stats().shotsFired, 0);
}

TEST(DemoRules, SameSeedSameStateHashEveryTick) {
  const Map map = rts::loadMap(assetPath("arena.json"));
  Game a(map, config(60)), b(map, config(60)), c(map, config(60));
  rts::ScriptedOpponent oa(42), ob(42), oc(43);
  std::vector<Command> ca, cb, cc;
  bool differs = false;
  for (int tick = 0; tick < 600; ++tick) {
    ca.clear();
    cb.clear();
    cc.clear();
    oa.commandsFor(a.tickCount(), a, ca);
    ob.commandsFor(b.tickCount(), b, cb);
    oc.commandsFor(c.tickCount(), c, cc);
    for (const Command& x : ca) a.apply(x);
    for (const Command& x : cb) b.apply(x);
    for (const Command& x : cc) c.apply(x);
    a.tick();
    b.tick();
    c.tick();
    ASSERT_EQ(a.worldHash(), b.worldHash()) << "tick " << a.tickCount();
    ASSERT_EQ(a.stateHash(), b.stateHash()) << "tick " << a.tickCount();
    differs |= a.stateHash() != c.stateHash();
  }
  EXPECT_TRUE(differs) << "another seed should give another game";
  EXPECT_GT(a.stats().shotsFired, 0);
  EXPECT_GT(a.stats().crossings, 0);
}

TEST(DemoRules, ARecordedCommandLogReplaysWithoutTheOpponent) {
  // The shape issue 6 needs: the commands of a game, applied again at their ticks, give the same game.
  const Map map = rts::loadMap(assetPath("arena.json"));
  Game live(map, config(30));
  rts::ScriptedOpponent opponent(9);
  rts::TickLoop loop(live);
  loop.add(opponent);
  std::vector<Command> log;
  std::vector<uint64_t> hashes;
  for (int tick = 0; tick < 300; ++tick) {
    const std::vector<Command>& played = loop.tick();
    log.insert(log.end(), played.begin(), played.end());
    hashes.push_back(live.stateHash());
  }
  Game replay(map, config(30));
  size_t next = 0;
  for (int tick = 0; tick < 300; ++tick) {
    for (; next < log.size() && log[next].tick == replay.tickCount(); ++next) replay.apply(log[next]);
    replay.tick();
    ASSERT_EQ(replay.stateHash(), hashes[size_t(tick)]) << "tick " << replay.tickCount();
  }
}

TEST(DemoRules, ACrowdThroughADoorwayQueuesInsteadOfShoving) {
  // small.json: all 60 blue units, packed round their spawn point, sent through the 4-unit doorway at
  // x = 20 to the free corner of the east room (red stands idle in its middle). Steering keeps units
  // apart (units.cpp, keepApart), so the engine seldom has to resolve a collision between units: those
  // left come from units deflected by a wall's corner in the doorway. Steering that drove units into
  // one another at top speed made about 24,600 here (49,194 reports); keeping apart, about 540.
  Game g(rts::loadMap(assetPath("small.json")), config(60, false));
  std::vector<uint32_t> blue;
  for (const rts::Unit& u : g.units()) {
    if (u.team == 0) blue.push_back(u.id);
  }
  ASSERT_TRUE(g.apply(move(0, blue, {35, 3})));
  long reports = 0;
  for (int tick = 0; tick < 600; ++tick) {
    g.tick();
    for (const rts::UnitContact& c : g.physics().lastEvents().unitContacts) reports += !c.wall;
  }
  int through = 0;
  for (uint32_t id : blue) through += g.units()[id].position.x > 21;
  EXPECT_GE(through, 30) << "the crowd did not get through the doorway";
  EXPECT_GE(g.doorways()[0].crossings[0], through);
  // Each collision between two units is reported for both.
  EXPECT_LT(reports, 2 * 1500) << "units were driven into one another";
}

// The same crowd with --steering naive (GameConfig::steering): every unit goes at full speed toward the
// corner, so units are driven into one another and the engine resolves many times more collisions between
// units than with the default; the units still get through, and the engine still keeps them from
// overlapping (checked from the positions, at the radii of kUnitTypes).
TEST(DemoRules, NaiveSteeringDrivesTheCrowdIntoItself) {
  long reports[2] = {0, 0};
  int through[2] = {0, 0};
  for (int naive = 0; naive < 2; ++naive) {
    GameConfig c = config(60, false);
    if (naive) c.steering = rts::Steering::Naive;
    Game g(rts::loadMap(assetPath("small.json")), c);
    std::vector<uint32_t> blue;
    for (const rts::Unit& u : g.units()) {
      if (u.team == 0) blue.push_back(u.id);
    }
    ASSERT_TRUE(g.apply(move(0, blue, {35, 3})));
    double deepest = 0;
    for (int tick = 0; tick < 300; ++tick) {
      g.tick();
      for (const rts::UnitContact& ct : g.physics().lastEvents().unitContacts) reports[naive] += !ct.wall;
      for (size_t i = 0; i < blue.size(); ++i)
        for (size_t j = i + 1; j < blue.size(); ++j) {
          const rts::Unit& a = g.units()[blue[i]];
          const rts::Unit& b = g.units()[blue[j]];
          const double touching = rts::kUnitTypes[a.type].radius + rts::kUnitTypes[b.type].radius;
          deepest = std::max(deepest, touching - rattle::length(a.position - b.position));
        }
    }
    for (uint32_t id : blue) through[naive] += g.units()[id].position.x > 21;
    EXPECT_LT(deepest, 1e-6) << (naive ? "naive" : "keep-apart") << ": units overlap";
  }
  std::printf("[ crowd of 60 ] collisions between units reported: keep-apart %ld, naive %ld; through: %d, %d\n",
              reports[0], reports[1], through[0], through[1]);
  EXPECT_GE(through[1], 20) << "the naive crowd did not get through the doorway";
  EXPECT_GT(reports[1], 10 * std::max(reports[0], 1L)) << "keep-apart " << reports[0] << ", naive " << reports[1];
}

// A second, larger unit type (kUnitTypes[1], radius 0.9 to a trooper's 0.5) dealt to every second
// unit: each unit stands clear of every other at the two radii, and clear of the walls at its own.
TEST(DemoRules, ALargerUnitTypeIsPlacedWithoutOverlap) {
  GameConfig c = config(60, false);
  c.unitTypes = {0, 1};
  Game g(rts::loadMap(assetPath("arena.json")), c);
  const std::vector<rts::Unit>& units = g.units();
  ASSERT_EQ(units.size(), 120u);
  int large = 0;
  for (const rts::Unit& u : units) {
    const double r = rts::kUnitTypes[u.type].radius;
    large += r > rts::kUnitTypes[0].radius;
    EXPECT_TRUE(g.physics().freeOfWalls(u.position, r)) << "unit " << u.id << " stands in a wall";
    for (const rts::Unit& o : units) {
      if (o.id <= u.id) continue;
      const double apart = rattle::length(o.position - u.position), touching = r + rts::kUnitTypes[o.type].radius;
      EXPECT_GE(apart, touching) << "units " << u.id << " and " << o.id << " overlap";
    }
  }
  EXPECT_EQ(large, 60);
}

// A 30 x 20 box split at x = 15 but for a gap 1.6 wide (y = 9 to 10.6): a trooper (1.0 across) walks
// through, a heavy (1.8 across) cannot, and its navigation knows it.
TEST(DemoRules, NavigationKeepsEachUnitTypesOwnClearance) {
  Map map;
  map.width = 30;
  map.height = 20;
  map.walls.push_back({1, {0, 0}, rattle::Polyline{{{0, 0}, {30, 0}, {30, 20}, {0, 20}, {0, 0}}}, false});
  map.walls.push_back({2, {15, 0}, rattle::Polyline{{{0, 0}, {0, 9}}}, false});
  map.walls.push_back({3, {15, 10.6}, rattle::Polyline{{{0, 0}, {0, 9.4}}}, false});
  map.spawns.push_back({4, 0, {5, 10}});
  map.spawns.push_back({5, 1, {25, 10}});
  GameConfig c = config(2, false);
  c.unitTypes = {0, 1};
  Game g(map, c);
  const uint32_t trooper = 0, heavy = 2;  // ids alternate between the teams
  ASSERT_EQ(g.units()[trooper].type, 0);
  ASSERT_EQ(g.units()[heavy].type, 1);
  ASSERT_EQ(g.units()[heavy].team, 0);
  ASSERT_TRUE(g.apply(move(0, {trooper, heavy}, {25, 4})));
  EXPECT_TRUE(g.units()[trooper].order.active);
  EXPECT_FALSE(g.units()[heavy].order.active) << "the heavy was sent through a gap narrower than it";
  runUntilArrived(g, trooper);
  EXPECT_GT(g.units()[trooper].position.x, 20) << "the trooper did not get through the gap";
  EXPECT_LT(g.units()[heavy].position.x, 15);
  // On its own side the heavy has somewhere to go.
  ASSERT_TRUE(g.apply(move(0, {heavy}, {5, 3})));
  EXPECT_TRUE(g.units()[heavy].order.active);
}

TEST(DemoRules, UnitTypesOutsideTheTableAreAClearError) {
  GameConfig c = config(2);
  c.unitTypes = {0, uint8_t(rts::kUnitTypes.size())};
  EXPECT_THROW(Game(rts::loadMap(assetPath("small.json")), c), rts::GameError);
  c.unitTypes.clear();
  EXPECT_THROW(Game(rts::loadMap(assetPath("small.json")), c), rts::GameError);
}

TEST(DemoRules, TooManyUnitsForTheMapIsAClearError) {
  try {
    Game g(rts::loadMap(assetPath("small.json")), config(5000));
    FAIL() << "5000 units per team fit on a 40 x 24 map?";
  } catch (const rts::GameError& e) {
    EXPECT_NE(std::string(e.what()).find("room for only"), std::string::npos) << e.what();
  }
}

}  // namespace
