// One side of a two-player lockstep game (issue 26), as a CommandSource: the game is played through
// rts::TickLoop as every other game is, with this session as its only source.
//
// Each tick t the local source (the scripted opponent for this side's team, later a person) is asked
// for its commands; they are stamped for t + d (the input delay) and sent, empty or not. Tick t runs
// once both teams' sets for t are here, team 0's applied before team 1's on both sides, so both sides
// apply the same commands in the same order at the same tick: the same game. The first d ticks have
// empty sets. Every k ticks each side sends its state hash and compares it with the other's.
//
// What decides which commands run at which tick is the tick each message carries, never when it
// arrived: waiting only stalls the game. The clock decides one thing, when to give up on a silent peer.
//
// Every way a session ends early is a SessionError of one kind with one line saying why. Before it is
// thrown the other side is told (a Refuse or a Bye) and the connection is closed, so neither hangs.
//
// A desync is also explained: each side keeps its state (replay::snapshotOf) at every hashed tick until
// the peer's hash for it has come, so that when the two differ each can send the other its state at that
// very tick (a Snapshot message), though it may have played a few ticks further. Both then name the
// bodies and fields that differ with the code rattle-replay verify uses (net/desync_report.h).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "game/commands.h"
#include "net/delayed_source.h"
#include "net/desync_report.h"
#include "net/protocol.h"
#include "net/transport.h"

namespace rts::net {

class SessionError : public std::runtime_error {
 public:
  enum class Kind {
    Refused,   ///< the handshake failed on this side or the other ("seed: mine 7, theirs 8")
    Desync,    ///< the two states differ ("desync at tick T: mine H1, theirs H2"), details() says how
    PeerLost,  ///< the peer could not be reached, disconnected, went silent, or left before the end
    Protocol,  ///< the peer sent garbage or a message out of turn
  };
  SessionError(Kind kind, const std::string& line, std::string details = "")
      : std::runtime_error(line), kind_(kind), details_(std::move(details)) {}
  Kind kind() const { return kind_; }
  /// More lines under what(), each indented and ended by a newline; empty but for a desync, where they
  /// are the report (net/desync_report.h) or why the peer's state did not come.
  const std::string& details() const { return details_; }

 private:
  Kind kind_;
  std::string details_;
};

/// This side left the game while a wait was under way: LockstepConfig::whileWaiting returned false (a
/// person closed the window). Not an error of the game: the peer has been told (a Bye, so it ends with
/// "the peer left") and the connection is closed. what(): whom and what this side was waiting for.
class LeftGame : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The limits a packet is decoded against, read off the game both sides play (its units, gates, doorways
/// and rooms): a player and a spectator take them the same way.
DecodeContext decodeContextOf(const class Game& game);

struct LockstepConfig {
  /// This side's Hello: its team, the input delay and the hash interval are the session's.
  Hello hello;
  /// A peer not heard from for this long is given up on (and ENet gives up a little later).
  double peerTimeoutSeconds = 10;
  /// A host waits this long for a player to join; 0: as long as it takes. A joiner waits the peer
  /// timeout for its connection to be accepted.
  double joinWaitSeconds = 0;
  /// Where lines for a person go (waiting, why it ended): one line each, no newline. May be empty.
  std::function<void(const std::string&)> log;
  /// A host on a transport with a spectator slot: a spectator that connects is sent the game so far and
  /// then every tick as it is played (net/README.md, "Spectators"). It is never waited for.
  bool acceptSpectator = false;
  /// Called on every round of a wait for the peer, and for the peer to connect, with whom and what this
  /// side waits for ("team 1 (red): its commands for tick 12", "the host: tick 40") and the seconds the
  /// wait has lasted: a window handles its events and draws here, so it stays responsive. With it set a
  /// round polls the network for at most kWaitingRoundSeconds. Returning false leaves the game: the
  /// session quits (as quit() does) and the wait throws LeftGame. Empty: the waits only poll.
  std::function<bool(const std::string& what, double seconds)> whileWaiting;
};

/// The longest a round of a wait polls the network when LockstepConfig::whileWaiting is set: a window
/// then handles its events and draws some 60 times a second while it waits.
inline constexpr double kWaitingRoundSeconds = 1.0 / 60;

/// A spectator more messages than this behind (sent and not acknowledged) is dropped: the players go
/// on, and the host keeps no more for it. Some 30 s of play at one message a tick; the game so far goes
/// in messages of up to kMaxTicksPerMessage ticks.
inline constexpr size_t kMaxSpectatorBacklog = 1024;
/// A Ticks message the host sends is kept under this many bytes (and kMaxTicksPerMessage ticks), so
/// that the game so far goes in pieces a lossy link resends cheaply.
inline constexpr size_t kTicksMessageBudget = 64 * 1024;

class LockstepSession : public CommandSource {
 public:
  /// `transport` and `local` must outlive the session. `local` is asked for this side's commands and
  /// may only issue its team's (a std::logic_error otherwise).
  LockstepSession(Transport& transport, CommandSource& local, LockstepConfig config);

  /// Waits for the connection, exchanges Hellos and compares them; on a difference both sides send
  /// Refuse and throw Refused. Then sends the hash of tick 0. Call once, before the first tick, with
  /// the game both sides built (its sizes check the peer's commands).
  void handshake(const class Game& game);

  /// Sends this side's commands for tick + d, then waits until both teams' for `tick` are here and
  /// appends them, team 0's first. Throws SessionError.
  void commandsFor(uint32_t tick, const class Game& game, std::vector<Command>& out) override;

  /// After each Game::tick(): sends the state hash when due and compares it with the peer's.
  void afterTick(const class Game& game);

  /// After the last tick: sends the final hash (when the interval did not), then Bye, and waits for
  /// the peer's, comparing the hashes that are still to come. Throws SessionError when the peer's
  /// game ended at another tick, or as any wait does.
  void finish(const class Game& game);

  /// This side leaves before the end (a person quit): tells the peer with a Bye (the peer ends with "the
  /// peer left", never waiting for its timeout) and the spectator, lingers up to a second for them to
  /// have it, and closes. Nothing else may be called after it. Says nothing to a peer not connected.
  void quit();

  /// Seconds spent waiting for the peer during the game (the handshake not counted).
  double waitedSeconds() const { return waited_; }
  /// The longest single wait among those: the worst stall.
  double longestWaitSeconds() const { return longestWait_; }
  /// State hashes compared with the peer's so far.
  uint32_t hashesCompared() const { return hashesCompared_; }
  uint8_t team() const { return config_.hello.team; }
  /// Spectators that were sent the game (one at a time), and the last one's fate, for the summary.
  uint32_t spectatorsServed() const { return spectatorsServed_; }

 private:
  enum class SpectatorState { None, AwaitingHello, AwaitingReload, Watching };
  void handleSpectator(TransportEvent& event);
  /// Sends the spectator the ticks played that it has not had yet, or drops it when it is too far behind.
  void feedSpectator();
  /// At the spectator's start tick, before its commands: sends the spectator the game's state in parts
  /// (GameState) and starts feeding it ticks from there.
  void startSpectator(const class Game& game);
  /// Tells the spectator why (a Refuse or a Bye), closes its connection; the game goes on.
  void dropSpectator(const std::string& line, const std::string& toSpectator, bool refuse);

  using Clock = std::chrono::steady_clock;

  void send(const Message& message);
  /// Polls until `ready()` holds, handling what arrives. `what` ends the waiting line: "its commands
  /// for tick 12". Throws when the peer is gone or silent for the timeout.
  void waitFor(const std::function<bool()>& ready, const std::string& what);
  void handle(TransportEvent event);
  void handleMessage(Message& message);
  void receiveCommands(Commands& message);
  void receiveHash(const Hash& hash);
  void receiveSnapshot(Snapshot& message);
  /// Sends this side's hash of the game's tick and compares it, or keeps it (with the state) for the
  /// peer's.
  void myHash(const class Game& game);
  void compare(uint32_t tick, SideState mine, uint64_t theirs);
  /// The hashes of `tick` differ: sends this side's state, waits for the peer's, throws Desync with the
  /// report.
  [[noreturn]] void desync(uint32_t tick, SideState mine, uint64_t theirs);
  /// Tells the peer (a Refuse when `refuse`, else a Bye with `toPeer`), closes, throws.
  [[noreturn]] void fail(SessionError::Kind kind, const std::string& line, const std::string& toPeer,
                         bool refuse = false);
  /// Says `lastWord` when there is one, lingers up to `lingerSeconds` for the peer to have everything
  /// sent, closes, throws `error`.
  [[noreturn]] void leave(const std::optional<Message>& lastWord, double lingerSeconds, const SessionError& error);
  /// leave() without the throw: the spectator is sent a Bye with `toSpectator`.
  void closeAll(const std::optional<Message>& lastWord, double lingerSeconds, const std::string& toSpectator);
  /// One round of a wait for the person behind whileWaiting; throws LeftGame when it asks to leave.
  void waitingRound(const std::string& what, Clock::time_point start);
  /// How long a round of a wait may poll: `limit`, or less with whileWaiting set.
  double roundSeconds(double limit) const;
  void say(const std::string& line) const;
  std::string peerName() const;
  std::string silentFor(Clock::time_point now) const;

  Transport& transport_;
  DelayedSource local_;
  LockstepConfig config_;
  DecodeContext context_;
  uint8_t peerTeam_ = 1;
  uint32_t delay_ = 0;
  uint32_t hashEvery_ = 1;
  bool handshaken_ = false;
  std::optional<Hello>* peerHello_ = nullptr;  // where the peer's Hello goes while the handshake waits for it

  uint32_t nextTick_ = 0;          // the tick commandsFor expects next
  int64_t sentThrough_ = -1;       // this side's sets are with the peer up to this tick (the first d free)
  uint32_t nextPeerCommands_ = 0;  // the tick of the peer's next Commands message
  std::map<uint32_t, std::vector<Command>> peerCommands_;
  uint32_t nextPeerHash_ = 0;   // the tick of the peer's next Hash on the interval
  int64_t lastPeerHash_ = -1;   // the tick of the peer's last Hash
  bool peerFinalHash_ = false;  // the peer sent a hash off the interval: its game is over
  // Not yet compared, by tick. This side's come with its state, for a desync's report; there are at most
  // about d + 2 of them, since the peer's commands for a tick come after its hashes of d ticks earlier.
  std::map<uint32_t, SideState> myHashes_;
  std::map<uint32_t, uint64_t> peerHashes_;
  uint32_t hashesCompared_ = 0;
  const class Game* game_ = nullptr;    // the game of the handshake: names bodies in a desync's report
  std::optional<uint32_t> desyncTick_;  // hashes differed here: only the peer's state is awaited
  std::optional<SideState> peerState_;  // its Snapshot of that tick
  bool byeSent_ = false;                // this side's last Bye has gone: no other one follows

  bool peerGone_ = false;  // Bye or a disconnect: nothing more will come
  bool peerSaidBye_ = false;
  bool peerDisconnected_ = false;
  std::string peerGoneWhy_;
  Clock::time_point lastHeard_;
  double waited_ = 0;
  double longestWait_ = 0;

  // What a spectator is sent: from its start tick on, every tick played, with the commands applied
  // before it and the hash after it when one is due (the interval, the last tick). Sent as soon as
  // played: toSpectator_ holds only what feedSpectator has not sent yet.
  std::vector<Ticks::Entry> toSpectator_;
  std::vector<Command> applying_;  // the commands of the tick being played, for toSpectator_
  SpectatorState spectator_ = SpectatorState::None;
  uint32_t startTick_ = 0;     // the spectator's: this side's ReloadWorld command is in that tick's set
  size_t spectatorNext_ = 0;   // the tick of toSpectator_[0]
  size_t stateFragments_ = 0;  // the spectator's backlog right after its state went, until it drains
  uint32_t spectatorsServed_ = 0;
};

}  // namespace rts::net
