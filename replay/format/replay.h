// A replay as data: what the reader returns and the writer is given. Plain structs, no behaviour.
//
// A replay is a game (its map, its configuration) and what happened to it: the commands applied before
// every tick, the state hash after every tick, a 16-bit digest of every body after every tick, and the
// exact state of every body every `keyframeEvery` ticks. FORMAT.md describes the bytes.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "game/commands.h"

namespace rts::replay {

/// One fact about the build that recorded the replay: ("compiler", "GNU 12.2.0"), ("flags", "-O2 ...").
struct BuildFact {
  std::string key;
  std::string value;
  friend bool operator==(const BuildFact&, const BuildFact&) = default;
};

/// How the game was set up. Enough, with the map, to build the same Game again.
struct ReplayConfig {
  uint64_t seed = 0;          ///< the scripted opponent's seed (information: replays do not need it)
  uint32_t unitsPerTeam = 0;  ///< GameConfig::unitsPerTeam
  uint8_t stepMode = 0;       ///< rattle::StepMode: 0 hybrid, 1 discrete, 2 predictive
  bool weapons = true;        ///< GameConfig::weapons
  uint8_t opponentTeams = 0;  ///< bit t: the scripted opponent played team t (information)
  uint32_t keyframeEvery = 0; ///< a keyframe every this many ticks (and at tick 0 and the last tick)
  // What the game was made of, so the records can be read without building it.
  uint32_t unitCount = 0;     ///< Game::units().size()
  uint32_t gateCount = 0;
  uint32_t doorwayCount = 0;
  uint32_t roomCount = 0;
  std::string recordedBy;     ///< "rattle-demo", "rattle-demo --window", "rattle-replay record", ...
  friend bool operator==(const ReplayConfig&, const ReplayConfig&) = default;
};

// ---- Body state, exactly (keyframes) ----

/// The game's own counters (one "body" of the divergence report: the game).
struct CountersState {
  int64_t shotsFired = 0, wallHits = 0, unitHits = 0, crossings = 0;
  int64_t losses[2] = {0, 0};
  std::vector<std::array<uint32_t, 2>> doorwayCrossings;  ///< by doorway, by team
  std::vector<int8_t> roomHolders;                        ///< by room: -1, 0, 1, 2 (contested)
  friend bool operator==(const CountersState&, const CountersState&) = default;
};

/// A body's exact motion: World::position and World::velocity.
struct MotionState {
  double px = 0, py = 0, vx = 0, vy = 0;
  friend bool operator==(const MotionState&, const MotionState&) = default;
};

struct UnitState {
  bool alive = false;
  bool orderActive = false;
  int32_t hitPoints = 0;
  int32_t reloadTicks = 0;
  // Only while alive:
  uint32_t bodyIndex = 0, bodyGeneration = 0;  ///< the engine's BodyId
  MotionState motion;
  // Only while the order is active:
  double targetX = 0, targetY = 0;
  friend bool operator==(const UnitState&, const UnitState&) = default;
};

struct ShotState {
  uint32_t id = 0;
  uint8_t team = 0;
  uint32_t shooter = 0;
  int32_t ticksLeft = 0;
  uint32_t bodyIndex = 0, bodyGeneration = 0;
  MotionState motion;
  friend bool operator==(const ShotState&, const ShotState&) = default;
};

struct GateBodyState {
  bool wantOpen = false;
  double openness = 0;
  MotionState motion;
  friend bool operator==(const GateBodyState&, const GateBodyState&) = default;
};

/// Every body's exact state at one tick: all units (dead ones too, by id), the live shots (by id), the
/// gates (by index), and the game's counters.
struct Snapshot {
  CountersState counters;
  std::vector<UnitState> units;
  std::vector<ShotState> shots;
  std::vector<GateBodyState> gates;
  friend bool operator==(const Snapshot&, const Snapshot&) = default;
};

// ---- Body digests (every tick) ----

struct ShotDigest {
  uint32_t id = 0;
  uint16_t digest = 0;
  friend bool operator==(const ShotDigest&, const ShotDigest&) = default;
};

/// 16-bit digests of each body's encoded state (see FORMAT.md, "Digests"): enough to name the bodies
/// that differ at the first diverging tick, at two bytes a body a tick.
struct Digests {
  uint16_t counters = 0;
  std::vector<uint16_t> units;    ///< unitCount of them
  std::vector<ShotDigest> shots;  ///< live shots, ascending id
  std::vector<uint16_t> gates;    ///< gateCount of them
  friend bool operator==(const Digests&, const Digests&) = default;
};

// ---- Records ----

/// Tick n (1-based): the commands applied before the n-th Game::tick() (stamped n - 1) and the state
/// after it (Game::tickCount() == n).
struct TickRecord {
  uint32_t tick = 0;
  uint64_t stateHash = 0;  ///< Game::stateHash()
  uint64_t worldHash = 0;  ///< Game::worldHash(): the engine's part
  std::vector<Command> commands;
  Digests digests;
};

struct Keyframe {
  uint32_t tick = 0;  ///< 0 is the state before the first tick
  Snapshot state;
};

struct Replay {
  uint16_t version = 0;
  std::vector<BuildFact> build;
  std::string mapName;   ///< the map file's name when it was recorded (information)
  uint64_t mapHash = 0;  ///< FNV-1a 64 of mapJson
  std::string mapJson;   ///< the map file, byte for byte
  ReplayConfig config;
  uint64_t initialStateHash = 0, initialWorldHash = 0;  ///< tick 0
  std::vector<TickRecord> ticks;                         ///< ticks[i].tick == i + 1
  std::vector<Keyframe> keyframes;                       ///< ascending tick, the first at tick 0

  uint32_t tickCount() const { return uint32_t(ticks.size()); }
  size_t commandCount() const {
    size_t n = 0;
    for (const TickRecord& t : ticks) n += t.commands.size();
    return n;
  }
};

}  // namespace rts::replay
