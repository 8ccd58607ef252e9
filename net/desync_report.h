// What both sides of a desync print under its first line ("desync at tick T: mine H1, theirs H2"): the
// bodies whose digests differ and every field that differs, by how much. The differences are found by
// the code rattle-replay verify uses (replay/tool/divergence.h) from the two sides' states at the tick
// (each side has sent the other its own in a Snapshot message), and the lines read as verify's do, with
// "mine" and "theirs" for its "recorded" and "now".
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "format/replay.h"
#include "game/game.h"

namespace rts::net {

/// One side's state at the tick of a desync.
struct SideState {
  uint64_t stateHash = 0;  ///< Game::stateHash()
  uint64_t worldHash = 0;  ///< Game::worldHash(): the engine's part
  /// replay::snapshotOf(game); the peer's is empty when it did not fit a message.
  std::optional<replay::Snapshot> state;
};

/// The report's lines, each indented by two spaces and ended by a newline, e.g.
///   engine world hash: matches (the difference is in the game's own state)
///   bodies that differ at tick 101 (1): unit 10 (red)
///   fields at tick 101:
///     unit 10 (red) order.active: mine false, theirs true
/// `game` names the bodies (units by team, gates by name); it may be at a later tick than `tick`.
/// With hashes compared every `hashEvery` ticks, a line says the games may have parted earlier. Without
/// the peer's state, a line says there is nothing to compare, and why.
std::string desyncDetails(uint32_t tick, const SideState& mine, const SideState& theirs, const Game& game,
                          uint32_t hashEvery);

}  // namespace rts::net
