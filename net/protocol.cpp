#include "net/protocol.h"

#include <cmath>
#include <cstdio>
#include <new>
#include <stdexcept>
#include <string_view>

#include "format/byte_reader.h"
#include "format/byte_writer.h"
#include "format/command_codec.h"
#include "format/limits.h"
#include "format/snapshot_codec.h"

namespace rts::net {
namespace {

using replay::ByteReader;
using replay::ByteWriter;
using replay::FormatError;

// Strings are sent with a u8 length.
static_assert(kMaxEngineVersionBytes <= 255 && kMaxReasonBytes <= 255);
static_assert(kMaxCommandsPerMessage <= UINT16_MAX);

// The fewest bytes a command takes (type, team, then a unit count or a gate, a varint of 1 byte at
// least), so a count can be checked against the bytes left before anything is allocated for it.
constexpr size_t kMinCommandBytes = 3;

/// A message that breaks a rule: the whole line. decode returns it, encode throws it as invalid_argument.
class Refusal : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void refuse(const std::string& line) { throw Refusal(line); }

std::string str(uint64_t v) { return std::to_string(v); }

std::string hexByte(uint8_t b) {
  char text[8];
  std::snprintf(text, sizeof text, "0x%02x", b);
  return text;
}

const char* nameOf(MessageType t) {
  switch (t) {
    case MessageType::Hello:
      return "Hello";
    case MessageType::Refuse:
      return "Refuse";
    case MessageType::Commands:
      return "Commands";
    case MessageType::Hash:
      return "Hash";
    case MessageType::Bye:
      return "Bye";
    case MessageType::Snapshot:
      return "Snapshot";
    case MessageType::Ticks:
      return "Ticks";
    case MessageType::GameState:
      return "GameState";
  }
  return nullptr;
}
const char* nameOf(const Hello&) { return "Hello"; }
const char* nameOf(const Refuse&) { return "Refuse"; }
const char* nameOf(const Commands&) { return "Commands"; }
const char* nameOf(const Hash&) { return "Hash"; }
const char* nameOf(const Bye&) { return "Bye"; }
const char* nameOf(const Snapshot&) { return "Snapshot"; }
const char* nameOf(const Ticks&) { return "Ticks"; }
const char* nameOf(const GameState&) { return "GameState"; }

// ---- The rules, shared by decode (as it reads) and encode (before it writes) ----

void checkText(const std::string& field, std::string_view s, size_t limit) {
  if (s.size() > limit) refuse(field + " length = " + str(s.size()) + " exceeds the limit " + str(limit));
  // Reasons and versions are printed: a control byte or an escape sequence would reach the terminal.
  for (size_t i = 0; i < s.size(); ++i) {
    const uint8_t c = uint8_t(s[i]);
    if (c < 0x20 || c > 0x7e)
      refuse(field + ": byte " + str(i) + " is " + hexByte(c) + ", not printable ASCII (0x20 to 0x7e)");
  }
}

void checkUnitsPerTeam(uint32_t v) {
  if (v < 1 || v > replay::kMaxUnitsPerTeam) {
    refuse("Hello.unitsPerTeam = " + str(v) + " is out of range (1 to " + str(replay::kMaxUnitsPerTeam) + ")");
  }
}

void checkStepMode(rattle::StepMode m) {
  if (uint8_t(m) > uint8_t(rattle::StepMode::Predictive)) {
    refuse("Hello.stepMode = " + str(uint8_t(m)) + " is not a step mode (0 hybrid, 1 discrete, 2 predictive)");
  }
}

void checkInputDelay(uint16_t v) {
  if (v > kMaxInputDelayTicks)
    refuse("Hello.inputDelayTicks = " + str(v) + " exceeds the limit " + str(kMaxInputDelayTicks));
}

void checkHashInterval(uint16_t v) {
  if (v < 1) refuse("Hello.hashIntervalTicks = 0 is below the minimum 1");
}

void checkRoleAndTeam(Role role, uint8_t team) {
  if (role == Role::Player) {
    if (team > 1) refuse("Hello.team = " + str(team) + ": a player's team is 0 (blue) or 1 (red)");
  } else if (role == Role::Spectator) {
    if (team != 0) refuse("Hello.team = " + str(team) + ": a spectator's team is 0");
  } else {
    refuse("Hello.role = " + str(uint8_t(role)) + " is not a role (0 player, 1 spectator)");
  }
}

void checkTicks(uint32_t v) {
  if (v > kMaxGameTicks) refuse("Hello.ticks = " + str(v) + " exceeds the limit " + str(kMaxGameTicks));
}

void checkSteering(Steering s) {
  if (uint8_t(s) > uint8_t(Steering::Naive)) {
    refuse("Hello.steering = " + str(uint8_t(s)) + " is not a steering (0 keep-apart, 1 naive)");
  }
}

void checkHello(const Hello& h) {
  checkText("Hello.engineVersion", h.engineVersion, kMaxEngineVersionBytes);
  checkUnitsPerTeam(h.unitsPerTeam);
  checkStepMode(h.stepMode);
  checkInputDelay(h.inputDelayTicks);
  checkHashInterval(h.hashIntervalTicks);
  checkRoleAndTeam(h.role, h.team);
  checkTicks(h.ticks);
  checkSteering(h.steering);
}

void checkMessageTeam(uint8_t team) {
  if (team > 1) refuse("Commands.team = " + str(team) + ": expected 0 (blue) or 1 (red)");
}

void checkCount(size_t n) {
  if (n > kMaxCommandsPerMessage)
    refuse("Commands.count = " + str(n) + " exceeds the limit " + str(kMaxCommandsPerMessage));
}

std::string commandField(size_t i) { return "Commands.commands[" + str(i) + "]"; }

// A peer speaks for its own team only: its commands for the other team's units would be ignored by the
// game anyway, and a gate toggled in the other team's name is not its to toggle.
void checkCommandTeam(size_t i, uint8_t commandTeam, uint8_t messageTeam) {
  if (commandTeam != messageTeam) {
    refuse(commandField(i) + " team = " + str(commandTeam) + " differs from Commands.team = " + str(messageTeam) +
           " (a peer sends its own team's commands only)");
  }
}

// What the command codec's decoder refuses on its own; encode checks it so as never to send it. The
// words are the codec's.
void checkCommandFields(const std::string& field, const Command& c) {
  const uint8_t type = uint8_t(c.type);
  if (type < uint8_t(CommandType::Move) || type > uint8_t(CommandType::ReloadWorld)) {
    refuse(field + " type: unknown command type " + str(type) + " (1 move, 2 stop, 3 toggle gate, 4 reload world)");
  }
  if (c.type == CommandType::Move) {
    if (!std::isfinite(c.target.x)) refuse(field + " target.x: not a finite number");
    if (!std::isfinite(c.target.y)) refuse(field + " target.y: not a finite number");
  }
}

void checkCommands(const Commands& m) {
  checkMessageTeam(m.team);
  checkCount(m.commands.size());
  for (size_t i = 0; i < m.commands.size(); ++i) {
    checkCommandFields(commandField(i), m.commands[i]);
    checkCommandTeam(i, m.commands[i].team, m.team);
  }
}

std::string entryField(size_t i) { return "Ticks.entries[" + str(i) + "]"; }

void checkTickCount(size_t n) {
  if (n < 1) refuse("Ticks.count = 0 is below the minimum 1");
  if (n > kMaxTicksPerMessage) refuse("Ticks.count = " + str(n) + " exceeds the limit " + str(kMaxTicksPerMessage));
}

void checkFirstTick(uint32_t first, size_t n) {
  if (uint64_t(first) + n > kMaxGameTicks) {
    refuse("Ticks.firstTick = " + str(first) + ": its " + str(n) + " ticks run past the limit " + str(kMaxGameTicks));
  }
}

void checkEntryCount(size_t i, size_t n) {
  if (n > kMaxCommandsPerTick) {
    refuse(entryField(i) + " count = " + str(n) + " exceeds the limit " + str(kMaxCommandsPerTick));
  }
}

// Both teams' commands of a tick, team 0's first: the order both players applied them in, which the
// spectator must apply them in too.
void checkEntryOrder(size_t i, size_t j, uint8_t previousTeam, uint8_t team) {
  if (team > 1) refuse(entryField(i) + " commands[" + str(j) + "] team = " + str(team) + ": expected 0 or 1");
  if (team < previousTeam) {
    refuse(entryField(i) + " commands[" + str(j) + "] team = " + str(team) +
           " after team " + str(previousTeam) + " (team 0's commands come first)");
  }
}

void checkTicksMessage(const Ticks& m) {
  checkTickCount(m.entries.size());
  checkFirstTick(m.firstTick, m.entries.size());
  for (size_t i = 0; i < m.entries.size(); ++i) {
    const Ticks::Entry& e = m.entries[i];
    checkEntryCount(i, e.commands.size());
    uint8_t previous = 0;
    for (size_t j = 0; j < e.commands.size(); ++j) {
      checkCommandFields(entryField(i) + " commands[" + str(j) + "]", e.commands[j]);
      checkEntryOrder(i, j, previous, e.commands[j].team);
      previous = e.commands[j].team;
    }
  }
}

std::string packetTooLarge(const char* name, size_t size) {
  return std::string(name) + ": packet of " + str(size) + " bytes exceeds the limit " + str(kMaxPacketBytes);
}

// ---- Encoding ----

void writeText(ByteWriter& out, const std::string& s) {
  out.u8(uint8_t(s.size()));
  out.bytes(s);
}

void write(ByteWriter& out, const Hello& h) {
  checkHello(h);
  out.u8(uint8_t(MessageType::Hello));
  out.u32(h.protocolVersion);
  writeText(out, h.engineVersion);
  out.u64(h.mapDigest);
  out.u64(h.seed);
  out.u32(h.unitsPerTeam);
  out.u8(uint8_t(h.stepMode));
  out.u16(h.inputDelayTicks);
  out.u16(h.hashIntervalTicks);
  out.u8(uint8_t(h.role));
  out.u8(h.team);
  out.u32(h.ticks);
  out.u8(uint8_t(h.steering));
}

void write(ByteWriter& out, const Refuse& r) {
  checkText("Refuse.reason", r.reason, kMaxReasonBytes);
  out.u8(uint8_t(MessageType::Refuse));
  writeText(out, r.reason);
}

void write(ByteWriter& out, const Commands& m) {
  checkCommands(m);
  out.u8(uint8_t(MessageType::Commands));
  out.u32(m.tick);
  out.u8(m.team);
  out.u16(uint16_t(m.commands.size()));
  for (const Command& c : m.commands) {
    replay::encodeCommand(out, c);
    // Stop at the first command past the limit rather than writing all of them first.
    if (out.size() > kMaxPacketBytes) throw Refusal(packetTooLarge("Commands", out.size()));
  }
}

void write(ByteWriter& out, const Hash& h) {
  out.u8(uint8_t(MessageType::Hash));
  out.u32(h.tick);
  out.u64(h.stateHash);
}

void write(ByteWriter& out, const Bye& b) {
  checkText("Bye.reason", b.reason, kMaxReasonBytes);
  out.u8(uint8_t(MessageType::Bye));
  writeText(out, b.reason);
}

// The sizes a state has, as decodeSnapshot needs them.
replay::ReplayConfig shapeOf(const replay::Snapshot& s) {
  replay::ReplayConfig c;
  c.unitCount = uint32_t(s.units.size());
  c.gateCount = uint32_t(s.gates.size());
  c.doorwayCount = uint32_t(s.counters.doorwayCrossings.size());
  c.roomCount = uint32_t(s.counters.roomHolders.size());
  return c;
}

void write(ByteWriter& out, const Snapshot& m) {
  out.u8(uint8_t(MessageType::Snapshot));
  out.u32(m.tick);
  out.u64(m.worldHash);
  out.u8(m.state ? 1 : 0);
  if (!m.state) return;
  const size_t start = out.size();
  replay::encodeSnapshot(out, *m.state);
  const size_t n = out.size() - start;
  if (n > kMaxSnapshotStateBytes) {
    refuse("Snapshot.state: " + str(n) + " bytes exceeds the limit " + str(kMaxSnapshotStateBytes));
  }
  // The keyframe codec's decoder has rules of its own (finite doubles, ascending shot ids, room holders
  // in range): read the bytes back with it rather than restate them here, so that nothing is sent that
  // the peer would refuse. Once a game, after a desync: the cost does not matter.
  replay::ByteReader back(std::string_view(out.data()).substr(start), start);
  try {
    replay::decodeSnapshot(back, shapeOf(*m.state), "Snapshot.state");
  } catch (const FormatError& e) {
    refuse(e.field() + ": " + e.what());
  }
}

void write(ByteWriter& out, const Ticks& m) {
  checkTicksMessage(m);
  out.u8(uint8_t(MessageType::Ticks));
  out.u32(m.firstTick);
  out.u16(uint16_t(m.entries.size()));
  for (const Ticks::Entry& e : m.entries) {
    out.u16(uint16_t(e.commands.size()));
    for (const Command& c : e.commands) replay::encodeCommand(out, c);
    out.u8(e.stateHash ? 1 : 0);
    if (e.stateHash) out.u64(*e.stateHash);
    if (out.size() > kMaxPacketBytes) throw Refusal(packetTooLarge("Ticks", out.size()));
  }
}

// The part's place in the state: decode's rule, which encode keeps too.
void checkGameStatePart(uint32_t total, uint32_t offset, size_t n) {
  if (total < 1 || total > kMaxGameStateBytes) {
    refuse("GameState.totalBytes = " + str(total) + ": expected 1 to " + str(kMaxGameStateBytes));
  }
  if (n < 1 || n > kMaxGameStatePartBytes) {
    refuse("GameState.bytes: " + str(n) + " bytes: expected 1 to " + str(kMaxGameStatePartBytes));
  }
  if (uint64_t(offset) + n > total) {
    refuse("GameState.offset = " + str(offset) + ": its " + str(n) + " bytes run past totalBytes = " + str(total));
  }
}

void write(ByteWriter& out, const GameState& m) {
  checkGameStatePart(m.totalBytes, m.offset, m.bytes.size());
  out.u8(uint8_t(MessageType::GameState));
  out.u32(m.tick);
  out.u32(m.totalBytes);
  out.u32(m.offset);
  out.bytes(m.bytes);
}

// ---- Decoding ----

// Reads one packet. Fixed-width fields are checked for length here, so that truncations read the same
// whatever the field; the command codec's own errors (FormatError) are put in the same words by run().
class Decoder {
 public:
  Decoder(const uint8_t* data, size_t size, const DecodeContext& context)
      : in_(std::string_view(reinterpret_cast<const char*>(data), size), 0), size_(size) {
    config_.unitCount = context.unitCount;
    config_.gateCount = context.gateCount;
    config_.doorwayCount = context.doorwayCount;
    config_.roomCount = context.roomCount;
  }

  Message run() {
    if (size_ == 0) refuse("empty packet: no message type");
    const uint8_t type = in_.u8("message type");
    name_ = nameOf(MessageType(type));
    if (name_ == nullptr)
      refuse("message type " + str(type) +
             " is unknown (1 Hello, 2 Refuse, 3 Commands, 4 Hash, 5 Bye, 6 Snapshot, 7 Ticks, 8 GameState)");
    if (size_ > kMaxPacketBytes) refuse(packetTooLarge(name_, size_));
    try {
      Message m = body(MessageType(type));
      if (!in_.atEnd()) {
        const size_t n = in_.remaining();
        refuse(std::string(name_) + ": " + str(n) + (n == 1 ? " byte" : " bytes") +
               " after the end of the message (from byte " + str(in_.offset()) + " of " + str(size_) + ")");
      }
      return m;
    } catch (const FormatError& e) {
      refuse(describe(e) + versionHint());
    } catch (const Refusal& r) {
      refuse(r.what() + versionHint());
    }
  }

 private:
  Message body(MessageType type) {
    switch (type) {
      case MessageType::Hello:
        return hello();
      case MessageType::Refuse:
        return Refuse{text("Refuse.reason", kMaxReasonBytes)};
      case MessageType::Commands:
        return commands();
      case MessageType::Hash: {
        Hash h;
        h.tick = u32("Hash.tick");
        h.stateHash = u64("Hash.stateHash");
        return h;
      }
      case MessageType::Bye:
        return Bye{text("Bye.reason", kMaxReasonBytes)};
      case MessageType::Snapshot:
        return snapshot();
      case MessageType::Ticks:
        return ticks();
      case MessageType::GameState: {
        GameState g;
        g.tick = u32("GameState.tick");
        g.totalBytes = u32("GameState.totalBytes");
        g.offset = u32("GameState.offset");
        const size_t n = in_.remaining();
        checkGameStatePart(g.totalBytes, g.offset, n);
        g.bytes = std::string(in_.bytes("GameState.bytes", n));
        return g;
      }
    }
    refuse("message type " + str(uint8_t(type)) + " is unknown");
  }

  Hello hello() {
    Hello h;
    h.protocolVersion = u32("Hello.protocolVersion");
    peerVersion_ = h.protocolVersion;
    h.engineVersion = text("Hello.engineVersion", kMaxEngineVersionBytes);
    h.mapDigest = u64("Hello.mapDigest");
    h.seed = u64("Hello.seed");
    h.unitsPerTeam = u32("Hello.unitsPerTeam");
    checkUnitsPerTeam(h.unitsPerTeam);
    h.stepMode = rattle::StepMode(u8("Hello.stepMode"));
    checkStepMode(h.stepMode);
    h.inputDelayTicks = u16("Hello.inputDelayTicks");
    checkInputDelay(h.inputDelayTicks);
    h.hashIntervalTicks = u16("Hello.hashIntervalTicks");
    checkHashInterval(h.hashIntervalTicks);
    h.role = Role(u8("Hello.role"));
    h.team = u8("Hello.team");
    checkRoleAndTeam(h.role, h.team);
    h.ticks = u32("Hello.ticks");
    checkTicks(h.ticks);
    h.steering = Steering(u8("Hello.steering"));
    checkSteering(h.steering);
    return h;
  }

  Commands commands() {
    Commands m;
    m.tick = u32("Commands.tick");
    m.team = u8("Commands.team");
    checkMessageTeam(m.team);
    const uint16_t count = u16("Commands.count");
    checkCount(count);
    if (count > in_.remaining() / kMinCommandBytes) {
      refuse("Commands.count = " + str(count) + ": truncated at byte " + str(in_.offset()) + " of " + str(size_) +
             " (" + str(count) + (count == 1 ? " command needs" : " commands need") + " at least " +
             str(size_t(count) * kMinCommandBytes) + " bytes, " + str(in_.remaining()) + " left)");
    }
    m.commands.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      m.commands.push_back(replay::decodeCommand(in_, config_, m.tick, commandField(i)));
      checkCommandTeam(i, m.commands.back().team, m.team);
    }
    return m;
  }

  // Every count is checked against the bytes left before anything is allocated for it: an entry takes
  // at least 3 bytes (its count and its hash flag), a command kMinCommandBytes.
  Ticks ticks() {
    Ticks m;
    m.firstTick = u32("Ticks.firstTick");
    const uint16_t count = u16("Ticks.count");
    checkTickCount(count);
    checkFirstTick(m.firstTick, count);
    constexpr size_t kMinEntryBytes = 3;
    if (count > in_.remaining() / kMinEntryBytes) {
      refuse("Ticks.count = " + str(count) + ": truncated at byte " + str(in_.offset()) + " of " + str(size_) + " (" +
             str(count) + (count == 1 ? " tick needs" : " ticks need") + " at least " +
             str(size_t(count) * kMinEntryBytes) + " bytes, " + str(in_.remaining()) + " left)");
    }
    m.entries.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      const std::string field = entryField(i);
      Ticks::Entry& e = m.entries.emplace_back();
      const uint16_t n = u16(field + " count");
      checkEntryCount(i, n);
      // Its hash flag and the ticks after it need bytes too: counting them keeps what the commands
      // reserve, with what the ticks reserved, within a small multiple of the packet.
      const size_t later = (size_t(count) - i - 1) * kMinEntryBytes + 1;
      const size_t room = in_.remaining() > later ? in_.remaining() - later : 0;
      if (n > room / kMinCommandBytes) {
        refuse(field + " count = " + str(n) + ": truncated at byte " + str(in_.offset()) + " of " + str(size_) +
               " (" + str(n) + (n == 1 ? " command needs" : " commands need") + " at least " +
               str(size_t(n) * kMinCommandBytes) + " bytes, " + str(room) + " left for them)");
      }
      e.commands.reserve(n);
      uint8_t previous = 0;
      for (size_t j = 0; j < n; ++j) {
        e.commands.push_back(
            replay::decodeCommand(in_, config_, uint32_t(m.firstTick + i), field + " commands[" + str(j) + "]"));
        checkEntryOrder(i, j, previous, e.commands.back().team);
        previous = e.commands.back().team;
      }
      const uint8_t hashed = u8(field + " hasHash");
      if (hashed > 1) refuse(field + " hasHash = " + str(hashed) + ": expected 0 or 1");
      if (hashed == 1) e.stateHash = u64(field + " stateHash");
    }
    return m;
  }

  // The state runs to the end of the packet, in the keyframe codec's bytes, for this game's sizes: its
  // decoder checks every count against the bytes left before allocating, as it does in a replay file.
  Snapshot snapshot() {
    Snapshot s;
    s.tick = u32("Snapshot.tick");
    s.worldHash = u64("Snapshot.worldHash");
    const uint8_t hasState = u8("Snapshot.hasState");
    if (hasState > 1) {
      refuse("Snapshot.hasState = " + str(hasState) + ": expected 0 (the state did not fit a packet) or 1");
    }
    if (hasState == 1) s.state = replay::decodeSnapshot(in_, config_, "Snapshot.state");
    return s;
  }

  void need(const std::string& field, size_t n) {
    if (in_.remaining() < n) {
      refuse(field + ": truncated at byte " + str(in_.offset()) + " of " + str(size_) + " (needs " + str(n) +
             (n == 1 ? " byte, " : " bytes, ") + str(in_.remaining()) + " left)");
    }
  }
  uint8_t u8(const std::string& field) { return need(field, 1), in_.u8(field); }
  uint16_t u16(const std::string& field) { return need(field, 2), in_.u16(field); }
  uint32_t u32(const std::string& field) { return need(field, 4), in_.u32(field); }
  uint64_t u64(const std::string& field) { return need(field, 8), in_.u64(field); }

  std::string text(const std::string& field, size_t limit) {
    const uint8_t n = u8(field + " length");
    if (n > limit) refuse(field + " length = " + str(n) + " exceeds the limit " + str(limit));
    need(field, n);
    std::string s(in_.bytes(field, n));
    checkText(field, s, limit);
    return s;
  }

  // The codec's errors, in this file's words: a field that runs past the end is "truncated at byte N of
  // SIZE" whichever way the codec found out (a short fixed field, a varint cut short, a count of more
  // items than the bytes left could hold).
  std::string describe(const FormatError& e) const {
    const std::string why = e.what();
    const bool cut = why.rfind("truncated", 0) == 0 || why.find("cannot fit in the") != std::string::npos;
    if (!cut) return e.field() + ": " + why;
    std::string detail = why;
    if (detail.rfind("truncated: ", 0) == 0) {
      detail.erase(0, 11);
    } else if (detail.rfind("truncated ", 0) == 0) {
      detail.erase(0, 10);
    }
    return e.field() + ": truncated at byte " + str(e.offset()) + " of " + str(size_) + " (" + detail + ")";
  }

  // A Hello from another protocol version may be laid out differently: say so, or its error would
  // look like a broken peer rather than an old or new one.
  std::string versionHint() const {
    if (!peerVersion_ || *peerVersion_ == kProtocolVersion) return "";
    return " (the peer speaks protocol version " + str(*peerVersion_) + "; this build speaks " + str(kProtocolVersion) +
           ")";
  }

  ByteReader in_;
  size_t size_;
  replay::ReplayConfig config_;
  const char* name_ = nullptr;
  std::optional<uint32_t> peerVersion_;
};

}  // namespace

const char* messageName(const Message& m) {
  return std::visit([](const auto& v) { return nameOf(v); }, m);
}

std::vector<uint8_t> encode(const Message& m) {
  ByteWriter out;
  try {
    std::visit([&out](const auto& v) { write(out, v); }, m);
    if (out.size() > kMaxPacketBytes) refuse(packetTooLarge(messageName(m), out.size()));
  } catch (const Refusal& r) {
    throw std::invalid_argument(r.what());
  }
  const std::string& bytes = out.data();
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

Decoded decode(const uint8_t* data, size_t size, const DecodeContext& context) noexcept {
  Decoded result;
  if (data == nullptr) size = 0;
  try {
    result.message = Decoder(data, size, context).run();
  } catch (const Refusal& r) {
    result.message.reset();
    try {
      result.error = r.what();
    } catch (...) {
      result.error = "out of memory";
    }
  } catch (const std::bad_alloc&) {
    // Short enough for std::string's own buffer: assigning it allocates nothing.
    result.message.reset();
    result.error = "out of memory";
  } catch (...) {
    result.message.reset();
    result.error = "internal error";
  }
  return result;
}

}  // namespace rts::net
