#include "net/delayed_source.h"

#include <stdexcept>
#include <string>

namespace rts::net {

const std::vector<Command>& DelayedSource::issue(uint32_t tick, const Game& game) {
  if (tick != nextIssue_) {
    throw std::logic_error("DelayedSource: issue(" + std::to_string(tick) + ") after tick " +
                           std::to_string(nextIssue_));
  }
  ++nextIssue_;
  // The first `delay` ticks are due before anything was issued: they have empty sets.
  if (pending_.empty()) firstPending_ = tick + delay_;
  std::vector<Command> issued;
  inner_.commandsFor(tick, game, issued);
  for (Command& c : issued) c.tick = tick + delay_;
  pending_.push_back(std::move(issued));
  return pending_.back();
}

void DelayedSource::addToLastIssued(Command command) {
  if (pending_.empty()) throw std::logic_error("DelayedSource: addToLastIssued() before issue()");
  command.tick = firstPending_ + uint32_t(pending_.size()) - 1;
  pending_.back().push_back(std::move(command));
}

void DelayedSource::takeDue(uint32_t tick, std::vector<Command>& out) {
  if (pending_.empty() || tick < firstPending_) return;
  if (tick != firstPending_) {
    throw std::logic_error("DelayedSource: takeDue(" + std::to_string(tick) + ") skips tick " +
                           std::to_string(firstPending_));
  }
  for (Command& c : pending_.front()) out.push_back(std::move(c));
  pending_.pop_front();
  ++firstPending_;
}

void DelayedSource::commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) {
  issue(tick, game);
  takeDue(tick, out);
}

}  // namespace rts::net
