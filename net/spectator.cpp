#include "net/spectator.h"

#include <algorithm>
#include <cstdio>

#include "game/game.h"
#include "net/text.h"

namespace rts::net {
namespace {}  // namespace

SpectatorSession::SpectatorSession(Transport& transport, LockstepConfig config)
    : transport_(transport), config_(std::move(config)), lastHeard_(Clock::now()) {}

void SpectatorSession::say(const std::string& line) const {
  if (config_.log) config_.log(line);
}

void SpectatorSession::fail(SessionError::Kind kind, const std::string& line, const std::string& toPeer, bool refuse) {
  if (transport_.connected()) {
    try {
      if (refuse) {
        transport_.send(Refuse{reasonText(toPeer)});
      } else if (!toPeer.empty()) {
        transport_.send(Bye{reasonText(toPeer)});
      }
    } catch (const std::exception&) {
    }
    transport_.close(1.0);
  }
  throw SessionError(kind, line);
}

void SpectatorSession::desync(uint32_t tick, uint64_t mine, uint64_t theirs) {
  const std::string line =
      "desync at tick " + std::to_string(tick) + ": mine " + hexHash(mine) + ", the host's " + hexHash(theirs);
  const std::string details = "  the host sends a spectator its state only at the tick it joined (" +
                              std::to_string(joinedAt_) +
                              "), where the spectator started from it: there is nothing to compare body by body\n";
  if (transport_.connected()) {
    try {
      transport_.send(Bye{reasonText("the spectator's game differs: " + line)});
    } catch (const std::exception&) {
    }
    transport_.close(1.0);
  }
  throw SessionError(SessionError::Kind::Desync, line, details);
}

void SpectatorSession::handshake(Game& game) {
  if (handshaken_) throw std::logic_error("SpectatorSession: handshake() twice");
  context_ = decodeContextOf(game);
  transport_.setPeerTimeout(config_.peerTimeoutSeconds + 1);
  const Clock::time_point start = Clock::now();
  while (!transport_.connected()) {
    waitingRound("the host to answer", start);
    const TransportEvent event = transport_.poll(roundSeconds(0.25), context_);
    if (event.kind == TransportEvent::Kind::Disconnected) {
      fail(SessionError::Kind::PeerLost,
           "cannot connect: no answer after " +
               secondsText(std::chrono::duration<double>(Clock::now() - start).count()) +
               " s (is a game hosted there, on that port, with a player joined? a host takes one spectator at a "
               "time)",
           "");
    }
  }
  lastHeard_ = Clock::now();
  transport_.send(config_.hello);
  waitFor([&] { return hostHello_.has_value(); }, "its Hello");
  if (hostHello_->role != Role::Player) {
    fail(SessionError::Kind::Refused, "the handshake failed: the host is not a player", "you are not a player", true);
  }
  if (const std::optional<std::string> mismatch = handshakeMismatch(config_.hello, *hostHello_)) {
    fail(SessionError::Kind::Refused, "the handshake failed: " + *mismatch, *mismatch, true);
  }
  handshaken_ = true;
  waitFor([&] { return stateComplete_; }, "its state (the game under way)");
  try {
    game.restoreState(state_);
  } catch (const GameError& e) {
    const std::string why = std::string("its game's state does not load: ") + e.what();
    fail(SessionError::Kind::Protocol, "the host sent a bad state: " + why,
         std::string("your state does not load here: ") + e.what());
  }
  if (game.tickCount() != joinedAt_) {
    fail(SessionError::Kind::Protocol,
         "the host sent a bad state: it is of tick " + std::to_string(game.tickCount()) + ", its GameState said " +
             std::to_string(joinedAt_),
         "your state's tick differs from its GameState's");
  }
  std::string().swap(state_);
  nextPlay_ = joinedAt_;
  say("watching from tick " + std::to_string(joinedAt_) + ", the host's state loaded (" + std::to_string(stateSize_) +
      " bytes)");
}

void SpectatorSession::commandsFor(uint32_t tick, const Game&, std::vector<Command>& out) {
  if (!handshaken_) throw std::logic_error("SpectatorSession: commandsFor() before handshake()");
  if (tick != nextPlay_) {
    throw std::logic_error("SpectatorSession: commandsFor(" + std::to_string(tick) + "), expected tick " +
                           std::to_string(nextPlay_));
  }
  for (;;) {
    TransportEvent event = transport_.poll(0, context_);
    if (event.kind == TransportEvent::Kind::None) break;
    handle(std::move(event));
  }
  waitFor([&] { return !ticks_.empty(); }, "tick " + std::to_string(tick));
  Ticks::Entry& e = ticks_.front();
  for (Command& c : e.commands) out.push_back(std::move(c));
  dueHash_ = e.stateHash;
  ticks_.pop_front();
  ++nextPlay_;
}

void SpectatorSession::afterTick(const Game& game) {
  if (!dueHash_) return;
  const uint64_t mine = game.stateHash();
  const uint64_t theirs = *dueHash_;
  dueHash_.reset();
  ++hashesCompared_;
  if (mine != theirs) desync(game.tickCount(), mine, theirs);
}

void SpectatorSession::finish(const Game& game) {
  waitFor([&] { return hostSaidBye_; }, "the end of its game");
  if (!ticks_.empty() || nextReceive_ != game.tickCount()) {
    fail(SessionError::Kind::PeerLost,
         "the host's game ended after tick " + std::to_string(nextReceive_) + " and this side's after tick " +
             std::to_string(game.tickCount()),
         "");
  }
  transport_.close(1.0);
}

void SpectatorSession::quit() {
  if (!transport_.connected()) return;
  say("leaving: the host is told");
  try {
    transport_.send(Bye{"the spectator quit"});
  } catch (const std::exception&) {
  }
  transport_.close(1.0);
}

double SpectatorSession::roundSeconds(double limit) const {
  return config_.whileWaiting ? std::min(limit, kWaitingRoundSeconds) : limit;
}

void SpectatorSession::waitingRound(const std::string& what, Clock::time_point start) {
  if (!config_.whileWaiting) return;
  if (!config_.whileWaiting(what, std::chrono::duration<double>(Clock::now() - start).count())) {
    quit();
    throw LeftGame("waiting for " + what);
  }
}

void SpectatorSession::waitFor(const std::function<bool()>& ready, const std::string& what) {
  if (ready()) return;
  const Clock::time_point start = Clock::now();
  const auto timeout = std::chrono::duration<double>(config_.peerTimeoutSeconds);
  Clock::time_point nextReport = start + std::chrono::milliseconds(500);
  while (!ready()) {
    const Clock::time_point now = Clock::now();
    if (hostGone_) fail(SessionError::Kind::PeerLost, hostGoneWhy_ + " while this side waited for " + what, "");
    if (now - lastHeard_ >= timeout) {
      fail(SessionError::Kind::PeerLost,
           "the host has been silent for " + secondsText(std::chrono::duration<double>(now - lastHeard_).count()) +
               " s (the limit is " + secondsText(config_.peerTimeoutSeconds) + " s) while this side waited for " + what,
           "you were silent");
    }
    if (now >= nextReport) {
      say("waiting for the host: " + what + " (" + secondsText(std::chrono::duration<double>(now - start).count()) +
          " s so far)");
      nextReport = now + std::chrono::seconds(1);
    }
    waitingRound("the host: " + what, start);
    const auto slice = std::min<Clock::duration>(
        nextReport - now, std::chrono::duration_cast<Clock::duration>(lastHeard_ + timeout - now));
    handle(transport_.poll(std::clamp(std::chrono::duration<double>(slice).count(), 0.001, roundSeconds(0.25)),
                           context_));
  }
  if (handshaken_) waited_ += std::chrono::duration<double>(Clock::now() - start).count();
}

void SpectatorSession::handle(TransportEvent event) {
  switch (event.kind) {
    case TransportEvent::Kind::None:
      return;
    case TransportEvent::Kind::Connected:
      lastHeard_ = Clock::now();
      return;
    case TransportEvent::Kind::Disconnected:
      if (!hostGone_) hostGoneWhy_ = "the host disconnected";
      hostGone_ = true;
      return;
    case TransportEvent::Kind::Garbage:
      fail(SessionError::Kind::Protocol, "the host sent garbage: " + event.error, "you sent garbage: " + event.error);
    case TransportEvent::Kind::Received:
      break;
  }
  lastHeard_ = Clock::now();
  Message& m = *event.message;
  auto outOfTurn = [&](const std::string& why) {
    fail(SessionError::Kind::Protocol, "the host broke the protocol: " + why, "you broke the protocol: " + why);
  };
  if (hostSaidBye_) outOfTurn(std::string(messageName(m)) + " after its Bye");
  if (auto* hello = std::get_if<Hello>(&m)) {
    if (hostHello_) outOfTurn("a second Hello");
    hostHello_ = std::move(*hello);
  } else if (auto* refuse = std::get_if<Refuse>(&m)) {
    fail(SessionError::Kind::Refused, "the host refused the spectator, saying: " + refuse->reason, "");
  } else if (auto* bye = std::get_if<Bye>(&m)) {
    hostSaidBye_ = true;
    hostGoneWhy_ = "the host left (" + bye->reason + ")";
    // The game's end comes after its last tick; a Bye before it is the game ending early.
    if (nextReceive_ < config_.hello.ticks) hostGone_ = true;
  } else if (!hostHello_) {
    outOfTurn(std::string(messageName(m)) + " before its Hello");
  } else if (auto* state = std::get_if<GameState>(&m)) {
    receiveState(*state);
  } else if (auto* ticks = std::get_if<Ticks>(&m)) {
    if (!stateComplete_) outOfTurn("Ticks before its whole state (GameState)");
    receiveTicks(*ticks);
  } else {
    outOfTurn(std::string(messageName(m)) + ": a host sends a spectator Hello, GameState, Ticks and Bye only");
  }
}

void SpectatorSession::receiveState(GameState& m) {
  const auto why = [&](const std::string& text) {
    const std::string line =
        "GameState of tick " + std::to_string(m.tick) + " at byte " + std::to_string(m.offset) + ": " + text;
    fail(SessionError::Kind::Protocol, "the host broke the protocol: " + line, "you broke the protocol: " + line);
  };
  if (stateComplete_) why("the state came whole already (a host sends it once)");
  if (state_.empty()) {
    // The first part: the game's length was agreed, so the tick it starts at must leave some to play.
    if (m.offset != 0) why("the first part must start at byte 0");
    if (m.tick >= config_.hello.ticks) {
      why("past the game's " + std::to_string(config_.hello.ticks) + " ticks, nothing would be left to watch");
    }
    joinedAt_ = m.tick;
    stateSize_ = m.totalBytes;
    nextReceive_ = m.tick;
  } else if (m.tick != joinedAt_ || m.totalBytes != stateSize_ || m.offset != state_.size()) {
    why("expected tick " + std::to_string(joinedAt_) + ", " + std::to_string(stateSize_) + " bytes in all, from byte " +
        std::to_string(state_.size()));
  }
  state_ += m.bytes;
  stateComplete_ = state_.size() == stateSize_;
}

void SpectatorSession::receiveTicks(Ticks& m) {
  const auto why = [&](const std::string& text) {
    const std::string line = "Ticks from tick " + std::to_string(m.firstTick) + ": " + text;
    fail(SessionError::Kind::Protocol, "the host broke the protocol: " + line, "you broke the protocol: " + line);
  };
  if (m.firstTick != nextReceive_) why("expected tick " + std::to_string(nextReceive_) + " next");
  // The game's length was agreed in the handshake: this also bounds what the host can make this side keep.
  if (uint64_t(m.firstTick) + m.entries.size() > config_.hello.ticks) {
    why("past the game's " + std::to_string(config_.hello.ticks) + " ticks");
  }
  const uint32_t hashEvery = std::max<uint32_t>(1, config_.hello.hashIntervalTicks);
  for (size_t i = 0; i < m.entries.size(); ++i) {
    const uint32_t after = m.firstTick + uint32_t(i) + 1;  // the tick count its hash is of
    const bool due = after % hashEvery == 0 || after == config_.hello.ticks;
    if (due != m.entries[i].stateHash.has_value()) {
      why("tick " + std::to_string(after - 1) +
          (due ? " has no state hash (one is due after it)" : " has a state hash off the interval"));
    }
    for (Command& c : m.entries[i].commands) c.tick = after - 1;
    ticks_.push_back(std::move(m.entries[i]));
  }
  nextReceive_ += uint32_t(m.entries.size());
}

}  // namespace rts::net
