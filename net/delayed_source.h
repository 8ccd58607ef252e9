// Input delay: the commands a source issues at tick t are applied at tick t + d. Lockstep needs the d
// ticks to carry them to the other side before they are due; a game without a network that plays
// with the same delay plays the same game, which is how the tests check the networked one.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "game/commands.h"

namespace rts::net {

class DelayedSource : public CommandSource {
 public:
  /// `inner` must outlive this; it is asked once a tick, with the game as it is at that tick.
  DelayedSource(CommandSource& inner, uint32_t delayTicks) : inner_(inner), delay_(delayTicks) {}

  /// Asks the inner source for tick `tick`'s commands and keeps them for tick + delay, stamped so.
  /// Returns them (what a lockstep side sends). Ticks must come in order, one call each.
  const std::vector<Command>& issue(uint32_t tick, const Game& game);
  /// Adds `command` to what the last issue() kept, stamped for the same tick: a command of the session's
  /// own (a ReloadWorld for a spectator), applied where the inner source's would be.
  void addToLastIssued(Command command);
  /// Appends the commands kept for `tick` to `out` and forgets them; the first `delay` ticks have none.
  void takeDue(uint32_t tick, std::vector<Command>& out);

  /// issue(tick), then takeDue(tick): the delayed source as a TickLoop plays it.
  void commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) override;

  uint32_t delay() const { return delay_; }

 private:
  CommandSource& inner_;
  uint32_t delay_;
  std::deque<std::vector<Command>> pending_;  // pending_[i]: for tick firstPending_ + i
  uint32_t firstPending_ = 0;
  uint32_t nextIssue_ = 0;
};

}  // namespace rts::net
