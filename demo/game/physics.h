// Where the game calls the engine. Everything the game asks of rattle goes through this class: it
// builds the bodies for a map, adds and removes units and projectiles, steps the world, and turns the
// engine's contact and sensor events into game events (a projectile hit a wall, a unit came into sight,
// a unit touched a doorway). The rules in the other files never see a fixture.
//
// Collision filtering does most of the game's work for free: a team's sight sensors only ever report
// the other team's units, a projectile only ever hits walls and enemies, doorways only notice units
// (see the category table in physics.cpp). Rooms are not in the engine: the game counts unit centres
// in them itself (doorways.cpp).
#pragma once

#include <rattle/world.h>

#include <array>
#include <cstdint>
#include <vector>

#include "game/unit_types.h"
#include "map/map.h"

namespace rts {

/// What a body is to the game. Stored per body slot, so an event about a body destroyed since (the
/// engine reports end events a step later) is recognised by its generation and dropped.
enum class Tag : uint8_t { None, Wall, Gate, Doorway, Room, Unit, Shot };

struct ShotContact {
  uint32_t shot = 0;
  Tag other = Tag::None;  ///< Wall, Gate or Unit
  uint32_t otherId = 0;   ///< unit id when other == Unit
  Vec2 point;
};

struct SensorChange {
  uint32_t sensor = 0;  ///< observer unit id (sight) or doorway index
  uint32_t unit = 0;    ///< the unit that came in or went out
  bool begin = true;
};

/// A unit bumped into another unit or into a wall.
struct UnitContact {
  uint32_t unit = 0;
  bool wall = false;   ///< true: a wall, building or gate; false: unit `other`
  uint32_t other = 0;
  Vec2 normal;         ///< unit, from `unit` toward what it hit
};

/// A step's events in the engine's order (by time, then fixture ids).
struct StepEvents {
  std::vector<ShotContact> shotContacts;
  std::vector<UnitContact> unitContacts;
  std::vector<SensorChange> sight;
  std::vector<SensorChange> doorways;
};

class Physics {
 public:
  explicit Physics(const Map& map, rattle::StepMode mode = rattle::StepMode::Hybrid);

  rattle::BodyId addUnit(uint32_t id, int team, Vec2 position, const UnitType& type);
  rattle::BodyId addShot(uint32_t id, int team, Vec2 position, Vec2 velocity, double radius);
  void remove(rattle::BodyId body);

  // A spectator's start (game_state.cpp).
  /// The world saved and loaded again (rattle::World::load), as a ReloadWorld command asks before a tick:
  /// a spectator that loads the same save then steps as this world does, bit for bit.
  void reload() { world_ = rattle::World::load(world_.save()); }
  std::vector<uint8_t> saveWorld() const { return world_.save(); }
  /// Takes `world` (a World::load of a save of this map's game) in place of its own, its units' and
  /// shots' bodies as listed (body, id). Throws GameError, and changes nothing, when the world is not one
  /// of this map's (the walls, doorways and gates where this world has them, the same definition) or a
  /// listed body is not a live dynamic body of its own, within `place` of the origin and slower than
  /// `speed` on each axis.
  void adopt(rattle::World world, const std::vector<std::pair<rattle::BodyId, uint32_t>>& units,
             const std::vector<std::pair<rattle::BodyId, uint32_t>>& shots, double place, double speed);

  Vec2 position(rattle::BodyId body) const { return world_.position(body); }
  Vec2 velocity(rattle::BodyId body) const { return world_.velocity(body); }
  void setVelocity(rattle::BodyId body, Vec2 v) { world_.setVelocity(body, v); }

  Vec2 gatePosition(size_t gate) const { return world_.position(gates_[gate]); }
  Vec2 gateVelocity(size_t gate) const { return world_.velocity(gates_[gate]); }
  void moveGate(size_t gate, Vec2 velocity) { world_.setVelocity(gates_[gate], velocity); }
  void placeGate(size_t gate, Vec2 position);

  /// Steps the world by dt and collects its events. Only world.step is inside the timed part.
  const StepEvents& step(double dt);
  /// The events of the last step (what step returned).
  const StepEvents& lastEvents() const { return events_; }
  /// Wall-clock time of the last world.step.
  double lastStepSeconds() const { return lastStepSeconds_; }
  /// CPU time of this thread during the last world.step: unlike the wall clock, it does not count the
  /// time another process held the core (the benchmark's arena scene reports it).
  double lastStepCpuSeconds() const { return lastStepCpuSeconds_; }
  const rattle::StepStats& lastStepStats() const { return world_.stats(); }

  /// No wall, building or gate touches the segment from a to b (units never block sight).
  bool clearLine(Vec2 a, Vec2 b) const;
  /// Fraction in [0, 1] of `translation` a ray from `origin` travels before a wall, building or gate.
  double wallFraction(Vec2 origin, Vec2 translation) const;
  /// No wall, building or gate overlaps the disk.
  bool freeOfWalls(Vec2 center, double radius) const;
  /// No wall or building overlaps the disk (gates ignored: they move).
  bool freeOfStaticWalls(Vec2 center, double radius) const;
  /// Whether gate `gate`, standing closed (or open), comes within `radius` of p.
  bool gateBlocks(size_t gate, bool open, Vec2 p, double radius) const;
  /// Whether any unit overlaps the box.
  bool anyUnitIn(const rattle::Box& box) const;

  /// The engine's hash of every body's exact state.
  uint64_t stateHash() const { return world_.stateHash(); }
  int bodyCount() const { return world_.bodyCount(); }
  /// Read-only access for tests and tools.
  const rattle::World& world() const { return world_; }

 private:
  struct SlotTag {
    uint32_t generation = 0;
    Tag tag = Tag::None;
    uint32_t id = 0;
  };
  void setTag(rattle::BodyId body, Tag tag, uint32_t id);
  const SlotTag* tagOf(rattle::BodyId body) const;

  rattle::World world_;
  std::vector<SlotTag> tags_;
  std::vector<rattle::BodyId> gates_;
  std::vector<MapGate> gateShapes_;
  StepEvents events_;
  double lastStepSeconds_ = 0;
  double lastStepCpuSeconds_ = 0;
};

}  // namespace rts
