// The lockstep protocol (net/protocol.h): every message round-trips bit for bit; the bytes are the
// documented layout; every truncation, a trailing byte, every limit one over and unknown types are
// refused with one line naming the message and field; a Snapshot's state is checked as a replay's
// keyframe is; the handshake names each difference; random and mutated packets are refused cleanly or
// round-trip.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "format/byte_writer.h"
#include "format/command_codec.h"
#include "format/snapshot_codec.h"
#include "net_test_support.h"

namespace {

using namespace net_test;
using rts::CommandType;
using rts::replay::ByteWriter;

// ---- Bytes written field by field, independently of encode, to pin the layout and to break rules ----

struct RawHello {
  uint32_t version = kProtocolVersion;
  std::string engine = "rattle 0.1.0";
  int engineLength = -1;  // the string's own length unless set
  uint64_t digest = 0x0123456789abcdefull, seed = 7;
  uint32_t units = 100;
  uint8_t stepMode = 0;
  uint16_t delay = 4, interval = 1;
  uint8_t role = 0, team = 0;
  uint32_t ticks = 600;
  uint8_t steering = 0;
};

std::vector<uint8_t> raw(const RawHello& h) {
  ByteWriter w;
  w.u8(1);
  w.u32(h.version);
  w.u8(uint8_t(h.engineLength >= 0 ? h.engineLength : int(h.engine.size())));
  w.bytes(h.engine);
  w.u64(h.digest);
  w.u64(h.seed);
  w.u32(h.units);
  w.u8(h.stepMode);
  w.u16(h.delay);
  w.u16(h.interval);
  w.u8(h.role);
  w.u8(h.team);
  w.u32(h.ticks);
  w.u8(h.steering);
  return bytesOf(w.data());
}

// A Ticks header; the entries are appended by the caller.
ByteWriter rawTicksHeader(uint32_t firstTick, uint16_t count) {
  ByteWriter w;
  w.u8(7);
  w.u32(firstTick);
  w.u16(count);
  return w;
}

std::vector<uint8_t> rawText(uint8_t type, const std::string& s) {
  ByteWriter w;
  w.u8(type);
  w.u8(uint8_t(s.size()));
  w.bytes(s);
  return bytesOf(w.data());
}

// A Commands header; the commands are appended by the caller with encodeCommand or by hand.
ByteWriter rawCommandsHeader(uint32_t tick, uint8_t team, uint16_t count) {
  ByteWriter w;
  w.u8(3);
  w.u32(tick);
  w.u8(team);
  w.u16(count);
  return w;
}

std::string errorOf(const std::vector<uint8_t>& bytes, const DecodeContext& context = largestGame()) {
  const Decoded d = decodeBytes(bytes, context);
  EXPECT_FALSE(d.ok()) << "accepted";
  return d.error;
}

std::string encodeError(const Message& m) {
  try {
    encode(m);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(encoded)";
}

// ---- Round trips and layout ----

TEST(NetProtocol, EveryMessageRoundTripsBitForBit) {
  std::vector<std::pair<std::string, Message>> cases = sampleMessages();
  cases.push_back({"commands-full", fullCommands()});
  for (const auto& [name, message] : cases) {
    const std::vector<uint8_t> bytes = encode(message);
    const Decoded d = decodeBytes(bytes, contextFor(message));
    ASSERT_TRUE(d.ok()) << name << ": " << d.error;
    EXPECT_EQ(d.error, "") << name;
    expectSame(message, *d.message, name);
    EXPECT_EQ(encode(*d.message), bytes) << name;
  }
  // The doubles kept their bits: -0.0 stays negative, the smallest subnormal stays itself.
  const Decoded d = decodeBytes(encode(everyCommandType()), largestGame());
  const rts::Command& move = std::get<Commands>(*d.message).commands[0];
  EXPECT_TRUE(std::signbit(move.target.x));
  EXPECT_EQ(bits(move.target.y), 1u);
  EXPECT_EQ(move.tick, 123456u);  // stamped with the message's tick
  const Decoded state = decodeBytes(encode(sampleSnapshot()), snapshotGame());
  const rts::replay::UnitState& unit = std::get<Snapshot>(*state.message).state->units[0];
  EXPECT_TRUE(std::signbit(unit.targetX));
  EXPECT_EQ(bits(unit.targetY), 1u);
  EXPECT_EQ(std::get<Snapshot>(*state.message).state, sampleState());
}

TEST(NetProtocol, MessagesWithoutCommandsDecodeBeforeTheHandshake) {
  for (const auto& [name, message] : sampleMessages()) {
    if (name == "commands-every-type" || name == "snapshot" || name == "ticks") continue;
    const Decoded d = decodeBytes(encode(message), noGame());
    ASSERT_TRUE(d.ok()) << name << ": " << d.error;
    expectSame(message, *d.message, name);
  }
  EXPECT_EQ(errorOf(encode(everyCommandType()), noGame()),
            "Commands.commands[0] unit count: 6 is out of range (at most 0)");
  // The state of a game with bodies in it is read as one of a game without: no doorways, no rooms, no
  // units, then a shot count where the doorways' counts are (0 shots), and the rest is left over.
  EXPECT_EQ(errorOf(encode(sampleSnapshot()), noGame()),
            "Snapshot: 224 bytes after the end of the message (from byte 21 of 245)");
}

TEST(NetProtocol, TheBytesAreTheDocumentedLayout) {
  Hello h = playerHello();
  RawHello r;
  r.digest = h.mapDigest;
  r.seed = h.seed;
  r.units = h.unitsPerTeam;
  r.stepMode = 2;
  r.delay = 4;
  r.interval = 30;
  r.role = 0;
  r.team = 1;
  EXPECT_EQ(encode(h), raw(r));
  EXPECT_EQ(encode(h).size(), 50u);
  h.steering = rts::Steering::Naive;
  h.ticks = 0x01020304;
  r.steering = 1;
  r.ticks = 0x01020304;
  EXPECT_EQ(encode(h), raw(r));

  // Ticks: the header, then each tick's count, its commands (the replay's codec) and its hash flag.
  Ticks ticks;
  ticks.firstTick = 0x010b0c0d;
  ticks.entries.resize(2);
  ticks.entries[0].commands.push_back(command(0x010b0c0d, 1, CommandType::Stop, {5}));
  ticks.entries[1].stateHash = 0x8000000000000001ull;
  const std::vector<uint8_t> ticksBytes = {7,    0x0d, 0x0c, 0x0b, 0x01, 2, 0, 1,    0, 2, 1, 1, 5, 0,
                                           0,    0,    1,    0x01, 0,    0, 0, 0,    0, 0, 0x80};
  EXPECT_EQ(encode(ticks), ticksBytes);

  const std::vector<uint8_t> hash = {4, 0x78, 0x56, 0x34, 0x12, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80};
  EXPECT_EQ(encode(Hash{0x12345678, 0x8000000000000001ull}), hash);
  EXPECT_EQ(encode(Bye{"ok"}), (std::vector<uint8_t>{5, 2, 'o', 'k'}));
  EXPECT_EQ(encode(Refuse{""}), (std::vector<uint8_t>{2, 0}));

  // Commands: tick, team, u16 count, then the replay's command codec: type, team, varint count, varint
  // ids, f64 target (Move); varint gate (ToggleGate).
  Commands m;
  m.tick = 2;
  m.team = 1;
  m.commands.push_back(command(2, 1, CommandType::Move, {300}, {1.0, 0.0}));
  m.commands.push_back(command(2, 1, CommandType::ToggleGate, {}, {}, 3));
  // clang-format off
  const std::vector<uint8_t> expected = {
      3, 2, 0, 0, 0, 1, 2, 0,                          // Commands, tick 2, team 1, 2 commands
      1, 1, 1, 0xac, 0x02,                             // Move, team 1, 1 unit: 300
      0, 0, 0, 0, 0, 0, 0xf0, 0x3f, 0, 0, 0, 0, 0, 0, 0, 0,  // target 1.0, 0.0
      3, 1, 3};                                        // ToggleGate, team 1, gate 3
  // clang-format on
  EXPECT_EQ(encode(m), expected);
  EXPECT_EQ(encode(Commands{7, 0, {}}), (std::vector<uint8_t>{3, 7, 0, 0, 0, 0, 0, 0}));

  // Snapshot: tick, world hash, whether the state follows, then the state as a replay's keyframe stores
  // it (FORMAT.md, "KEYF"): counters (zigzags, then by doorway two varints, by room a u8 holder + 1),
  // every unit, a shot count and the shots, every gate.
  Snapshot snap;
  snap.tick = 0x01020304;
  snap.worldHash = 0x1122334455667788ull;
  rts::replay::Snapshot& st = snap.state.emplace();
  st.counters.shotsFired = 1;
  st.counters.losses[1] = 64;  // a two-byte zigzag
  st.counters.doorwayCrossings = {{2, 300}};
  st.counters.roomHolders = {1};
  rts::replay::UnitState unit;
  unit.alive = true;
  unit.hitPoints = 100;
  unit.bodyIndex = 3;
  unit.bodyGeneration = 1;
  unit.motion = {1.0, 0, 0, 0};
  st.units = {unit};
  // clang-format off
  const std::vector<uint8_t> state = {
      6, 4, 3, 2, 1, 0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11,  // Snapshot, tick, world hash
      1,                                               // the state follows
      2, 0, 0, 0, 0, 0x80, 0x01,                       // shots 1, walls, units, crossings, losses 0, losses 64
      2, 0xac, 0x02, 2,                                // doorway 0: 2 and 300; room 0: red (1 + 1)
      1, 0xc8, 0x01, 0, 3, 1,                          // unit 0: alive, 100 hit points, reload 0, body 3 gen 1
      0, 0, 0, 0, 0, 0, 0xf0, 0x3f, 0, 0, 0, 0, 0, 0, 0, 0,  // position 1.0, 0.0
      0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,  // velocity 0.0, 0.0
      0};                                              // no shots (and no gates)
  // clang-format on
  EXPECT_EQ(encode(snap), state);
  const Decoded d = decodeBytes(state, {1, 0, 1, 1});
  ASSERT_TRUE(d.ok()) << d.error;
  EXPECT_EQ(std::get<Snapshot>(*d.message).state, snap.state);
  EXPECT_EQ(encode(Snapshot{2, 3, std::nullopt}),
            (std::vector<uint8_t>{6, 2, 0, 0, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0}));  // no state: it did not fit
  // The state's bytes are the replay's keyframe codec's.
  rts::replay::ByteWriter keyframe;
  rts::replay::encodeSnapshot(keyframe, sampleState());
  const std::vector<uint8_t> sample = encode(sampleSnapshot());
  EXPECT_EQ(textOf({sample.begin() + kSnapshotHeaderBytes, sample.end()}), keyframe.data());
}

TEST(NetProtocol, TheLargestPacketPassesAndOneByteMoreDoesNot) {
  // One Move whose packet is exactly kMaxPacketBytes: 8 bytes of header, type and team, a 3-byte unit
  // count, 16 bytes of target, and the ids: one of 2 bytes (128 to 16383) and the rest of 3.
  const size_t n = (kMaxPacketBytes - 8 - 2 - 3 - 16 + 1) / 3;
  Commands m;
  m.tick = 1;
  m.team = 0;
  m.commands.push_back(command(1, 0, CommandType::Move, std::vector<uint32_t>(n, 20000), {1, 2}));
  m.commands[0].units[0] = 200;
  const std::vector<uint8_t> bytes = encode(m);
  ASSERT_EQ(bytes.size(), kMaxPacketBytes);
  const Decoded d = decodeBytes(bytes, largestGame());
  ASSERT_TRUE(d.ok()) << d.error;
  EXPECT_EQ(std::get<Commands>(*d.message).commands[0].units.size(), n);

  m.commands[0].units.push_back(5);
  EXPECT_EQ(encodeError(m), "Commands: packet of 1048577 bytes exceeds the limit 1048576");
  std::vector<uint8_t> over = bytes;
  over.push_back(0);
  EXPECT_EQ(errorOf(over), "Commands: packet of 1048577 bytes exceeds the limit 1048576");
}

TEST(NetProtocol, TheLargestSnapshotPassesAndOneByteMoreDoesNot) {
  // Dead units of 3 bytes (flags, hit points, reload), a few of 4 (64 hit points: a two-byte zigzag),
  // six bytes of counters and a shot count: exactly kMaxSnapshotStateBytes of state, a whole packet.
  ASSERT_EQ(kMaxSnapshotStateBytes, kMaxPacketBytes - 14);
  const size_t units = (kMaxSnapshotStateBytes - 7) / 3, longer = (kMaxSnapshotStateBytes - 7) % 3;
  ASSERT_EQ(7 + 3 * units + longer, kMaxSnapshotStateBytes);
  Snapshot m;
  m.state.emplace();
  m.state->units.resize(units);
  for (size_t i = 0; i < longer; ++i) m.state->units[i].hitPoints = 64;
  const std::vector<uint8_t> bytes = encode(m);
  ASSERT_EQ(bytes.size(), kMaxPacketBytes);
  const DecodeContext context{uint32_t(units), 0, 0, 0};
  const Decoded d = decodeBytes(bytes, context);
  ASSERT_TRUE(d.ok()) << d.error;
  EXPECT_EQ(std::get<Snapshot>(*d.message).state->units.size(), units);

  m.state->units[longer].hitPoints = 64;
  EXPECT_EQ(encodeError(m), "Snapshot.state: 1048563 bytes exceeds the limit 1048562");
  std::vector<uint8_t> over = bytes;
  over.push_back(0);
  EXPECT_EQ(errorOf(over, context), "Snapshot: packet of 1048577 bytes exceeds the limit 1048576");
}

// ---- Truncations, trailing bytes, unknown types ----

TEST(NetProtocol, EveryTruncationIsAnErrorNamingTheMessage) {
  std::vector<std::pair<std::string, Message>> cases = sampleMessages();
  cases.push_back({"commands-full", fullCommands()});
  int checked = 0;
  for (const auto& [name, message] : cases) {
    const std::vector<uint8_t> bytes = encode(message);
    const std::string type = messageName(message);
    for (size_t n = 1; n < bytes.size(); ++n) {
      const std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + std::ptrdiff_t(n));
      const Decoded d = decodeBytes(cut, contextFor(message));
      ASSERT_FALSE(d.ok()) << name << " cut at " << n;
      ASSERT_EQ(d.error.rfind(type, 0), 0u) << name << " cut at " << n << ": " << d.error;
      ASSERT_NE(d.error.find(": truncated at byte "), std::string::npos) << name << " cut at " << n << ": " << d.error;
      ASSERT_NE(d.error.find(" of " + std::to_string(n) + " ("), std::string::npos)
          << name << " cut at " << n << ": " << d.error;
      expectCleanError(cut, d.error, name);
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
  // Exactly, at a few places.
  const std::vector<uint8_t> hello = encode(playerHello());
  EXPECT_EQ(errorOf({hello.begin(), hello.begin() + 3}),
            "Hello.protocolVersion: truncated at byte 1 of 3 (needs 4 bytes, 2 left)");
  EXPECT_EQ(errorOf({hello.begin(), hello.begin() + 5}),
            "Hello.engineVersion length: truncated at byte 5 of 5 (needs 1 byte, 0 left)");
  EXPECT_EQ(errorOf({hello.begin(), hello.begin() + 6}),
            "Hello.engineVersion: truncated at byte 6 of 6 (needs 12 bytes, 0 left)");
  EXPECT_EQ(errorOf({hello.begin(), hello.begin() + 44}),
            "Hello.team: truncated at byte 44 of 44 (needs 1 byte, 0 left)");
  const std::vector<uint8_t> commands = encode(everyCommandType());
  EXPECT_EQ(errorOf({commands.begin(), commands.begin() + 9}),
            "Commands.count = 5: truncated at byte 8 of 9 (5 commands need at least 15 bytes, 1 left)");
  EXPECT_EQ(errorOf({commands.begin(), commands.begin() + 30}),
            "Commands.commands[0] target.x: truncated at byte 23 of 30 (needs 8 bytes, 7 left)");
  Commands oneMove = everyCommandType();
  oneMove.commands.resize(1);
  const std::vector<uint8_t> move = encode(oneMove);
  EXPECT_EQ(errorOf({move.begin(), move.begin() + 21}),
            "Commands.commands[0] unit 5: truncated at byte 21 of 21 (inside a varint)");
  EXPECT_EQ(errorOf({move.begin(), move.begin() + 12}),
            "Commands.commands[0] unit count: truncated at byte 10 of 12 (6 items cannot fit in the 1 bytes left)");
  const std::vector<uint8_t> snapshot = encode(sampleSnapshot());
  const DecodeContext game = snapshotGame();
  EXPECT_EQ(errorOf({snapshot.begin(), snapshot.begin() + 8}, game),
            "Snapshot.worldHash: truncated at byte 5 of 8 (needs 8 bytes, 3 left)");
  EXPECT_EQ(errorOf({snapshot.begin(), snapshot.begin() + 13}, game),
            "Snapshot.hasState: truncated at byte 13 of 13 (needs 1 byte, 0 left)");
  EXPECT_EQ(errorOf({snapshot.begin(), snapshot.begin() + 14}, game),
            "Snapshot.state counters shotsFired: truncated at byte 14 of 14 (inside a varint)");
  // The sample's bytes: 14 of header, 16 of counters, units of 54, 39 and 3 bytes (unit 0's position.y
  // at byte 44), the shot count at 126, shots of 38 and 39, a gate of 41: 245 in all.
  ASSERT_EQ(snapshot.size(), 245u);
  EXPECT_EQ(errorOf({snapshot.begin(), snapshot.begin() + 46}, game),
            "Snapshot.state unit 0 position.y: truncated at byte 44 of 46 (needs 8 bytes, 2 left)");
  EXPECT_EQ(errorOf({snapshot.begin(), snapshot.begin() + 190}, game),
            "Snapshot.state shot count: truncated at byte 126 of 190 (2 items cannot fit in the 63 bytes left)");
  EXPECT_EQ(errorOf({}), "empty packet: no message type");
  EXPECT_EQ(decode(nullptr, 0, largestGame()).error, "empty packet: no message type");
  EXPECT_EQ(decode(nullptr, 5, largestGame()).error, "empty packet: no message type");
}

TEST(NetProtocol, AByteAfterTheMessageIsAnError) {
  for (const auto& [name, message] : sampleMessages()) {
    std::vector<uint8_t> bytes = encode(message);
    const size_t size = bytes.size();
    bytes.push_back(0);
    EXPECT_EQ(errorOf(bytes, contextFor(message)), std::string(messageName(message)) +
                                                       ": 1 byte after the end of the message (from byte " +
                                                       std::to_string(size) + " of " + std::to_string(size + 1) + ")")
        << name;
    bytes.push_back(0xff);
    EXPECT_NE(errorOf(bytes, contextFor(message)).find(": 2 bytes after the end of the message"), std::string::npos)
        << name;
  }
}

TEST(NetProtocol, UnknownMessageTypesAreErrors) {
  for (const uint8_t type : {0, 9, 127, 255}) {
    const std::string line =
        "message type " + std::to_string(type) +
        " is unknown (1 Hello, 2 Refuse, 3 Commands, 4 Hash, 5 Bye, 6 Snapshot, 7 Ticks, 8 GameState)";
    EXPECT_EQ(errorOf({type, 1, 2, 3}), line);
    EXPECT_EQ(errorOf({type}), line);
  }
}

// ---- Every limit, one over ----

TEST(NetProtocol, HelloFieldsOneOverTheirLimitsAreErrors) {
  ASSERT_TRUE(decodeBytes(raw({}), largestGame()).ok()) << decodeBytes(raw({}), largestGame()).error;
  auto with = [](auto change) {
    RawHello r;
    change(r);
    return errorOf(raw(r));
  };
  EXPECT_EQ(with([](RawHello& r) { r.engine = std::string(kMaxEngineVersionBytes + 1, 'v'); }),
            "Hello.engineVersion length = 65 exceeds the limit 64");
  EXPECT_EQ(with([](RawHello& r) {
              r.engine = std::string(kMaxEngineVersionBytes, 'v');
              r.engineLength = 255;
            }),
            "Hello.engineVersion length = 255 exceeds the limit 64");
  EXPECT_EQ(with([](RawHello& r) { r.engine = "rat\ntle"; }),
            "Hello.engineVersion: byte 3 is 0x0a, not printable ASCII (0x20 to 0x7e)");
  EXPECT_EQ(with([](RawHello& r) { r.engine = "x\x7f"; }),
            "Hello.engineVersion: byte 1 is 0x7f, not printable ASCII (0x20 to 0x7e)");
  EXPECT_EQ(with([](RawHello& r) { r.engine = std::string("\x1f", 1); }),
            "Hello.engineVersion: byte 0 is 0x1f, not printable ASCII (0x20 to 0x7e)");
  EXPECT_EQ(with([](RawHello& r) { r.engine = std::string("\xc3\xa9"); }),
            "Hello.engineVersion: byte 0 is 0xc3, not printable ASCII (0x20 to 0x7e)");
  EXPECT_EQ(with([](RawHello& r) { r.units = rts::replay::kMaxUnitsPerTeam + 1; }),
            "Hello.unitsPerTeam = 200001 is out of range (1 to 200000)");
  EXPECT_EQ(with([](RawHello& r) { r.units = 0; }), "Hello.unitsPerTeam = 0 is out of range (1 to 200000)");
  EXPECT_EQ(with([](RawHello& r) { r.stepMode = 3; }),
            "Hello.stepMode = 3 is not a step mode (0 hybrid, 1 discrete, 2 predictive)");
  EXPECT_EQ(with([](RawHello& r) { r.delay = kMaxInputDelayTicks + 1; }),
            "Hello.inputDelayTicks = 301 exceeds the limit 300");
  EXPECT_EQ(with([](RawHello& r) { r.interval = 0; }), "Hello.hashIntervalTicks = 0 is below the minimum 1");
  EXPECT_EQ(with([](RawHello& r) { r.role = 2; }), "Hello.role = 2 is not a role (0 player, 1 spectator)");
  EXPECT_EQ(with([](RawHello& r) { r.team = 2; }), "Hello.team = 2: a player's team is 0 (blue) or 1 (red)");
  EXPECT_EQ(with([](RawHello& r) {
              r.role = 1;
              r.team = 1;
            }),
            "Hello.team = 1: a spectator's team is 0");

  // At the limits, all is well.
  RawHello edge;
  edge.engine = std::string(kMaxEngineVersionBytes, '~');
  edge.units = rts::replay::kMaxUnitsPerTeam;
  edge.stepMode = 2;
  edge.delay = kMaxInputDelayTicks;
  edge.interval = 1;
  edge.role = 1;
  EXPECT_TRUE(decodeBytes(raw(edge), largestGame()).ok());
}

TEST(NetProtocol, AnotherProtocolVersionDecodesAndItsErrorsSaySo) {
  ASSERT_EQ(kProtocolVersion, 4u);
  RawHello r;
  r.version = 1;  // a build from before Snapshot
  const Decoded d = decodeBytes(raw(r), largestGame());
  ASSERT_TRUE(d.ok()) << d.error;  // so that the handshake, not the decoder, refuses it
  EXPECT_EQ(std::get<Hello>(*d.message).protocolVersion, 1u);
  r.stepMode = 9;
  EXPECT_EQ(errorOf(raw(r)),
            "Hello.stepMode = 9 is not a step mode (0 hybrid, 1 discrete, 2 predictive) "
            "(the peer speaks protocol version 1; this build speaks 4)");
}

TEST(NetProtocol, ReasonsOneOverTheirLimitsAreErrors) {
  const std::string longest(kMaxReasonBytes, 'r');
  EXPECT_TRUE(decodeBytes(rawText(2, longest), largestGame()).ok());
  EXPECT_TRUE(decodeBytes(rawText(5, longest), largestGame()).ok());
  EXPECT_EQ(errorOf(rawText(2, longest + "r")), "Refuse.reason length = 201 exceeds the limit 200");
  EXPECT_EQ(errorOf(rawText(5, longest + "r")), "Bye.reason length = 201 exceeds the limit 200");
  EXPECT_EQ(errorOf(rawText(2, "a\tb")), "Refuse.reason: byte 1 is 0x09, not printable ASCII (0x20 to 0x7e)");
  EXPECT_EQ(errorOf(rawText(5, "\x1b[2J")), "Bye.reason: byte 0 is 0x1b, not printable ASCII (0x20 to 0x7e)");
}

TEST(NetProtocol, CommandsFieldsOneOverTheirLimitsAreErrors) {
  const DecodeContext small{200, 4};
  auto oneCommand = [](uint8_t team, const rts::Command& c) {
    ByteWriter w = rawCommandsHeader(5, team, 1);
    rts::replay::encodeCommand(w, c);
    return bytesOf(w.data());
  };
  EXPECT_TRUE(decodeBytes(oneCommand(1, command(5, 1, CommandType::Move, {199}, {1, 2})), small).ok());
  EXPECT_EQ(errorOf(oneCommand(2, command(5, 2, CommandType::Stop))),
            "Commands.team = 2: expected 0 (blue) or 1 (red)");
  EXPECT_EQ(errorOf(oneCommand(0, command(5, 1, CommandType::Stop))),
            "Commands.commands[0] team = 1 differs from Commands.team = 0 (a peer sends its own team's commands only)");
  EXPECT_EQ(errorOf(oneCommand(1, command(5, 1, CommandType::Move, {200}, {1, 2})), small),
            "Commands.commands[0] unit 0: 200 is out of range (0 to 199)");
  EXPECT_EQ(errorOf(oneCommand(1, command(5, 1, CommandType::Stop, std::vector<uint32_t>(201, 1))), small),
            "Commands.commands[0] unit count: 201 is out of range (at most 200)");
  EXPECT_TRUE(decodeBytes(oneCommand(1, command(5, 1, CommandType::ToggleGate, {}, {}, 3)), small).ok());
  EXPECT_EQ(errorOf(oneCommand(1, command(5, 1, CommandType::ToggleGate, {}, {}, 4)), small),
            "Commands.commands[0] gate: 4 is out of range (0 to 3)");
  EXPECT_EQ(errorOf(oneCommand(1, command(5, 1, CommandType::Move, {1}, {std::nan(""), 0}))),
            "Commands.commands[0] target.x: not a finite number");
  EXPECT_EQ(errorOf(oneCommand(1, command(5, 1, CommandType::Move, {1}, {0, -HUGE_VAL}))),
            "Commands.commands[0] target.y: not a finite number");
  EXPECT_TRUE(decodeBytes(oneCommand(1, command(5, 1, CommandType::ReloadWorld)), small).ok());
  std::vector<uint8_t> unknown = oneCommand(1, command(5, 1, CommandType(5)));
  unknown.push_back(0);
  EXPECT_EQ(errorOf(unknown),
            "Commands.commands[0] type: unknown command type 5 (1 move, 2 stop, 3 toggle gate, 4 reload world)");

  // The count: the limit, then one over (with the commands really there), then a huge one in a small packet.
  auto stops = [](uint16_t count, size_t present) {
    ByteWriter w = rawCommandsHeader(5, 0, count);
    for (size_t i = 0; i < present; ++i) rts::replay::encodeCommand(w, command(5, 0, CommandType::Stop));
    return bytesOf(w.data());
  };
  EXPECT_TRUE(decodeBytes(stops(kMaxCommandsPerMessage, kMaxCommandsPerMessage), largestGame()).ok());
  EXPECT_EQ(errorOf(stops(kMaxCommandsPerMessage + 1, kMaxCommandsPerMessage + 1)),
            "Commands.count = 1025 exceeds the limit 1024");
  EXPECT_EQ(errorOf(stops(UINT16_MAX, 2)), "Commands.count = 65535 exceeds the limit 1024");
  EXPECT_EQ(errorOf(stops(3, 2)),
            "Commands.count = 3: truncated at byte 8 of 14 (3 commands need at least 9 bytes, 6 left)");
}

// The state is read by the replay's keyframe decoder, for this game's sizes: whatever a keyframe may
// not hold, a Snapshot may not either, and encode refuses it in the words decode would use.
TEST(NetProtocol, SnapshotStatesAreCheckedAsAKeyframeIs) {
  const DecodeContext game = snapshotGame();
  const std::vector<uint8_t> good = encode(sampleSnapshot());
  ASSERT_TRUE(decodeBytes(good, game).ok());
  // Another game's sizes: a fourth unit is read from the shot count (2: an order without life); without
  // the gate, its 41 bytes are left over.
  EXPECT_EQ(errorOf(good, {4, 1, 2, 2}), "Snapshot.state unit 3 flags: a dead unit with an active order");
  EXPECT_EQ(errorOf(good, {3, 0, 2, 2}), "Snapshot: 41 bytes after the end of the message (from byte 204 of 245)");
  // Whether the state follows is a flag.
  std::vector<uint8_t> flag = encode(Snapshot{1, 2, std::nullopt});
  flag[13] = 2;
  EXPECT_EQ(errorOf(flag, game), "Snapshot.hasState = 2: expected 0 (the state did not fit a packet) or 1");
  flag[13] = 1;
  EXPECT_EQ(errorOf(flag, game), "Snapshot.state counters shotsFired: truncated at byte 14 of 14 (inside a varint)");
  EXPECT_EQ(errorOf(good, {3, 1, 2, 1}).rfind("Snapshot.state ", 0), 0u);

  struct Case {
    void (*change)(rts::replay::Snapshot&);
    std::string line;
  };
  const Case cases[] = {
      {[](rts::replay::Snapshot& s) { s.units[1].motion.px = std::nan(""); },
       "Snapshot.state unit 1 position.x: not a finite number"},
      {[](rts::replay::Snapshot& s) { s.units[0].targetY = -HUGE_VAL; },
       "Snapshot.state unit 0 order.target.y: not a finite number"},
      {[](rts::replay::Snapshot& s) { s.units[0].bodyGeneration = 0; },
       "Snapshot.state unit 0 body generation: 0 is out of range (1 to 4294967295)"},
      {[](rts::replay::Snapshot& s) { s.shots[1].id = 5; }, "Snapshot.state shot 1 id: shot ids must ascend"},
      {[](rts::replay::Snapshot& s) { s.shots[0].team = 2; }, "Snapshot.state shot 0 team: 2: expected 0 or 1"},
      {[](rts::replay::Snapshot& s) { s.gates[0].openness = INFINITY; },
       "Snapshot.state gate 0 openness: not a finite number"},
      {[](rts::replay::Snapshot& s) { s.counters.roomHolders[1] = 3; },
       "Snapshot.state counters room 1 holder: expected 0 to 3 (nobody, blue, red, contested)"},
      {[](rts::replay::Snapshot& s) { s.counters.shotsFired = -1; },
       "Snapshot.state counters shotsFired: -1 is out of range (0 to 4611686018427387904)"},
  };
  for (const Case& c : cases) {
    Snapshot m = sampleSnapshot();
    c.change(*m.state);
    EXPECT_EQ(encodeError(m), c.line);
    // The same bytes, written without encode's checks, are refused by decode in the same words.
    rts::replay::ByteWriter w;
    w.u8(6);
    w.u32(m.tick);
    w.u64(m.worldHash);
    w.u8(1);
    rts::replay::encodeSnapshot(w, *m.state);
    EXPECT_EQ(errorOf(bytesOf(w.data()), game), c.line);
  }
}

TEST(NetProtocol, EncodeRefusesWhatDecodeWouldRefuseInTheSameWords) {
  Hello h = playerHello();
  h.engineVersion = std::string(kMaxEngineVersionBytes + 1, 'v');
  EXPECT_EQ(encodeError(h), "Hello.engineVersion length = 65 exceeds the limit 64");
  h = playerHello();
  h.engineVersion = "a\nb";
  EXPECT_EQ(encodeError(h), "Hello.engineVersion: byte 1 is 0x0a, not printable ASCII (0x20 to 0x7e)");
  h = playerHello();
  h.unitsPerTeam = 0;
  EXPECT_EQ(encodeError(h), "Hello.unitsPerTeam = 0 is out of range (1 to 200000)");
  h = playerHello();
  h.stepMode = rattle::StepMode(3);
  EXPECT_EQ(encodeError(h), "Hello.stepMode = 3 is not a step mode (0 hybrid, 1 discrete, 2 predictive)");
  h = playerHello();
  h.inputDelayTicks = kMaxInputDelayTicks + 1;
  EXPECT_EQ(encodeError(h), "Hello.inputDelayTicks = 301 exceeds the limit 300");
  h = playerHello();
  h.hashIntervalTicks = 0;
  EXPECT_EQ(encodeError(h), "Hello.hashIntervalTicks = 0 is below the minimum 1");
  h = playerHello();
  h.role = Role(2);
  EXPECT_EQ(encodeError(h), "Hello.role = 2 is not a role (0 player, 1 spectator)");
  h = playerHello();
  h.role = Role::Spectator;
  EXPECT_EQ(encodeError(h), "Hello.team = 1: a spectator's team is 0");

  EXPECT_EQ(encodeError(Refuse{std::string(kMaxReasonBytes + 1, 'r')}),
            "Refuse.reason length = 201 exceeds the limit 200");
  EXPECT_EQ(encodeError(Bye{"\x07"}), "Bye.reason: byte 0 is 0x07, not printable ASCII (0x20 to 0x7e)");

  Commands m = fullCommands();
  m.commands.push_back(m.commands.back());
  EXPECT_EQ(encodeError(m), "Commands.count = 1025 exceeds the limit 1024");
  m = everyCommandType();
  m.team = 2;
  EXPECT_EQ(encodeError(m), "Commands.team = 2: expected 0 (blue) or 1 (red)");
  m = everyCommandType();
  m.commands[3].team = 0;
  EXPECT_EQ(encodeError(m),
            "Commands.commands[3] team = 0 differs from Commands.team = 1 (a peer sends its own team's commands only)");
  m = everyCommandType();
  m.commands[1].target.y = INFINITY;
  EXPECT_EQ(encodeError(m), "Commands.commands[1] target.y: not a finite number");
  m = everyCommandType();
  m.commands[2].type = CommandType(0);
  EXPECT_EQ(encodeError(m),
            "Commands.commands[2] type: unknown command type 0 (1 move, 2 stop, 3 toggle gate, 4 reload world)");
}

TEST(NetProtocol, HelloTicksAndSteeringOutOfRangeAreErrors) {
  RawHello r;
  r.ticks = kMaxGameTicks + 1;
  EXPECT_EQ(errorOf(raw(r)), "Hello.ticks = 100000001 exceeds the limit 100000000");
  r.ticks = kMaxGameTicks;
  EXPECT_TRUE(decodeBytes(raw(r), largestGame()).ok());
  r.steering = 2;
  EXPECT_EQ(errorOf(raw(r)), "Hello.steering = 2 is not a steering (0 keep-apart, 1 naive)");
  r.steering = 1;
  EXPECT_TRUE(decodeBytes(raw(r), largestGame()).ok());
  const std::vector<uint8_t> hello = encode(playerHello());
  EXPECT_EQ(errorOf({hello.begin(), hello.begin() + 47}), "Hello.ticks: truncated at byte 45 of 47 (needs 4 bytes, 2 left)");
  EXPECT_EQ(errorOf({hello.begin(), hello.begin() + 49}),
            "Hello.steering: truncated at byte 49 of 49 (needs 1 byte, 0 left)");
  Hello h = playerHello();
  h.ticks = kMaxGameTicks + 1;
  EXPECT_EQ(encodeError(h), "Hello.ticks = 100000001 exceeds the limit 100000000");
  h = playerHello();
  h.steering = rts::Steering(7);
  EXPECT_EQ(encodeError(h), "Hello.steering = 7 is not a steering (0 keep-apart, 1 naive)");
}

TEST(NetProtocol, TicksFieldsOneOverTheirLimitsAreErrors) {
  const DecodeContext small{200, 4};
  // An empty tick: a count of 0 commands and no hash.
  auto emptyTicks = [](uint32_t first, uint16_t count) {
    ByteWriter w = rawTicksHeader(first, count);
    for (uint16_t i = 0; i < count; ++i) {
      w.u16(0);
      w.u8(0);
    }
    return bytesOf(w.data());
  };
  EXPECT_TRUE(decodeBytes(emptyTicks(0, uint16_t(kMaxTicksPerMessage)), small).ok());
  EXPECT_EQ(errorOf(emptyTicks(0, uint16_t(kMaxTicksPerMessage + 1)), small),
            "Ticks.count = 4097 exceeds the limit 4096");
  EXPECT_EQ(errorOf(emptyTicks(0, 0), small), "Ticks.count = 0 is below the minimum 1");
  EXPECT_TRUE(decodeBytes(emptyTicks(kMaxGameTicks - 2, 2), small).ok());
  EXPECT_EQ(errorOf(emptyTicks(kMaxGameTicks - 1, 2), small),
            "Ticks.firstTick = 99999999: its 2 ticks run past the limit 100000000");
  // A count of more ticks than the bytes left could hold, refused before anything is allocated.
  ByteWriter shortOne = rawTicksHeader(0, 1000);
  shortOne.u16(0);
  shortOne.u8(0);
  EXPECT_EQ(errorOf(bytesOf(shortOne.data()), small),
            "Ticks.count = 1000: truncated at byte 7 of 10 (1000 ticks need at least 3000 bytes, 3 left)");
  // An entry's command count: over the limit, and more than the bytes left.
  ByteWriter tooMany = rawTicksHeader(0, 1);
  tooMany.u16(uint16_t(kMaxCommandsPerTick + 1));
  tooMany.u8(0);
  EXPECT_EQ(errorOf(bytesOf(tooMany.data()), small), "Ticks.entries[0] count = 2049 exceeds the limit 2048");
  ByteWriter cut = rawTicksHeader(0, 1);
  cut.u16(5);
  cut.u8(0);
  cut.u8(0);
  EXPECT_EQ(errorOf(bytesOf(cut.data()), small),
            "Ticks.entries[0] count = 5: truncated at byte 9 of 11 (5 commands need at least 15 bytes, 1 left for them)");
  // Team 1's before team 0's: not the order the players applied them in.
  ByteWriter order = rawTicksHeader(3, 1);
  order.u16(2);
  rts::replay::encodeCommand(order, command(3, 1, CommandType::Stop, {1}));
  rts::replay::encodeCommand(order, command(3, 0, CommandType::Stop, {0}));
  order.u8(0);
  EXPECT_EQ(errorOf(bytesOf(order.data()), small),
            "Ticks.entries[0] commands[1] team = 0 after team 1 (team 0's commands come first)");
  // A unit the game does not have, in the codec's words with this message's field.
  ByteWriter unit = rawTicksHeader(3, 1);
  unit.u16(1);
  rts::replay::encodeCommand(unit, command(3, 0, CommandType::Stop, {200}));
  unit.u8(0);
  EXPECT_EQ(errorOf(bytesOf(unit.data()), small).rfind("Ticks.entries[0] commands[0] unit", 0), 0u)
      << errorOf(bytesOf(unit.data()), small);
  // The hash flag.
  ByteWriter flag = rawTicksHeader(3, 1);
  flag.u16(0);
  flag.u8(2);
  EXPECT_EQ(errorOf(bytesOf(flag.data()), small), "Ticks.entries[0] hasHash = 2: expected 0 or 1");
  ByteWriter hash = rawTicksHeader(3, 1);
  hash.u16(0);
  hash.u8(1);
  hash.u32(0);
  EXPECT_EQ(errorOf(bytesOf(hash.data()), small),
            "Ticks.entries[0] stateHash: truncated at byte 10 of 14 (needs 8 bytes, 4 left)");
  // Encode refuses the same.
  Ticks m;
  EXPECT_EQ(encodeError(m), "Ticks.count = 0 is below the minimum 1");
  m.entries.resize(1);
  m.entries[0].commands.push_back(command(0, 1, CommandType::Stop, {1}));
  m.entries[0].commands.push_back(command(0, 0, CommandType::Stop, {0}));
  EXPECT_EQ(encodeError(m), "Ticks.entries[0] commands[1] team = 0 after team 1 (team 0's commands come first)");
  m.entries[0].commands.resize(1);
  m.entries[0].commands[0].target.x = NAN;
  m.entries[0].commands[0].type = CommandType::Move;
  EXPECT_EQ(encodeError(m), "Ticks.entries[0] commands[0] target.x: not a finite number");
}

// ---- The handshake ----

TEST(NetProtocol, HandshakeAcceptsTheSameGame) {
  Hello blue = playerHello(), red = playerHello();
  blue.team = 0;
  red.team = 1;
  EXPECT_EQ(handshakeMismatch(blue, red), std::nullopt);
  EXPECT_EQ(handshakeMismatch(red, blue), std::nullopt);
  Hello watcher = blue;
  watcher.role = Role::Spectator;
  EXPECT_EQ(handshakeMismatch(blue, watcher), std::nullopt);
  EXPECT_EQ(handshakeMismatch(watcher, red), std::nullopt);
}

TEST(NetProtocol, HandshakeNamesEachDifferenceWithBothValues) {
  Hello mine = playerHello();
  mine.team = 0;
  const Hello base = [&] {
    Hello h = mine;
    h.team = 1;
    return h;
  }();
  struct Case {
    void (*change)(Hello&);
    std::string expected;
  };
  const Case cases[] = {
      {[](Hello& h) { h.protocolVersion = 1; }, "protocol version: mine 4, theirs 1"},
      {[](Hello& h) { h.engineVersion = "rattle 0.2.0"; },
       "engine version: mine \"rattle 0.1.0\", theirs \"rattle 0.2.0\""},
      {[](Hello& h) { h.mapDigest = 0xab; }, "map digest: mine 0x0123456789abcdef, theirs 0x00000000000000ab"},
      {[](Hello& h) { h.seed = 8; }, "seed: mine 18364758544493064720, theirs 8"},
      {[](Hello& h) { h.unitsPerTeam = 5000; }, "units a team: mine 100, theirs 5000"},
      {[](Hello& h) { h.stepMode = rattle::StepMode::Hybrid; }, "step mode: mine predictive, theirs hybrid"},
      {[](Hello& h) { h.steering = rts::Steering::Naive; }, "steering: mine keep-apart, theirs naive"},
      {[](Hello& h) { h.ticks = 601; }, "ticks: mine 600, theirs 601"},
      {[](Hello& h) { h.inputDelayTicks = 6; }, "input delay: mine 4 ticks, theirs 6 ticks"},
      {[](Hello& h) { h.hashIntervalTicks = 1; }, "hash interval: mine 30 ticks, theirs 1 ticks"},
      {[](Hello& h) { h.team = 0; }, "team: both players are on team 0 (blue)"},
  };
  for (const Case& c : cases) {
    Hello theirs = base;
    c.change(theirs);
    const auto line = handshakeMismatch(mine, theirs);
    ASSERT_TRUE(line.has_value()) << c.expected;
    EXPECT_EQ(*line, c.expected);
  }
  // Several at once: all of them, in one line.
  Hello theirs = base;
  theirs.seed = 8;
  theirs.stepMode = rattle::StepMode::Discrete;
  theirs.team = 0;
  EXPECT_EQ(handshakeMismatch(mine, theirs),
            "seed: mine 18364758544493064720, theirs 8; step mode: mine predictive, theirs discrete; "
            "team: both players are on team 0 (blue)");
  // Two spectators have no game to follow.
  Hello a = mine, b = base;
  a.role = b.role = Role::Spectator;
  a.team = b.team = 0;
  EXPECT_EQ(handshakeMismatch(a, b), "role: both sides are spectators");
}

// ---- Random and mutated bytes ----

TEST(NetProtocol, RandomBytesAreRefusedCleanlyOrRoundTrip) {
  std::mt19937_64 rng(26);
  int decoded = 0, refused = 0, hashes = 0;
  for (int i = 0; i < 4000; ++i) {
    std::vector<uint8_t> bytes(rng() % 49);
    for (uint8_t& b : bytes) b = uint8_t(rng());
    // Half of them start with a known type, so that they get past the first byte.
    if (!bytes.empty() && rng() % 2 == 0) bytes[0] = uint8_t(1 + rng() % 7);
    const std::string where = "random input " + std::to_string(i);
    for (const DecodeContext& context : {noGame(), largestGame(), snapshotGame()}) {
      (expectRefusedCleanlyOrRoundTrips(bytes, context, where) ? decoded : refused)++;
    }
    // Any 13 bytes that start with 4 are a Hash, and these are its fields.
    if (bytes.size() == 13 && bytes[0] == 4) {
      ++hashes;
      const Decoded d = decodeBytes(bytes, noGame());
      ASSERT_TRUE(d.ok()) << d.error;
      uint64_t tick = 0, hash = 0;
      for (int k = 0; k < 4; ++k) tick |= uint64_t(bytes[size_t(1 + k)]) << (8 * k);
      for (int k = 0; k < 8; ++k) hash |= uint64_t(bytes[size_t(5 + k)]) << (8 * k);
      EXPECT_EQ(std::get<Hash>(*d.message).tick, tick);
      EXPECT_EQ(std::get<Hash>(*d.message).stateHash, hash);
    }
  }
  EXPECT_GT(hashes, 0);
  EXPECT_GT(decoded, 0);
  EXPECT_GT(refused, 10000);
}

TEST(NetProtocol, MutatedPacketsAreRefusedCleanlyOrRoundTrip) {
  std::mt19937_64 rng(2026);
  const auto samples = sampleMessages();
  int decoded = 0, refused = 0, exact = 0;
  for (int i = 0; i < 3000; ++i) {
    const auto& [name, message] = samples[size_t(rng() % samples.size())];
    std::vector<uint8_t> bytes = encode(message);
    const int flips = 1 + int(rng() % 3);
    for (int f = 0; f < flips; ++f) bytes[1 + size_t(rng() % (bytes.size() - 1))] ^= uint8_t(1u << (rng() % 8));
    const std::string where = name + " mutant " + std::to_string(i);
    if (!expectRefusedCleanlyOrRoundTrips(bytes, contextFor(message), where)) {
      ++refused;
      continue;
    }
    ++decoded;
    // Fixed-width fields have one encoding each: what decodes encodes back to the very same bytes
    // (commands' and states' varints may have longer spellings than the shortest, which encode writes).
    const Decoded d = decodeBytes(bytes, contextFor(message));
    if (!std::holds_alternative<Commands>(*d.message) && !std::holds_alternative<Snapshot>(*d.message) &&
        !std::holds_alternative<Ticks>(*d.message)) {
      EXPECT_EQ(encode(*d.message), bytes) << where;
      ++exact;
    }
  }
  EXPECT_GT(decoded, 300);
  EXPECT_GT(refused, 300);
  EXPECT_GT(exact, 100);
}

}  // namespace

namespace {

using rts::net::GameState;

// GameState: the part of a game's state runs to the end of the packet, so a shorter packet is a shorter
// part (no truncation to find); what decode checks is where the part lies in the whole.
TEST(NetProtocol, GameStatePartsRoundTripAndLieWithinTheState) {
  GameState part;
  part.tick = 106;
  part.totalBytes = 5000;
  part.offset = 1000;
  part.bytes = std::string(300, 'x');
  const std::vector<uint8_t> bytes = encode(part);
  ByteWriter w;
  w.u8(8);
  w.u32(106);
  w.u32(5000);
  w.u32(1000);
  w.bytes(part.bytes);
  EXPECT_EQ(bytes, bytesOf(w.data()));
  ASSERT_EQ(bytes.size(), kGameStateHeaderBytes + 300);
  const Decoded d = decodeBytes(bytes, DecodeContext{});
  ASSERT_TRUE(d.ok()) << d.error;
  const GameState& back = std::get<GameState>(*d.message);
  EXPECT_EQ(back.tick, 106u);
  EXPECT_EQ(back.totalBytes, 5000u);
  EXPECT_EQ(back.offset, 1000u);
  EXPECT_EQ(back.bytes, part.bytes);

  auto rawPart = [](uint32_t total, uint32_t offset, size_t n) {
    ByteWriter r;
    r.u8(8);
    r.u32(1);
    r.u32(total);
    r.u32(offset);
    r.bytes(std::string(n, 'y'));
    return bytesOf(r.data());
  };
  EXPECT_EQ(errorOf(rawPart(0, 0, 1)), "GameState.totalBytes = 0: expected 1 to 268435456");
  EXPECT_EQ(errorOf(rawPart(kMaxGameStateBytes + 1, 0, 1)),
            "GameState.totalBytes = 268435457: expected 1 to 268435456");
  EXPECT_EQ(errorOf(rawPart(10, 0, 0)), "GameState.bytes: 0 bytes: expected 1 to 1048563");
  EXPECT_EQ(errorOf(rawPart(10, 8, 3)), "GameState.offset = 8: its 3 bytes run past totalBytes = 10");
  EXPECT_EQ(errorOf(rawPart(UINT32_MAX, UINT32_MAX, 1)), "GameState.totalBytes = 4294967295: expected 1 to 268435456");
  EXPECT_TRUE(decodeBytes(rawPart(10, 7, 3), DecodeContext{}).ok());
  // The largest part fills a packet; one byte more is over it.
  EXPECT_TRUE(decodeBytes(rawPart(kMaxGameStateBytes, 0, kMaxGameStatePartBytes), DecodeContext{}).ok());
  EXPECT_EQ(errorOf(rawPart(kMaxGameStateBytes, 0, kMaxGameStatePartBytes + 1)).rfind("GameState", 0), 0u);
  std::vector<uint8_t> header = rawPart(10, 0, 1);
  header.resize(9);
  EXPECT_EQ(errorOf(header), "GameState.offset: truncated at byte 9 of 9 (needs 4 bytes, 0 left)");
  // encode refuses what decode would, in the same words.
  part.offset = 4900;
  EXPECT_EQ(encodeError(part), "GameState.offset = 4900: its 300 bytes run past totalBytes = 5000");
}

}  // namespace
