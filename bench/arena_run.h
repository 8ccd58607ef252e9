// rattle-bench: one run of the arena scene (the demo's game; bench/arena.h) and its row.
#pragma once

#include <stdexcept>

#include "options.h"

namespace rattle_bench {

/// The engine asked for cannot run the arena scene (only rattle's own modes step the game's world).
struct ArenaUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Plays o.scene.n units per team for o.seconds of game time, prints the row, returns the exit status.
/// Throws ArenaUnavailable for an engine other than discrete, hybrid or predictive; EngineUnavailable
/// when rattle-bench was built without the demo; SceneError when the map or the units do not work.
int runArena(const Options& o);

}  // namespace rattle_bench
