// The lockstep wire protocol (issue 26): the messages two peers of a networked game exchange, their bytes,
// and the handshake's comparison. No sockets here: the transport (net/transport.h, on ENet) carries one
// message a packet. net/README.md describes the bytes.
//
// Packets come from the network, so decode() trusts nothing, as the replay reader does: every field is
// range-checked, every count is checked against the bytes left before anything is allocated, and the
// first problem comes back as one line naming the message, the field, the value and why. It never throws.
#pragma once

#include <rattle/types.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "format/replay.h"
#include "game/commands.h"
#include "game/steering.h"

namespace rts::net {

/// Bumped on any change to the bytes below. Both sides send it in Hello, and handshakeMismatch refuses
/// a peer whose version differs, so a newer build never misreads an older one's commands.
/// Version 2 added Snapshot (type 6), the state each side sends the other after a desync. Version 3
/// added Hello.ticks and Hello.steering (the handshake compares them) and Ticks (type 7), what a host
/// sends a spectator. Version 4 added the ReloadWorld command (type 4) and GameState (type 8): a spectator
/// starts from the host's state instead of playing the game from tick 0.
inline constexpr uint32_t kProtocolVersion = 4;

// ---- Limits (decode refuses anything beyond them, encode throws) ----

/// A whole packet. Enough for one Move of every unit of the largest team a replay allows (200,000 ids
/// of at most 3 bytes each, 600 KB); a transport can hand this to ENet as its largest packet, so a peer
/// cannot make the other buffer more.
inline constexpr size_t kMaxPacketBytes = size_t(1) << 20;
/// Hello.engineVersion: "rattle 0.1.0" and the like, the BILD chunk's `engine` fact; 64 bytes as the
/// replay's build-fact keys. It is printed in refusals, so it must be short and printable.
inline constexpr size_t kMaxEngineVersionBytes = 64;
/// Refuse.reason and Bye.reason: one line for a person to read (the handshake's mismatch line is
/// shorter). Printable ASCII only, since it reaches a terminal: no escape sequences, no newlines.
inline constexpr size_t kMaxReasonBytes = 200;
/// Commands in one Commands message (one team, one tick). A person issues a few a tick and the scripted
/// opponent at most 9 (8 squads and a gate); 1024 is far above both, and caps what a packet of empty
/// commands decodes to (3 bytes each on the wire, about 60 in memory).
inline constexpr size_t kMaxCommandsPerMessage = 1024;
/// Hello.inputDelayTicks. Ten seconds at 30 ticks a second: a longer delay is no longer a game, and a
/// peer buffers up to this many ticks of the other side's commands, so it bounds that buffer.
inline constexpr uint16_t kMaxInputDelayTicks = 300;
// Hello.unitsPerTeam is 1 to rts::replay::kMaxUnitsPerTeam (replay/format/limits.h), as a replay's.
/// Snapshot's fields before the state: type, tick, worldHash, hasState.
inline constexpr size_t kSnapshotHeaderBytes = 14;
/// Snapshot.state: what is left of one packet. A live unit with an order takes about 56 bytes and a
/// shot about 45, so this holds the state of a game of some 8,000 units a team with thousands of shots
/// in flight (the demo plays 100 by default); a larger game's state is not sent (a Snapshot without
/// one), and the desync report says so. One packet, not parts: a peer never makes the other assemble
/// more than a packet.
inline constexpr size_t kMaxSnapshotStateBytes = kMaxPacketBytes - kSnapshotHeaderBytes;
/// Hello.ticks: rattle-demo's --ticks limit. A game is that many ticks long; two sides that would stop at
/// different ticks do not play one game.
inline constexpr uint32_t kMaxGameTicks = 100'000'000;
/// Ticks.count: ticks in one Ticks message. A host sends a spectator the game so far in messages of at
/// most this many ticks (and well under a packet); an entry takes at least 3 bytes, so this also caps
/// what one message decodes to.
inline constexpr size_t kMaxTicksPerMessage = 4096;
/// GameState.totalBytes: a game's state (Game::saveState) at most. It took 280 bytes a unit at 100 units
/// a team and 470 at 5,000 (the world's body and its two fixtures, the game's unit and what it sees), so
/// 256 MiB holds the largest game a replay allows (200,000 a team: about 190 MB).
inline constexpr uint32_t kMaxGameStateBytes = uint32_t(1) << 28;
/// GameState's fields before its part of the state: type, tick, totalBytes, offset.
inline constexpr size_t kGameStateHeaderBytes = 13;
/// The most of the state one GameState carries: what is left of a packet.
inline constexpr size_t kMaxGameStatePartBytes = kMaxPacketBytes - kGameStateHeaderBytes;
/// Ticks entry's command count: both teams' commands of one tick.
inline constexpr size_t kMaxCommandsPerTick = 2 * kMaxCommandsPerMessage;

// ---- Messages ----

/// The first byte of every packet. The numbers are stable: changing one takes a new kProtocolVersion.
enum class MessageType : uint8_t {
  Hello = 1,
  Refuse = 2,
  Commands = 3,
  Hash = 4,
  Bye = 5,
  Snapshot = 6,
  Ticks = 7,
  GameState = 8,
};

enum class Role : uint8_t { Player = 0, Spectator = 1 };

/// The first message each side sends. Two sides play together only when handshakeMismatch finds
/// nothing: the same build of the same game, from the same map, seed and settings.
struct Hello {
  uint32_t protocolVersion = kProtocolVersion;
  std::string engineVersion;  ///< "rattle 0.1.0": the engine's arithmetic changes between versions
  uint64_t mapDigest = 0;     ///< FNV-1a 64 of the map file's bytes (as a replay's MAPJ hash)
  uint64_t seed = 0;
  uint32_t unitsPerTeam = 1;
  rattle::StepMode stepMode = rattle::StepMode::Hybrid;
  uint16_t inputDelayTicks = 0;    ///< commands issued at tick t are stamped t + this
  uint16_t hashIntervalTicks = 1;  ///< state hashes are exchanged every this many ticks (at least 1)
  Role role = Role::Player;
  uint8_t team = 0;  ///< a player's team, 0 (blue) or 1 (red); 0 for a spectator
  uint32_t ticks = 0;  ///< the game's length in ticks (rattle-demo --ticks), 0 to kMaxGameTicks
  Steering steering = Steering::KeepApart;  ///< GameConfig::steering: it changes the game
};

/// Sent instead of play when the handshake fails (or the game is full); the connection then closes.
struct Refuse {
  std::string reason;
};

/// One team's commands for one tick, sent every tick, empty or not: a tick runs only when every
/// player's set for it has arrived.
struct Commands {
  uint32_t tick = 0;
  uint8_t team = 0;  ///< the sender's team; every command carries it too
  /// Each one's `tick` is not sent: decode sets it to `tick` above, encode ignores it.
  std::vector<rts::Command> commands;
};

/// Game::stateHash() after tick `tick`, every hashIntervalTicks ticks.
struct Hash {
  uint32_t tick = 0;
  uint64_t stateHash = 0;
};

/// The sender is leaving (the game ended, the player quit, the other side sent garbage).
struct Bye {
  std::string reason;
};

/// After a desync at `tick`, each side sends the other its state at that tick, so that both can name the
/// bodies and fields that differ with the code rattle-replay verify uses (replay/tool/divergence.h).
/// Sent once, only after hashes for `tick` differed.
struct Snapshot {
  uint32_t tick = 0;
  uint64_t worldHash = 0;  ///< Game::worldHash() after `tick`: the engine's part of the state hash
  /// Every body, exactly, as a replay's keyframe holds it. Empty when it would not fit a packet
  /// (kMaxSnapshotStateBytes): the peer then learns that none is coming rather than waiting for it.
  std::optional<rts::replay::Snapshot> state;
};

/// What a host sends its spectator: the ticks played, in order, each with the commands both teams applied
/// before it (team 0's first, as the players apply them) and, on the hash interval and at the game's last
/// tick, the host's state hash after it. The spectator plays them and compares the hashes.
struct Ticks {
  struct Entry {
    /// Each one's `tick` is not sent: decode sets it to the entry's tick.
    std::vector<rts::Command> commands;
    std::optional<uint64_t> stateHash;  ///< Game::stateHash() once the tick is played (tickCount = tick + 1)
  };
  uint32_t firstTick = 0;  ///< the tick of entries[0]; entries[i] is of firstTick + i
  std::vector<Entry> entries;  ///< 1 to kMaxTicksPerMessage
};

/// A part of the host's game state at the start of tick `tick` (Game::saveState, before the commands of
/// `tick`, one of which is the ReloadWorld that makes the players' worlds the spectator's): what a spectator
/// starts from. A state over a packet goes in parts, in order, each starting where the last ended.
struct GameState {
  uint32_t tick = 0;
  uint32_t totalBytes = 0;  ///< the whole state's, 1 to kMaxGameStateBytes
  uint32_t offset = 0;      ///< where `bytes` starts within the state
  std::string bytes;        ///< to the end of the packet: 1 to kMaxGameStatePartBytes, within totalBytes
};

using Message = std::variant<Hello, Refuse, Commands, Hash, Bye, Snapshot, Ticks, GameState>;

/// "Hello", "Refuse", "Commands", "Hash", "Bye", "Snapshot", "Ticks", "GameState": how errors and logs
/// name a message.
const char* messageName(const Message& m);

// ---- Bytes ----

/// One message's bytes: the type, then its fields, little-endian, fixed width; strings as a u8 length
/// and the bytes; commands as the replay's command codec writes them (FORMAT.md, "Commands").
/// Throws std::invalid_argument, naming the field as decode would, when the message breaks a rule
/// decode enforces, except the commands' unit ids and gates and a snapshot's sizes, which need the
/// game's (the receiver checks those). Never sends what the other side would refuse for any other
/// reason. A Snapshot's state is written as a replay's keyframe (format/snapshot_codec.h).
std::vector<uint8_t> encode(const Message& m);

/// What decoding needs to know about the game: unit ids must be below unitCount and gates below
/// gateCount (as rts::replay::decodeCommand checks them), and a Snapshot holds exactly this many units,
/// gates, doorways and rooms (as a replay's keyframe). Before the handshake, when the game is not built
/// yet, the default (nothing) decodes every message except Commands that name a unit or a gate and
/// Snapshots of a game with anything in it.
struct DecodeContext {
  uint32_t unitCount = 0;     ///< Game::units().size(): both teams
  uint32_t gateCount = 0;     ///< the map's gates
  uint32_t doorwayCount = 0;  ///< Game::doorways().size()
  uint32_t roomCount = 0;     ///< Game::rooms().size()
};

/// A decoded packet: the message, or why the bytes are not one.
struct Decoded {
  std::optional<Message> message;
  /// One line when `message` is empty, e.g. "Commands.count = 1025 exceeds the limit 1024" or
  /// "Hello.engineVersion: truncated at byte 23 of 23 (needs 12 bytes, 0 left)". It starts with the
  /// message's name once the type byte is known ("empty packet", "message type 9 ..." otherwise).
  std::string error;
  bool ok() const { return message.has_value(); }
};

/// Decodes one packet of `size` bytes (data may be null when size is 0). Refuses packets over
/// kMaxPacketBytes, unknown message types, any field out of range or over its limit, non-printable
/// strings, commands the game's sizes forbid or that are not the message's team's, snapshots of a game
/// of other sizes or with a value a replay's keyframe may not hold, and any byte after a complete
/// message. Never throws, never reads outside the bytes, allocates at most a small multiple
/// of `size`.
Decoded decode(const uint8_t* data, size_t size, const DecodeContext& context) noexcept;

// ---- Handshake ----

/// Whether two sides may play together, from the Hello each sent. nullopt when they may; otherwise one
/// line naming every difference with both values, mine first, e.g.
///   seed: mine 7, theirs 8; step mode: mine hybrid, theirs discrete
/// Compared: protocol version, engine version, map digest, seed, units a team, step mode, steering,
/// ticks, input delay, hash interval. Two players on the same team do not go together either, nor do two spectators.
std::optional<std::string> handshakeMismatch(const Hello& mine, const Hello& theirs);

}  // namespace rts::net
