// Shared by the protocol's tests: sample messages of every type, a field-by-field comparison (doubles by
// their bits), and the fuzzer's property (fuzz/net_packet.cpp) as gtest expectations.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "format/byte_writer.h"
#include "format/limits.h"
#include "format/snapshot_codec.h"
#include "net/protocol.h"

namespace net_test {

using namespace rts::net;

/// Before the handshake: no game yet.
inline DecodeContext noGame() { return {}; }
/// The largest game a replay allows: every unit id and gate a command may name. The fuzzer decodes
/// with these contexts too.
inline DecodeContext largestGame() {
  return {2 * rts::replay::kMaxUnitsPerTeam, rts::replay::kMaxGates, rts::replay::kMaxDoorways, rts::replay::kMaxRooms};
}
/// The game of the sample Snapshot: 3 units, 1 gate, 2 doorways, 2 rooms. A Snapshot decodes only in a
/// game of its own sizes; fuzz/net_packet.cpp decodes with this context as well, for the seeds'.
inline DecodeContext snapshotGame() { return {3, 1, 2, 2}; }

inline std::vector<uint8_t> bytesOf(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }
inline std::string textOf(const std::vector<uint8_t>& b) { return std::string(b.begin(), b.end()); }

inline Decoded decodeBytes(const std::vector<uint8_t>& b, const DecodeContext& context) {
  return decode(b.data(), b.size(), context);
}

inline rts::Command command(uint32_t tick, uint8_t team, rts::CommandType type, std::vector<uint32_t> units = {},
                            rattle::Vec2 target = {}, uint32_t gate = 0) {
  rts::Command c;
  c.tick = tick;
  c.team = team;
  c.type = type;
  c.units = std::move(units);
  c.target = target;
  c.gate = gate;
  return c;
}

inline Hello playerHello() {
  Hello h;
  h.engineVersion = "rattle 0.1.0";
  h.mapDigest = 0x0123456789abcdefull;
  h.seed = 0xfedcba9876543210ull;
  h.unitsPerTeam = 100;
  h.stepMode = rattle::StepMode::Predictive;
  h.inputDelayTicks = 4;
  h.hashIntervalTicks = 30;
  h.role = Role::Player;
  h.team = 1;
  h.ticks = 600;
  h.steering = rts::Steering::KeepApart;
  return h;
}

/// Every field at the top of its range; the version string every printable byte's edges.
inline Hello spectatorHello() {
  Hello h;
  h.protocolVersion = kProtocolVersion;
  h.engineVersion = " ~" + std::string(kMaxEngineVersionBytes - 2, 'x');
  h.mapDigest = UINT64_MAX;
  h.seed = UINT64_MAX;
  h.unitsPerTeam = rts::replay::kMaxUnitsPerTeam;
  h.stepMode = rattle::StepMode::Discrete;
  h.inputDelayTicks = kMaxInputDelayTicks;
  h.hashIntervalTicks = UINT16_MAX;
  h.role = Role::Spectator;
  h.team = 0;
  h.ticks = kMaxGameTicks;
  h.steering = rts::Steering::Naive;
  return h;
}

/// Ticks as a host sends them to a spectator: empty ticks, both teams' commands in one (team 0's
/// first), hashes on some, the last tick a game may have.
inline Ticks sampleTicks() {
  Ticks m;
  m.firstTick = 30;
  m.entries.resize(4);
  m.entries[1].commands.push_back(command(31, 0, rts::CommandType::Move, {0, 2, 128}, {12.5, -0.0}));
  m.entries[1].commands.push_back(command(31, 0, rts::CommandType::ToggleGate, {}, {}, 0));
  m.entries[1].commands.push_back(command(31, 1, rts::CommandType::Stop, {1, 399999}));
  m.entries[1].stateHash = 0x8000000000000001ull;
  m.entries[3].stateHash = 0;
  return m;
}

/// One command of each type, unit ids at every varint length, targets a double's awkward values.
inline Commands everyCommandType() {
  Commands m;
  m.tick = 123456;
  m.team = 1;
  const double tiny = std::numeric_limits<double>::denorm_min();
  m.commands.push_back(command(m.tick, 1, rts::CommandType::Move, {0, 127, 128, 16383, 16384, 399999}, {-0.0, tiny}));
  m.commands.push_back(command(m.tick, 1, rts::CommandType::Move, {7}, {1e300, -123.456}));
  m.commands.push_back(command(m.tick, 1, rts::CommandType::Stop, {}));
  m.commands.push_back(command(m.tick, 1, rts::CommandType::Stop, {3, 2, 3}));
  m.commands.push_back(command(m.tick, 1, rts::CommandType::ToggleGate, {}, {}, rts::replay::kMaxGates - 1));
  return m;
}

/// Every kind of body a state holds, with awkward values: a live unit with an order (a target of -0.0
/// and the smallest subnormal), one without, a dead one; two shots (an id of two varint bytes); a gate;
/// doorway counts and room holders at the ends of their ranges. The game is snapshotGame().
inline rts::replay::Snapshot sampleState() {
  rts::replay::Snapshot s;
  s.counters.shotsFired = 12;
  s.counters.wallHits = 3;
  s.counters.unitHits = 4;
  s.counters.crossings = 1;
  s.counters.losses[0] = 1;
  s.counters.losses[1] = 0;
  s.counters.doorwayCrossings = {{0, 1}, {UINT32_MAX, 7}};
  s.counters.roomHolders = {-1, 2};
  rts::replay::UnitState moving;
  moving.alive = moving.orderActive = true;
  moving.hitPoints = 100;
  moving.reloadTicks = -2;
  moving.bodyIndex = 4;
  moving.bodyGeneration = 1;
  moving.motion = {10.5, -3.25, 0.1, -0.0};
  moving.targetX = -0.0;
  moving.targetY = std::numeric_limits<double>::denorm_min();
  rts::replay::UnitState still = moving;
  still.orderActive = false;
  still.targetX = still.targetY = 0;
  still.bodyIndex = 200;
  still.bodyGeneration = 3;
  rts::replay::UnitState dead;
  dead.hitPoints = -5;
  s.units = {moving, still, dead};
  rts::replay::ShotState shot;
  shot.id = 5;
  shot.team = 1;
  shot.shooter = 1;
  shot.ticksLeft = 30;
  shot.bodyIndex = 9;
  shot.bodyGeneration = 2;
  shot.motion = {1, 2, 300, -400};
  rts::replay::ShotState later = shot;
  later.id = 300;
  later.team = 0;
  later.shooter = 0;
  s.shots = {shot, later};
  rts::replay::GateBodyState gate;
  gate.wantOpen = true;
  gate.openness = 0.5;
  gate.motion = {7, 8, 0, 0.25};
  s.gates = {gate};
  return s;
}

inline Snapshot sampleSnapshot() { return Snapshot{101, 0x0102030405060708ull, sampleState()}; }

/// The decode context a sample message decodes in: a Snapshot's own game, or the largest game.
inline DecodeContext contextFor(const Message& m) {
  if (const auto* s = std::get_if<Snapshot>(&m); s && s->state) {
    return {uint32_t(s->state->units.size()), uint32_t(s->state->gates.size()),
            uint32_t(s->state->counters.doorwayCrossings.size()), uint32_t(s->state->counters.roomHolders.size())};
  }
  return largestGame();
}

inline Commands fullCommands() {
  Commands m;
  m.tick = 9;
  m.team = 0;
  for (size_t i = 0; i < kMaxCommandsPerMessage; ++i) m.commands.push_back(command(m.tick, 0, rts::CommandType::Stop));
  return m;
}

/// One of each message type (several of some), named: the fuzzer's seeds are these, encoded.
inline std::vector<std::pair<std::string, Message>> sampleMessages() {
  Commands empty;
  empty.tick = 0;
  empty.team = 0;
  return {
      {"hello-player", playerHello()},
      {"hello-spectator", spectatorHello()},
      {"refuse", Refuse{"seed: mine 7, theirs 8"}},
      {"refuse-longest", Refuse{std::string(kMaxReasonBytes, '!')}},
      {"commands-empty", empty},
      {"commands-every-type", everyCommandType()},
      {"hash", Hash{UINT32_MAX, 0x8000000000000001ull}},
      {"bye", Bye{"the game is over"}},
      {"bye-empty", Bye{""}},
      {"snapshot", sampleSnapshot()},
      // A game with nothing in it: what the context before the handshake decodes.
      {"snapshot-empty-game", Snapshot{0, 0, rts::replay::Snapshot{}}},
      // A state too large for a packet is not sent, but the message is.
      {"snapshot-without-state", Snapshot{UINT32_MAX, UINT64_MAX, std::nullopt}},
      {"ticks", sampleTicks()},
      {"ticks-one-empty", Ticks{kMaxGameTicks - 1, std::vector<Ticks::Entry>(1)}},
  };
}

inline uint64_t bits(double d) { return std::bit_cast<uint64_t>(d); }

inline void expectSameCommand(const rts::Command& a, const rts::Command& b, const std::string& where) {
  EXPECT_EQ(a.tick, b.tick) << where;
  EXPECT_EQ(a.team, b.team) << where;
  EXPECT_EQ(a.type, b.type) << where;
  EXPECT_EQ(a.units, b.units) << where;
  EXPECT_EQ(bits(a.target.x), bits(b.target.x)) << where;
  EXPECT_EQ(bits(a.target.y), bits(b.target.y)) << where;
  EXPECT_EQ(a.gate, b.gate) << where;
}

/// Every field, doubles by their bits. `where` names the case in failures.
inline void expectSame(const Message& a, const Message& b, const std::string& where) {
  ASSERT_EQ(a.index(), b.index()) << where << ": " << messageName(a) << " vs " << messageName(b);
  if (const auto* x = std::get_if<Hello>(&a)) {
    const Hello& y = std::get<Hello>(b);
    EXPECT_EQ(x->protocolVersion, y.protocolVersion) << where;
    EXPECT_EQ(x->engineVersion, y.engineVersion) << where;
    EXPECT_EQ(x->mapDigest, y.mapDigest) << where;
    EXPECT_EQ(x->seed, y.seed) << where;
    EXPECT_EQ(x->unitsPerTeam, y.unitsPerTeam) << where;
    EXPECT_EQ(x->stepMode, y.stepMode) << where;
    EXPECT_EQ(x->inputDelayTicks, y.inputDelayTicks) << where;
    EXPECT_EQ(x->hashIntervalTicks, y.hashIntervalTicks) << where;
    EXPECT_EQ(x->role, y.role) << where;
    EXPECT_EQ(x->team, y.team) << where;
    EXPECT_EQ(x->ticks, y.ticks) << where;
    EXPECT_EQ(x->steering, y.steering) << where;
  } else if (const auto* x = std::get_if<Ticks>(&a)) {
    const Ticks& y = std::get<Ticks>(b);
    EXPECT_EQ(x->firstTick, y.firstTick) << where;
    ASSERT_EQ(x->entries.size(), y.entries.size()) << where;
    for (size_t i = 0; i < x->entries.size(); ++i) {
      const std::string at = where + " entry " + std::to_string(i);
      EXPECT_EQ(x->entries[i].stateHash, y.entries[i].stateHash) << at;
      ASSERT_EQ(x->entries[i].commands.size(), y.entries[i].commands.size()) << at;
      for (size_t j = 0; j < x->entries[i].commands.size(); ++j) {
        expectSameCommand(x->entries[i].commands[j], y.entries[i].commands[j], at + " command " + std::to_string(j));
      }
    }
  } else if (const auto* x = std::get_if<Refuse>(&a)) {
    EXPECT_EQ(x->reason, std::get<Refuse>(b).reason) << where;
  } else if (const auto* x = std::get_if<Commands>(&a)) {
    const Commands& y = std::get<Commands>(b);
    EXPECT_EQ(x->tick, y.tick) << where;
    EXPECT_EQ(x->team, y.team) << where;
    ASSERT_EQ(x->commands.size(), y.commands.size()) << where;
    for (size_t i = 0; i < x->commands.size(); ++i) {
      expectSameCommand(x->commands[i], y.commands[i], where + " command " + std::to_string(i));
    }
  } else if (const auto* x = std::get_if<Hash>(&a)) {
    EXPECT_EQ(x->tick, std::get<Hash>(b).tick) << where;
    EXPECT_EQ(x->stateHash, std::get<Hash>(b).stateHash) << where;
  } else if (const auto* x = std::get_if<Bye>(&a)) {
    EXPECT_EQ(x->reason, std::get<Bye>(b).reason) << where;
  } else if (const auto* x = std::get_if<Snapshot>(&a)) {
    const Snapshot& y = std::get<Snapshot>(b);
    EXPECT_EQ(x->tick, y.tick) << where;
    EXPECT_EQ(x->worldHash, y.worldHash) << where;
    ASSERT_EQ(x->state.has_value(), y.state.has_value()) << where;
    if (!x->state) return;
    // Every field by its bits: the keyframe codec writes them all exactly.
    rts::replay::ByteWriter p, q;
    rts::replay::encodeSnapshot(p, *x->state);
    rts::replay::encodeSnapshot(q, *y.state);
    EXPECT_EQ(p.data(), q.data()) << where;
    EXPECT_EQ(x->state->units.size(), y.state->units.size()) << where;
    EXPECT_EQ(x->state->shots.size(), y.state->shots.size()) << where;
    EXPECT_EQ(x->state->gates.size(), y.state->gates.size()) << where;
  }
}

/// Whether an error line reads as promised: one line, not empty, not long, and naming the message once
/// the type byte says which.
inline void expectCleanError(const std::vector<uint8_t>& input, const std::string& error, const std::string& where) {
  EXPECT_FALSE(error.empty()) << where;
  EXPECT_EQ(error.find('\n'), std::string::npos) << where << ": " << error;
  EXPECT_LE(error.size(), 400u) << where << ": " << error;
  static const char* const names[] = {"Hello", "Refuse", "Commands", "Hash", "Bye", "Snapshot", "Ticks", "GameState"};
  if (input.empty()) {
    EXPECT_EQ(error, "empty packet: no message type") << where;
  } else if (input[0] >= 1 && input[0] <= 8) {
    const std::string name = names[input[0] - 1];
    EXPECT_EQ(error.rfind(name, 0), 0u) << where << ": " << error;
    const char next = error.size() > name.size() ? error[name.size()] : '\0';
    EXPECT_TRUE(next == '.' || next == ':') << where << ": " << error;
  } else {
    EXPECT_EQ(error, "message type " + std::to_string(input[0]) +
                         " is unknown (1 Hello, 2 Refuse, 3 Commands, 4 Hash, 5 Bye, 6 Snapshot, 7 Ticks, 8 GameState)")
        << where;
  }
}

/// The fuzzer's property: refused with a clean error, or decoded, and then encoded again it decodes to
/// the same message and encodes to the same bytes. Returns whether the input decoded.
inline bool expectRefusedCleanlyOrRoundTrips(const std::vector<uint8_t>& input, const DecodeContext& context,
                                             const std::string& where) {
  const Decoded d = decodeBytes(input, context);
  if (!d.ok()) {
    expectCleanError(input, d.error, where);
    return false;
  }
  EXPECT_TRUE(d.error.empty()) << where;
  const std::vector<uint8_t> once = encode(*d.message);
  const Decoded again = decodeBytes(once, context);
  EXPECT_TRUE(again.ok()) << where << ": " << again.error;
  if (!again.ok()) return true;
  expectSame(*d.message, *again.message, where);
  EXPECT_EQ(encode(*again.message), once) << where;
  return true;
}

}  // namespace net_test
