// A Game's bodies as a Snapshot (format/replay.h): what keyframes store and digests hash.
#pragma once

#include "format/replay.h"
#include "game/game.h"

namespace rts::replay {

/// Reads the game (and its world, through the public API); changes nothing.
Snapshot snapshotOf(const Game& game);

/// The parts of a replay's configuration that come from the game: sizes and settings.
ReplayConfig configOf(const Game& game);

}  // namespace rts::replay
