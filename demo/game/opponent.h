// The scripted opponent: plays both teams from a seed, so a headless run is worth watching and the
// same seed gives the same game. It only issues commands (it reads the game, never changes it), so a
// recorded command log replays without it.
#pragma once

#include "game/commands.h"
#include "game/rng.h"

namespace rts {

class ScriptedOpponent : public CommandSource {
 public:
  /// `teams`: bit 0 plays team 0, bit 1 plays team 1 (the window leaves team 0 to the person).
  explicit ScriptedOpponent(uint64_t seed, unsigned teams = 3) : rng_(seed), teams_(teams) {}
  void commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) override;

 private:
  Rng rng_;
  unsigned teams_;
};

}  // namespace rts
