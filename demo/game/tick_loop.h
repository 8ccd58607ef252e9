// The one loop a game is played with. rattle-demo (headless and in its window), rattle-replay's record
// and re-run, rattle-trace, the pinned-hash test and rattle-bench's arena all play a tick the same way:
// the commands of every source, asked in the order the sources were added, applied in that order, then
// the tick. A map, a seed and the same sources therefore give the same game in every one of them, and a
// recorder that writes what tick() returns writes what was played.
#pragma once

#include <vector>

#include "game/commands.h"

namespace rts {

class Game;

class TickLoop {
 public:
  explicit TickLoop(Game& game) : game_(game) {}

  /// Asked for its commands every tick from now on, after the sources added before it. Not owned: it
  /// must outlive the loop.
  void add(CommandSource& source) { sources_.push_back(&source); }

  /// The coming tick's commands from every source, applied (Game::apply drops those that name nothing);
  /// the tick itself is left to the caller, for a caller that measures it (rattle-bench). Returns them,
  /// valid until the next call.
  const std::vector<Command>& applyCommands();

  /// applyCommands(), then Game::tick(). Returns the commands of the tick, as a recorder writes them.
  const std::vector<Command>& tick();

  Game& game() const { return game_; }

 private:
  Game& game_;
  std::vector<CommandSource*> sources_;
  std::vector<Command> commands_;
};

}  // namespace rts
