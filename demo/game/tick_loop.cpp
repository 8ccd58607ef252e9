#include "game/tick_loop.h"

#include "game/game.h"

namespace rts {

const std::vector<Command>& TickLoop::applyCommands() {
  commands_.clear();
  for (CommandSource* source : sources_) source->commandsFor(game_.tickCount(), game_, commands_);
  for (const Command& c : commands_) game_.apply(c);
  return commands_;
}

const std::vector<Command>& TickLoop::tick() {
  applyCommands();
  game_.tick();
  return commands_;
}

}  // namespace rts
