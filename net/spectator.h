// A spectator of a lockstep game (rattle-demo --watch): a third process that follows a game under way
// from its host, never sends a command, and is never waited for by the players.
//
// It starts from the host's state: the host puts a ReloadWorld command in its next set of commands (tick
// T), and at T, before that set, sends its game's state (Game::saveState, in GameState parts). The
// spectator's game takes it (Game::restoreState) and plays on from T with the commands the host sends
// (Ticks, net/protocol.h); the ReloadWorld makes the players' worlds load from their saves at T as the
// spectator's did, so the three step alike. From T on the host's state hashes, on the players' interval
// and at the last tick, are compared with its own. A difference ends it as a player's desync does
// (exit status 4).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "game/commands.h"
#include "net/lockstep.h"
#include "net/protocol.h"
#include "net/transport.h"

namespace rts::net {

class SpectatorSession : public CommandSource {
 public:
  /// `config.hello` is a spectator's Hello (spectatorHello); joinWaitSeconds is not used (the peer
  /// timeout bounds the connection attempt).
  SpectatorSession(Transport& transport, LockstepConfig config);

  /// Connects, exchanges Hellos (a difference: Refused), waits for the host's state and gives it to
  /// `game` (built from the same map and settings as the players'), which is then at the tick the
  /// spectator joined. A state the game refuses ends the session as the host's garbage (Protocol).
  void handshake(class Game& game);
  /// The commands both players applied before `tick`, as the host sent them; waits for them.
  void commandsFor(uint32_t tick, const class Game& game, std::vector<Command>& out) override;
  /// After each Game::tick(): compares the state hash with the host's when it sent one.
  void afterTick(const class Game& game);
  /// After the last tick: waits for the host's Bye and leaves.
  void finish(const class Game& game);
  /// This side leaves before the end (a person quit): tells the host with a Bye (it drops the spectator
  /// and plays on) and closes. Nothing else may be called after it.
  void quit();

  /// Ticks the host has sent that this side has not played yet: how far behind it is, for a loop that
  /// plays them faster to catch up (a window paced by the clock).
  size_t ticksReceived() const { return ticks_.size(); }

  /// The tick the spectator joined at: its game started from the host's state there.
  uint32_t joinedAt() const { return joinedAt_; }
  /// The bytes of that state.
  size_t stateBytes() const { return stateSize_; }
  uint32_t hashesCompared() const { return hashesCompared_; }
  double waitedSeconds() const { return waited_; }

 private:
  using Clock = std::chrono::steady_clock;

  void waitFor(const std::function<bool()>& ready, const std::string& what);
  /// One round of a wait for the person behind whileWaiting; throws LeftGame when it asks to leave.
  void waitingRound(const std::string& what, Clock::time_point start);
  double roundSeconds(double limit) const;
  void handle(TransportEvent event);
  void receiveTicks(Ticks& m);
  void receiveState(GameState& m);
  [[noreturn]] void fail(SessionError::Kind kind, const std::string& line, const std::string& toPeer,
                         bool refuse = false);
  /// Ends the game as a desync: the line names `tick` and the two hashes there.
  [[noreturn]] void desync(uint32_t tick, uint64_t mine, uint64_t theirs);
  void say(const std::string& line) const;

  Transport& transport_;
  LockstepConfig config_;
  DecodeContext context_;
  bool handshaken_ = false;
  std::optional<Hello> hostHello_;
  // The host's state as its GameState parts come: `state_` grows to stateSize_ bytes.
  std::string state_;
  size_t stateSize_ = 0;
  bool stateComplete_ = false;
  uint32_t joinedAt_ = 0;
  std::deque<Ticks::Entry> ticks_;  // received, not yet played: ticks_[0] is of tick nextPlay_
  uint32_t nextPlay_ = 0;           // the tick commandsFor gives next
  uint32_t nextReceive_ = 0;        // the tick the host's next Ticks message must start at
  std::optional<uint64_t> dueHash_;  // the host's hash of the tick being played
  uint32_t hashesCompared_ = 0;
  bool hostGone_ = false, hostSaidBye_ = false;
  std::string hostGoneWhy_;
  Clock::time_point lastHeard_;
  double waited_ = 0;
};

}  // namespace rts::net
