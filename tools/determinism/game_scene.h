// The game scene rattle-trace and the pinned-hash test play: a map, a unit count a team and a step mode,
// with the scripted opponent playing both teams through the game's one tick loop (rts::TickLoop), so both
// programs play the same game tick for tick.
#pragma once

#include <rattle/world.h>

#include <cstdint>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"

namespace rattle_trace {

class GameScene {
 public:
  GameScene(const rts::Map& map, rattle::StepMode mode, int unitsPerTeam, uint64_t seed);
  GameScene(const GameScene&) = delete;  // the loop holds the game and the opponent
  GameScene& operator=(const GameScene&) = delete;

  /// One tick; returns the game's state hash after it.
  uint64_t tick();

 private:
  rts::Game game_;
  rts::ScriptedOpponent opponent_;
  rts::TickLoop loop_;
};

}  // namespace rattle_trace
