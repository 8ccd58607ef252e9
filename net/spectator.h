// A spectator of a lockstep game (rattle-demo --watch): a third process that follows a game under way
// from its host, never sends a command, and is never waited for by the players.
//
// A game is its map, its settings and the commands applied before each tick, so the spectator builds
// the game as the players did and plays the ticks the host sends it: the game so far in a few messages,
// then each tick as the host plays it (Ticks, net/protocol.h). A keyframe's state cannot be loaded into a
// Game (the game keeps more than a keyframe holds: flow fields, sensor contents, the engine's contacts),
// so the host's state at the tick the spectator joined (a Snapshot) is where the spectator checks its
// own in full, body by body; from then on the host's state hashes, on the players' interval and at the
// last tick, are compared with its own. A difference ends it as a player's desync does (exit status 4).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "game/commands.h"
#include "net/desync_report.h"
#include "net/lockstep.h"
#include "net/protocol.h"
#include "net/transport.h"

namespace rts::net {

class SpectatorSession : public CommandSource {
 public:
  /// `config.hello` is a spectator's Hello (spectatorHello); joinWaitSeconds is not used (the peer
  /// timeout bounds the connection attempt).
  SpectatorSession(Transport& transport, LockstepConfig config);

  /// Connects, exchanges Hellos (a difference: Refused), and waits for the host's state of the tick it
  /// joined at. Call once, with the game built as the players built theirs.
  void handshake(const class Game& game);
  /// The commands both players applied before `tick`, as the host sent them; waits for them.
  void commandsFor(uint32_t tick, const class Game& game, std::vector<Command>& out) override;
  /// After each Game::tick(): compares the state hash with the host's when it sent one, and the whole
  /// state with the host's at the tick it joined.
  void afterTick(const class Game& game);
  /// After the last tick: waits for the host's Bye and leaves.
  void finish(const class Game& game);
  /// This side leaves before the end (a person quit): tells the host with a Bye (it drops the spectator
  /// and plays on) and closes. Nothing else may be called after it.
  void quit();

  /// Ticks the host has sent that this side has not played yet: how far behind it is, for a loop that
  /// plays them faster to catch up (a window paced by the clock).
  size_t ticksReceived() const { return ticks_.size(); }

  /// The tick the spectator joined at: the host's state of it was compared in full.
  uint32_t joinedAt() const { return checkpointTick_; }
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
  [[noreturn]] void fail(SessionError::Kind kind, const std::string& line, const std::string& toPeer,
                         bool refuse = false);
  /// Ends the game as a desync: the line names `tick` and the two hashes there; the report compares the
  /// two states at `stateTick` when the host's is known (`host.state`), after `note`.
  [[noreturn]] void desync(uint32_t tick, uint64_t mine, uint64_t theirs, uint32_t stateTick, const SideState& mineThen,
                           const SideState& hostThen, const std::string& note);
  void say(const std::string& line) const;

  Transport& transport_;
  LockstepConfig config_;
  DecodeContext context_;
  const class Game* game_ = nullptr;
  bool handshaken_ = false;
  std::optional<Hello> hostHello_;
  std::optional<Snapshot> checkpoint_;
  uint32_t checkpointTick_ = 0;
  std::optional<uint64_t> checkpointHash_;  // the host's hash of the checkpoint's tick, when it sent one
  bool checkpointChecked_ = false;
  struct Mismatch {
    uint32_t tick;
    uint64_t mine, theirs;
  };
  // The first hash that differed while the game so far was played: reported at the checkpoint, where
  // the host's state is known and the fields that differ can be named.
  std::optional<Mismatch> firstMismatch_;
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
