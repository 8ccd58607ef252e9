// rattle-bench: the error measures of the `arena` scene (the demo's game), taken after every tick from
// the game's state and the engine's events, outside the timed step. They are worked out here from the
// map's geometry and the positions alone (plain distances and ray casts against each wall shape), not
// from the engine's broad phase or the game's rules, so they check the engine rather than repeat it.
//
//  - tunnelled shots: a projectile's centre crossed a wall, a building or a standing gate during a tick
//    (its path from where it was before the tick to where it is after it meets the shape). Exact modes
//    stop a projectile one projectile radius before the wall, so for them the count is 0.
//  - overlaps of units: unit against unit, (r_i + r_j - d) / min(r_i, r_j), and unit against a wall,
//    building or gate, (r - distance) / r (a centre inside a building counts 1: its distance is 0).
//  - sensor begins: which (sight sensor, enemy unit) and (doorway, unit) pairs overlap at the end of
//    each tick, from the positions; a pair that overlaps now and did not at the end of the last tick
//    began, and the engine must have reported a begin for it in that tick. Visits that start and end
//    inside one tick cannot be seen this way, so the count is a lower bound of what an engine missed.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "game/game.h"
#include "measure.h"

namespace rattle_bench {

/// The solid shapes of a map (walls, buildings) and its gates where they stand, with their boxes.
class ArenaWalls {
 public:
  explicit ArenaWalls(const rts::Map& map);
  /// Places gate g at `position` (its body's position); `standing`: it did not move in the tick looked at.
  /// A moving gate is left out of the path test: a path it swept over after the projectile passed would
  /// look blocked.
  void placeGate(size_t g, rattle::Vec2 position, bool standing);

  /// Whether the segment from a to b meets a wall, a building or a standing gate.
  bool pathBlocked(rattle::Vec2 a, rattle::Vec2 b) const;
  /// The distance from p to the nearest wall, building or gate, when it is below `limit`; else `limit`.
  double distance(rattle::Vec2 p, double limit) const;

 private:
  struct Shape {
    rattle::Vec2 position;
    rattle::Geometry geometry;
    rattle::Box box;  ///< absolute
    bool solidForPaths = true;
  };
  std::vector<Shape> shapes_;
  size_t firstGate_ = 0;
};

/// One body disk of a unit, for the overlap measure.
struct UnitDisk {
  rattle::Vec2 position;
  double radius = 0.5;
};

/// Adds the overlaps among `units` and between units and `walls` to `stats` (cell grid, O(n)).
void measureUnitOverlaps(const std::vector<UnitDisk>& units, const ArenaWalls& walls, OverlapStats& stats);

/// Begins counted per pair: the begins seen from positions at tick ends against the begins the engine
/// reported, summed as sum over pairs of max(0, seen - reported).
class BeginTally {
 public:
  /// One tick: the pairs overlapping at its end (any order, no repeats) and the begins the engine
  /// reported in it (one entry per begin event).
  void tick(std::vector<uint64_t> overlappingNow, const std::vector<uint64_t>& reportedBegins);
  long long seen() const { return seen_; }
  long long reported() const { return reported_; }
  long long missed() const;

 private:
  std::vector<uint64_t> previous_;                 // sorted
  std::map<uint64_t, std::array<long long, 2>> perPair_;  // seen, reported
  long long seen_ = 0, reported_ = 0;
};

/// Keys of the sensor pairs: sight (observer unit, target unit) and (doorway, unit).
inline uint64_t sightKey(uint32_t observer, uint32_t target) { return uint64_t(observer) << 32 | target; }
inline uint64_t doorwayKey(uint32_t doorway, uint32_t unit) { return 1ull << 63 | uint64_t(doorway) << 32 | unit; }

/// The sight and doorway pairs overlapping now, computed from the units' positions and the map.
std::vector<uint64_t> overlappingSensorPairs(const rts::Game& game);

/// Everything measured over a game.
struct ArenaTotals {
  long long ticks = 0;
  long long contacts = 0;        ///< contact events the engine reported (units, walls, gates, shots)
  long long tunnelledShots = 0;  ///< distinct shots whose centre crossed a wall or a standing gate
  OverlapStats overlaps;         ///< units against units, walls, buildings and gates
  long long sensorBeginsSeen = 0;      ///< sight and doorway begins seen from the positions at tick ends
  long long sensorBeginsReported = 0;  ///< sight and doorway begin events the engine reported
  long long sensorMissed = 0;          ///< sum over pairs of max(0, seen - reported)
  // The game's own counts (as rattle-demo's summary prints them).
  long shotsFired = 0, unitHits = 0, wallHits = 0, outOfRange = 0;
  long crossings = 0;
  int alive[2] = {0, 0};
};

/// Measures a game tick by tick: call before() just before Game::tick and after() just after it.
class ArenaMeter {
 public:
  explicit ArenaMeter(const rts::Game& game);
  void before(const rts::Game& game);
  /// `overlaps`: also measure the overlaps of units this tick (they cost O(units)).
  void after(const rts::Game& game, bool overlaps = true);
  ArenaTotals totals(const rts::Game& game) const;

 private:
  ArenaWalls walls_;
  std::vector<rattle::Vec2> gatesBefore_;
  std::vector<uint8_t> tunnelled_;  // by shot id
  long long tunnelledCount_ = 0;
  long long ticks_ = 0;
  long long contacts_ = 0;
  OverlapStats overlaps_;
  BeginTally sensors_;
  std::vector<UnitDisk> disks_;
  std::vector<uint64_t> reported_;
};

}  // namespace rattle_bench
