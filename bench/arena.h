// rattle-bench: the `arena` scene: the demo's game (demo/game), played headless on the demo's default map
// (assets/maps/arena.json) by the scripted opponent from a seed, with its engine in one of rattle's step
// modes. The game ticks at its own fixed rate (rts::Game::kTickSeconds, 1/30 s) and times its own engine
// step (Physics::step, around World::step alone), so the benchmark reads the step times from the game and
// measures the errors after each tick (arena_measure.h).
//
// A library, not part of the rattle-bench program, so that the tests can play a short game with it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "arena_measure.h"
#include "game/commands.h"
#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"

namespace rattle_bench {

struct ArenaParams {
  int unitsPerTeam = 100;
  uint64_t seed = 1;  ///< the scripted opponent's seed
  rattle::StepMode mode = rattle::StepMode::Hybrid;
  std::string map;  ///< empty: defaultArenaMap()
};

/// The demo's default map in the source tree this was built from, or assets/maps/arena.json under the
/// current directory when the source tree is gone.
std::string defaultArenaMap();

class ArenaGame {
 public:
  /// Loads the map and places the units. Throws rts::MapError (the map) or rts::GameError (the units do
  /// not fit).
  explicit ArenaGame(const ArenaParams& params);
  ArenaGame(const ArenaGame&) = delete;  // the loop holds the opponent it asks
  ArenaGame& operator=(const ArenaGame&) = delete;

  /// One tick: the scripted opponent's commands, Game::tick (which times the engine step), then the
  /// measures. `measureOverlaps` false skips the overlap measure this tick (the others always run).
  void tick(bool measureOverlaps = true);

  const rts::Game& game() const { return *game_; }
  ArenaTotals totals() const { return meter_->totals(*game_); }

 private:
  std::unique_ptr<rts::Game> game_;
  rts::ScriptedOpponent opponent_;
  std::unique_ptr<ArenaMeter> meter_;
  rts::TickLoop loop_;
};

}  // namespace rattle_bench
