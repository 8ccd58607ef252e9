// The game: its state and its rules, advanced one fixed tick at a time.
//
// Determinism: a game is its map, its configuration and the commands applied before each tick. Nothing
// in here reads a clock (except to time the engine step, which is reported, never used), draws a random
// number (randomness belongs to the command sources), or iterates an unordered container. Units are
// numbered by creation and never renumbered; every loop goes in id order, so two runs with the same
// commands give the same state hash at every tick.
//
// The rules are split by subject, each in its own file of Game members:
//   units.cpp        placing units, orders, steering (seek along a route, arrive)
//   sight.cpp        who is in whose sight sensor, line of sight, fog of war
//   projectiles.cpp  firing, hits, walls
//   doorways.cpp     doorway crossings, rooms held, gates
//   game.cpp         construction, commands, the order of the rules within one tick, the state hash
// and the engine is only ever called through Physics (physics.h).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "game/commands.h"
#include "game/navigation.h"
#include "game/physics.h"
#include "game/steering.h"
#include "game/unit_types.h"
#include "map/map.h"

namespace rts {

/// A map the game cannot start on (a spawn point inside a wall, not enough room for the units).
class GameError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GameConfig {
  int unitsPerTeam = 100;
  rattle::StepMode stepMode = rattle::StepMode::Hybrid;
  bool weapons = true;  ///< false: nobody fires (tests of movement, peaceful scenes)
  /// Indices into kUnitTypes, dealt in turn to each team's units in the order they are placed (nearest
  /// a spawn point first): {0} makes every unit a trooper, {0, 0, 1} every third unit a heavy.
  std::vector<uint8_t> unitTypes{0};
  /// How units are steered (steering.h). Replays record none: they are played with the default.
  Steering steering = Steering::KeepApart;
};

struct Order {
  bool active = false;
  Vec2 target;
  double arrivalRadius = 1;  ///< done when this close; grows with the size of the group ordered
  std::shared_ptr<const FlowField> field;  ///< shared by the whole group ordered together
  double bestDistance = 0;  ///< closest walking distance to the target so far, to notice being stuck
  int stuckTicks = 0;
  int stuckSpells = 0;
};

struct Unit {
  uint32_t id = 0;
  uint8_t team = 0;
  uint8_t type = 0;  ///< index into kUnitTypes
  bool alive = true;
  int hitPoints = 0;
  int reloadTicks = 0;  ///< ticks until it may fire (or look for a target) again
  rattle::BodyId body;
  Vec2 position;  ///< after the last tick
  Vec2 previous;  ///< before the last tick
  Vec2 velocity;
  Order order;
  /// What it bumped into lately, so it steers along them instead of into them again.
  /// A wall touched lately (units are kept apart before they touch: units.cpp).
  struct Touch {
    Vec2 normal;  ///< toward the wall
    int ticksLeft = 0;
  };
  std::array<Touch, 4> touches{};
  /// Asked this tick by friends it stands in the way of: where to step aside to (summed; idle units only).
  Vec2 makeWay;
  std::vector<uint32_t> inSensor;  ///< enemy unit ids inside the sight sensor (may hold dead ones)
  struct DoorTouch {
    uint32_t doorway;
    int8_t entrySide;
  };
  std::vector<DoorTouch> doorways;  ///< doorway sensors it overlaps, with the side it came from
};

struct Shot {
  uint32_t id = 0;
  uint8_t team = 0;
  uint8_t type = 0;  ///< the shooter's unit type: its shot's size
  bool alive = true;
  uint32_t shooter = 0;
  rattle::BodyId body;
  Vec2 position, velocity;
  Vec2 previous;  ///< before the last tick (where it was fired, for a shot fired in it)
  int ticksLeft = 0;
};

/// Where a projectile ended, for the renderer's sparks.
struct Impact {
  Vec2 point;
  uint32_t tick = 0;
  bool wall = false;
};

struct DoorwayState {
  std::array<int, 2> crossings{0, 0};  ///< by team
  int lastCrossTick = -1000;
  int lastCrossTeam = 0;
};

struct RoomState {
  std::array<int, 2> inside{0, 0};
  int holder = -1;  ///< -1: nobody, 0 or 1: that team alone has units inside, 2: both (contested)
};

struct GateState {
  bool wantOpen = false;
  uint32_t nextToggleTick = 0;  ///< 0: no timer
  double openness = 0;          ///< 0 closed .. 1 open
  int toggles = 0;
};

struct GameStats {
  long shotsFired = 0;
  long wallHits = 0;
  long unitHits = 0;
  std::array<long, 2> losses{0, 0};
  long crossings = 0;
  long commandsApplied = 0;
  long commandsIgnored = 0;
  long eventBudgetSteps = 0;        ///< steps that hit the engine's per-step event budget
  std::vector<double> stepSeconds;     ///< engine step time of every tick (wall clock)
  std::vector<double> stepCpuSeconds;  ///< the same steps by this thread's CPU time
  std::vector<int> stepCollisions;     ///< collisions the engine resolved in each step
  std::vector<int> stepImpactTests;    ///< time-of-impact (and sensor) tests of each step
};

class Game {
 public:
  static constexpr int kTicksPerSecond = 30;
  static constexpr double kTickSeconds = 1.0 / kTicksPerSecond;

  /// Builds the world for the map and places the units. Throws GameError when they do not fit.
  Game(Map map, const GameConfig& config);
  ~Game();

  /// Applies a command before the next tick. Returns false (and changes nothing) when it names no live
  /// unit of its team, no gate, or a target that is not a finite point: commands may come from files.
  bool apply(const Command& command);
  /// Advances the game by one tick.
  void tick();

  uint32_t tickCount() const { return tick_; }
  /// The engine's hash of every body, mixed with the game's own state (hit points, orders, counters).
  uint64_t stateHash() const;
  uint64_t worldHash() const { return physics_.stateHash(); }

  const Map& map() const { return map_; }
  const GameConfig& config() const { return config_; }
  const std::vector<Unit>& units() const { return units_; }
  const std::vector<Shot>& shots() const { return shots_; }
  /// The shots removed in the last tick (spent on a unit or a wall, or out of range), as they were at
  /// its end: with shots(), every shot that moved in the last tick (the benchmark checks their paths).
  const std::vector<Shot>& spentShots() const { return spentShots_; }
  const std::vector<Impact>& impacts() const { return impacts_; }
  const std::vector<DoorwayState>& doorways() const { return doorways_; }
  const std::vector<RoomState>& rooms() const { return rooms_; }
  const std::vector<GateState>& gates() const { return gates_; }
  const GameStats& stats() const { return stats_; }
  const Navigation& navigation() const { return navigation_; }
  Navigation& navigation() { return navigation_; }
  const Physics& physics() const { return physics_; }
  int alive(int team) const { return aliveCount_[team & 1]; }
  // The state between ticks (game_state.cpp): what a spectator starts from.
  /// Everything the game carries from one tick to the next, its world's World::save among it, as bytes
  /// (the map and the config are not in it: a Game built from the same ones takes it). Between ticks.
  std::string saveState() const;
  /// This game becomes the one saveState() saved, on a game built from the same map and config. Throws
  /// GameError naming the byte and the field when the bytes are not such a state; the game is then
  /// unchanged. A hostile state never crashes: every id, body and count is checked.
  void restoreState(std::string_view bytes);

  /// The current outline of gate g (absolute coordinates).
  std::vector<Vec2> gateOutline(size_t g) const;

  // Sight (sight.cpp).
  /// The rule: target is an enemy inside observer's sight sensor and no wall is on the line between them.
  bool sees(uint32_t observer, uint32_t target) const;
  /// For every unit id: whether some live unit of `team` sees it (its own units count as seen).
  std::vector<uint8_t> visibleTo(int team) const;
  /// The part of a unit's sight disk that walls do not hide, as a fan of `rays` points around it.
  std::vector<Vec2> sightOutline(const Unit& unit, int rays) const;

 private:
  // units.cpp
  void placeUnits();
  void orderMove(Unit& u, Vec2 target, double arrivalRadius, std::shared_ptr<const FlowField> field);
  void steer();
  void onBump(const UnitContact& contact);
  Vec2 alongTouches(Unit& u, Vec2 desired);
  void fillUnitGrid();
  Vec2 keepApart(Unit& u, Vec2 desired);
  // sight.cpp
  void onSight(const SensorChange& change);
  // projectiles.cpp
  void fireWeapons();
  void fire(Unit& shooter, const Unit& target);
  void onShotContact(const ShotContact& contact);
  void expireShots();
  void damage(Unit& target);
  // doorways.cpp
  void onDoorway(const SensorChange& change);
  void updateRooms();
  void driveGates();
  void toggleGate(size_t g);
  uint32_t gatesOpen() const;  ///< bit g: gate g is fully open
  // game.cpp
  void removeDead();

  Map map_;
  GameConfig config_;
  Physics physics_;
  Navigation navigation_;
  std::array<int, kUnitTypes.size()> navigationLayer_{};  // by unit type: its clearance's layer
  uint32_t tick_ = 0;
  // A ReloadWorld command came: the world is saved and loaded again before the next tick (Physics::reload).
  bool reloadPending_ = false;
  std::vector<Unit> units_;
  std::vector<Shot> shots_;  // live shots, in id order
  std::vector<Shot> spentShots_;  // removed in the last tick, in id order
  uint32_t nextShotId_ = 0;
  std::vector<Impact> impacts_;
  std::vector<DoorwayState> doorways_;
  std::vector<RoomState> rooms_;
  std::vector<GateState> gates_;
  std::array<int, 2> aliveCount_{0, 0};
  GameStats stats_;
  // Where the live units stood at the start of the tick (a counting sort by grid cell), for steering.
  struct UnitGrid {
    double cell = 1;
    int nx = 0, ny = 0;
    std::vector<uint32_t> start;  // per cell, into `units`; one more than cells
    std::vector<uint32_t> units;  // unit ids by cell, ascending within a cell
  } grid_;
};

}  // namespace rts
