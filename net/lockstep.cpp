#include "net/lockstep.h"

#include <algorithm>
#include <cstdio>

#include "game/game.h"
#include "net/text.h"
#include "tool/snapshot.h"

namespace rts::net {
namespace {

std::string teamName(uint8_t team) { return "team " + std::to_string(team) + (team == 0 ? " (blue)" : " (red)"); }

}  // namespace

LockstepSession::LockstepSession(Transport& transport, CommandSource& local, LockstepConfig config)
    : transport_(transport),
      local_(local, config.hello.inputDelayTicks),
      config_(std::move(config)),
      peerTeam_(config_.hello.team == 0 ? 1 : 0),
      delay_(config_.hello.inputDelayTicks),
      hashEvery_(std::max<uint32_t>(1, config_.hello.hashIntervalTicks)),
      sentThrough_(int64_t(delay_) - 1),
      nextPeerCommands_(delay_),
      lastHeard_(Clock::now()) {}

void LockstepSession::say(const std::string& line) const {
  if (config_.log) config_.log(line);
}

std::string LockstepSession::peerName() const { return teamName(peerTeam_); }

void LockstepSession::send(const Message& message) { transport_.send(message); }

void LockstepSession::fail(SessionError::Kind kind, const std::string& line, const std::string& toPeer, bool refuse) {
  std::optional<Message> lastWord;
  if (refuse) {
    lastWord = Refuse{reasonText(toPeer)};
  } else if (!toPeer.empty() && !byeSent_) {
    lastWord = Bye{reasonText(toPeer)};
  }
  leave(lastWord, 1.0, SessionError(kind, line));
}

void LockstepSession::leave(const std::optional<Message>& lastWord, double lingerSeconds, const SessionError& error) {
  closeAll(lastWord, lingerSeconds, std::string("the game ended early: ") + error.what());
  throw error;
}

void LockstepSession::closeAll(const std::optional<Message>& lastWord, double lingerSeconds,
                               const std::string& toSpectator) {
  if (transport_.spectatorConnected()) {
    try {
      transport_.sendToSpectator(Bye{reasonText(toSpectator)});
    } catch (const std::exception&) {
    }
    transport_.closeSpectator(1.0);
  }
  if (transport_.connected()) {
    try {
      if (lastWord) send(*lastWord);
    } catch (const std::exception&) {
      // The peer learns of the end from the disconnect instead.
    }
    transport_.close(lingerSeconds);
  }
}

void LockstepSession::quit() {
  const std::string why = "the player quit at tick " + std::to_string(game_ ? game_->tickCount() : 0);
  if (transport_.connected()) say("leaving the game: " + why + "; the peer is told");
  std::optional<Message> lastWord;
  // After this side's Bye (its game is over) the peer expects no other word.
  if (!byeSent_) lastWord = Bye{reasonText(why)};
  byeSent_ = true;
  closeAll(lastWord, 1.0, "the game ended early: " + why);
}

double LockstepSession::roundSeconds(double limit) const {
  return config_.whileWaiting ? std::min(limit, kWaitingRoundSeconds) : limit;
}

void LockstepSession::waitingRound(const std::string& what, Clock::time_point start) {
  if (!config_.whileWaiting) return;
  const std::string whom = handshaken_ || peerHello_ ? peerName() + ": " + what : what;
  if (!config_.whileWaiting(whom, std::chrono::duration<double>(Clock::now() - start).count())) {
    quit();
    throw LeftGame("waiting for " + whom);
  }
}

DecodeContext decodeContextOf(const Game& game) {
  DecodeContext context;
  context.unitCount = uint32_t(game.units().size());
  context.gateCount = uint32_t(game.map().gates.size());
  context.doorwayCount = uint32_t(game.doorways().size());
  context.roomCount = uint32_t(game.rooms().size());
  return context;
}

void LockstepSession::handshake(const Game& game) {
  if (handshaken_) throw std::logic_error("LockstepSession: handshake() twice");
  game_ = &game;
  context_ = decodeContextOf(game);
  // ENet gives up a second after this side would: the silence is then reported as silence.
  transport_.setPeerTimeout(config_.peerTimeoutSeconds + 1);

  const Clock::time_point start = Clock::now();
  std::optional<Hello> theirs;
  for (;;) {
    while (!transport_.connected()) {
      const double waited = std::chrono::duration<double>(Clock::now() - start).count();
      if (config_.joinWaitSeconds > 0 && waited >= config_.joinWaitSeconds) {
        fail(SessionError::Kind::PeerLost, "no player joined within " + secondsText(config_.joinWaitSeconds) + " s",
             "");
      }
      waitingRound("the other player to connect", start);
      const TransportEvent event = transport_.poll(roundSeconds(0.25), context_);
      if (event.kind == TransportEvent::Kind::Disconnected && !event.spectator) {
        fail(SessionError::Kind::PeerLost,
             "cannot connect: no answer after " +
                 secondsText(std::chrono::duration<double>(Clock::now() - start).count()) +
                 " s (is a host running there, on that port?)",
             "");
      }
    }
    lastHeard_ = Clock::now();
    send(config_.hello);

    peerHello_ = &theirs;
    waitFor([&] { return theirs.has_value(); }, "its Hello");
    peerHello_ = nullptr;
    // A spectator that comes before the second player has no game to watch yet: it is turned away and
    // the host waits on for its player.
    if (theirs->role == Role::Spectator && config_.acceptSpectator && config_.hello.role == Role::Player) {
      say("a spectator came before a player joined: it is turned away (watch once the game has started)");
      try {
        send(Refuse{"no game to watch yet: a player has not joined (watch once the game has started)"});
      } catch (const std::exception&) {
      }
      transport_.close(1.0);
      transport_.acceptAnotherPeer();
      theirs.reset();
      peerGone_ = peerSaidBye_ = peerDisconnected_ = false;
      peerGoneWhy_.clear();
      continue;
    }
    break;
  }
  if (const std::optional<std::string> mismatch = handshakeMismatch(config_.hello, *theirs)) {
    fail(SessionError::Kind::Refused, "the handshake failed: " + *mismatch, *mismatch, true);
  }
  if (theirs->role != Role::Player) {
    fail(SessionError::Kind::Refused, "the handshake failed: the peer is a spectator; this side needs a player",
         "this side plays; it takes a spectator only once its game has started", true);
  }
  handshaken_ = true;
  myHash(game);
}

void LockstepSession::commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) {
  if (!handshaken_) throw std::logic_error("LockstepSession: commandsFor() before handshake()");
  if (tick != nextTick_) {
    throw std::logic_error("LockstepSession: commandsFor(" + std::to_string(tick) + "), expected tick " +
                           std::to_string(nextTick_));
  }
  Commands mine;
  mine.tick = tick + delay_;
  mine.team = team();
  mine.commands = local_.issue(tick, game);
  if (spectator_ == SpectatorState::AwaitingReload && startTick_ == mine.tick) {
    // The spectator starts from this side's state at that tick: both players load their worlds then too.
    Command reload;
    reload.tick = mine.tick;
    reload.team = team();
    reload.type = CommandType::ReloadWorld;
    local_.addToLastIssued(reload);
    mine.commands.push_back(reload);
  }
  for (const Command& c : mine.commands) {
    if (c.team != team()) {
      throw std::logic_error("LockstepSession: the local source issued a command for team " + std::to_string(c.team) +
                             "; this side plays team " + std::to_string(team()));
    }
  }
  send(mine);
  sentThrough_ = int64_t(mine.tick);
  const size_t before = out.size();

  // Whatever has come meanwhile, so that acknowledgements go out even when nothing is missing.
  for (;;) {
    TransportEvent event = transport_.poll(0, context_);
    if (event.kind == TransportEvent::Kind::None) break;
    handle(std::move(event));
  }
  waitFor([&] { return tick < delay_ || peerCommands_.count(tick) != 0; },
          "its commands for tick " + std::to_string(tick));

  std::vector<Command> theirs;
  if (auto it = peerCommands_.find(tick); it != peerCommands_.end()) {
    theirs = std::move(it->second);
    peerCommands_.erase(it);
  }
  // Team 0's, then team 1's: the same order on both sides, whichever side this is.
  if (team() == 0) local_.takeDue(tick, out);
  for (Command& c : theirs) out.push_back(std::move(c));
  if (team() != 0) local_.takeDue(tick, out);
  if (config_.acceptSpectator) applying_.assign(out.begin() + std::ptrdiff_t(before), out.end());
  ++nextTick_;
}

void LockstepSession::afterTick(const Game& game) {
  if (spectator_ == SpectatorState::Watching) {
    Ticks::Entry entry;
    entry.commands = std::move(applying_);
    if (game.tickCount() % hashEvery_ == 0 || game.tickCount() == config_.hello.ticks) {
      entry.stateHash = game.stateHash();
    }
    toSpectator_.push_back(std::move(entry));
    feedSpectator();
  }
  applying_.clear();
  if (spectator_ == SpectatorState::AwaitingReload && game.tickCount() == startTick_) startSpectator(game);
  if (game.tickCount() % hashEvery_ == 0) myHash(game);
}

void LockstepSession::startSpectator(const Game& game) {
  const std::string state = game.saveState();
  if (state.size() > kMaxGameStateBytes) {
    dropSpectator("the game's state (" + std::to_string(state.size()) + " bytes) is over the " +
                      std::to_string(kMaxGameStateBytes) + " a spectator is sent; it is dropped",
                  "the game is too large to watch", false);
    return;
  }
  try {
    for (size_t at = 0; at < state.size(); at += kMaxGameStatePartBytes) {
      GameState part;
      part.tick = game.tickCount();
      part.totalBytes = uint32_t(state.size());
      part.offset = uint32_t(at);
      part.bytes = state.substr(at, kMaxGameStatePartBytes);
      transport_.sendToSpectator(part);
    }
  } catch (const std::exception& e) {
    dropSpectator(std::string("cannot send the spectator this side's state (") + e.what() + "); it is dropped", "",
                  false);
    return;
  }
  stateFragments_ = transport_.spectatorBacklog();
  spectator_ = SpectatorState::Watching;
  spectatorNext_ = game.tickCount();
  toSpectator_.clear();
  ++spectatorsServed_;
  say("a spectator is watching from tick " + std::to_string(game.tickCount()) + " (" + std::to_string(state.size()) +
      " bytes of state sent)");
}

void LockstepSession::handleSpectator(TransportEvent& event) {
  switch (event.kind) {
    case TransportEvent::Kind::None:
      return;
    case TransportEvent::Kind::Connected:
      if (!config_.acceptSpectator || !game_) {
        dropSpectator("a spectator connected; this side does not take spectators", "", false);
        return;
      }
      spectator_ = SpectatorState::AwaitingHello;
      say("a spectator connected");
      try {
        transport_.sendToSpectator(config_.hello);
      } catch (const std::exception&) {
      }
      return;
    case TransportEvent::Kind::Disconnected:
      if (spectator_ != SpectatorState::None) say("the spectator left; the game goes on");
      spectator_ = SpectatorState::None;
      toSpectator_.clear();
      return;
    case TransportEvent::Kind::Garbage:
      dropSpectator("the spectator sent garbage (" + event.error + "); it is dropped, the game goes on",
                    "you sent garbage: " + event.error, false);
      return;
    case TransportEvent::Kind::Received:
      break;
  }
  Message& m = *event.message;
  const Hello* hello = std::get_if<Hello>(&m);
  if (spectator_ != SpectatorState::AwaitingHello || !hello) {
    // A spectator only ever says Hello, and Bye when it leaves.
    if (std::holds_alternative<Bye>(m) || std::holds_alternative<Refuse>(m)) {
      dropSpectator("the spectator left; the game goes on", "", false);
    } else {
      const std::string why = std::string("a spectator sends nothing but its Hello (it sent ") + messageName(m) + ")";
      dropSpectator("the spectator broke the protocol: " + why + "; it is dropped, the game goes on",
                    "you broke the protocol: " + why, false);
    }
    return;
  }
  if (hello->role != Role::Spectator) {
    dropSpectator("a third player was turned away: the game has its two players",
                  "the game has its two players (join with --watch to watch it)", true);
    return;
  }
  if (const std::optional<std::string> mismatch = handshakeMismatch(config_.hello, *hello)) {
    dropSpectator("a spectator was refused: " + *mismatch, *mismatch, true);
    return;
  }
  // The spectator starts from this side's state at the first tick whose commands this side has not sent
  // yet: its own set for that tick then carries a ReloadWorld, so that the players' worlds are loaded from
  // their saves there, as the spectator's is (commands.h, ReloadWorld). Until then the game goes on.
  const uint32_t at = uint32_t(std::max<int64_t>(sentThrough_ + 1, int64_t(delay_)));
  if (at >= config_.hello.ticks) {
    dropSpectator("a spectator came too late: the game ends before tick " + std::to_string(at) +
                      ", the first it could start from",
                  "the game ends before a spectator could start (tick " + std::to_string(at) + ")", true);
    return;
  }
  spectator_ = SpectatorState::AwaitingReload;
  startTick_ = at;
  say("a spectator is let in: it starts from this side's state at tick " + std::to_string(at));
  if (game_->tickCount() == at) startSpectator(*game_);
}

void LockstepSession::feedSpectator() {
  if (spectator_ != SpectatorState::Watching) return;
  if (!transport_.spectatorConnected()) {
    spectator_ = SpectatorState::None;
    toSpectator_.clear();
    return;
  }
  const size_t backlog = transport_.spectatorBacklog();
  // The state's fragments (about one a kilobyte) went first: until they have drained, they do not count
  // against the spectator.
  if (backlog <= kMaxSpectatorBacklog) stateFragments_ = 0;
  if (backlog > kMaxSpectatorBacklog + stateFragments_) {
    dropSpectator("the spectator fell behind (" + std::to_string(backlog) +
                      " messages not acknowledged); it is dropped, the game goes on",
                  "you fell behind the game", false);
    return;
  }
  size_t next = 0;  // into toSpectator_
  while (next < toSpectator_.size()) {
    Ticks m;
    m.firstTick = uint32_t(spectatorNext_);
    size_t bytes = 7;
    while (next < toSpectator_.size() && m.entries.size() < kMaxTicksPerMessage) {
      const Ticks::Entry& e = toSpectator_[next];
      // A move is at most a few bytes a unit: a generous bound, so that a message stays under a packet.
      size_t entryBytes = 11;
      for (const Command& c : e.commands) entryBytes += 32 + 5 * c.units.size();
      if (!m.entries.empty() && bytes + entryBytes > kTicksMessageBudget) break;
      bytes += entryBytes;
      m.entries.push_back(e);
      ++spectatorNext_;
      ++next;
    }
    try {
      transport_.sendToSpectator(m);
    } catch (const std::exception& e) {
      dropSpectator(std::string("cannot send the spectator its ticks (") + e.what() + "); it is dropped", "", false);
      return;
    }
  }
  toSpectator_.clear();
}

void LockstepSession::dropSpectator(const std::string& line, const std::string& toSpectator, bool refuse) {
  say(line);
  if (transport_.spectatorConnected() && !toSpectator.empty()) {
    try {
      if (refuse) {
        transport_.sendToSpectator(Refuse{reasonText(toSpectator)});
      } else {
        transport_.sendToSpectator(Bye{reasonText(toSpectator)});
      }
    } catch (const std::exception&) {
    }
  }
  // A short linger for the last word: the players are not kept waiting for a spectator.
  transport_.closeSpectator(0.2);
  spectator_ = SpectatorState::None;
  toSpectator_.clear();
}

void LockstepSession::finish(const Game& game) {
  const uint32_t last = game.tickCount();
  // The final state is compared even when the interval does not fall on it.
  if (last % hashEvery_ != 0) myHash(game);
  send(Bye{"the game is over after " + std::to_string(last) + " ticks"});
  byeSent_ = true;
  waitFor([&] { return peerSaidBye_; }, "the end of its game");
  if (lastPeerHash_ != int64_t(last)) {
    fail(SessionError::Kind::PeerLost,
         "the peer's game ended after tick " + std::to_string(lastPeerHash_) + " and this side's after tick " +
             std::to_string(last) + ": both must play the same number of ticks",
         "");
  }
  // Until the peer has this side's Bye (and everything before it), or it waits for it in vain and takes
  // this side for lost; a lossy link may need a few resends. Done as soon as the peer has it.
  transport_.close(config_.peerTimeoutSeconds);
  // The game is over for the players; the spectator gets the rest of it and the end, as the peer did.
  feedSpectator();
  if (spectator_ == SpectatorState::Watching && transport_.spectatorConnected()) {
    try {
      transport_.sendToSpectator(Bye{"the game is over after " + std::to_string(last) + " ticks"});
    } catch (const std::exception&) {
    }
    transport_.closeSpectator(config_.peerTimeoutSeconds);
  } else if (transport_.spectatorConnected()) {
    transport_.closeSpectator(0.2);
  }
}

void LockstepSession::myHash(const Game& game) {
  const uint32_t tick = game.tickCount();
  SideState mine{game.stateHash(), game.worldHash(), {}};
  send(Hash{tick, mine.stateHash});
  auto it = peerHashes_.find(tick);
  // The state is taken only while it may still be needed: the game moves on before the peer's hash
  // comes, and a desync's report compares the states of the tick whose hashes differ.
  if (it == peerHashes_.end() || it->second != mine.stateHash) mine.state = replay::snapshotOf(game);
  if (it == peerHashes_.end()) {
    myHashes_[tick] = std::move(mine);
    return;
  }
  const uint64_t theirs = it->second;
  peerHashes_.erase(it);
  compare(tick, std::move(mine), theirs);
}

void LockstepSession::compare(uint32_t tick, SideState mine, uint64_t theirs) {
  ++hashesCompared_;
  if (mine.stateHash != theirs) desync(tick, std::move(mine), theirs);
}

void LockstepSession::desync(uint32_t tick, SideState mine, uint64_t theirs) {
  desyncTick_ = tick;
  const std::string t = std::to_string(tick);
  const std::string line = "desync at tick " + t + ": mine " + hexHash(mine.stateHash) + ", theirs " + hexHash(theirs);
  // Both sides get here (each sent its hash before it could know the other's), and each sends first and
  // then waits, so neither waits for the other's waiting.
  try {
    send(Snapshot{tick, mine.worldHash, mine.state});
  } catch (const std::invalid_argument&) {
    // Over a packet (a very large game): the peer learns that no state is coming rather than waiting.
    try {
      send(Snapshot{tick, mine.worldHash, std::nullopt});
    } catch (const std::exception&) {
    }
  } catch (const std::exception&) {  // ENet refused it: the peer's wait ends with its timeout
  }
  try {
    waitFor([&] { return peerState_.has_value(); }, "its state at tick " + t + " (to explain the desync)");
  } catch (const SessionError& e) {
    // The wait has already told the peer and closed; what ended the game is still the desync.
    throw SessionError(SessionError::Kind::Desync, line,
                       "  the peer's state at tick " + t + " did not come: " + e.what() + "\n");
  } catch (const LeftGame&) {
    throw SessionError(SessionError::Kind::Desync, line,
                       "  the peer's state at tick " + t + " did not come: this side quit while it waited for it\n");
  }
  peerState_->stateHash = theirs;
  const std::string details = desyncDetails(tick, mine, *peerState_, *game_, hashEvery_);
  // The peer may still be receiving this side's state: linger for it as long as for a silent peer.
  std::optional<Message> lastWord;
  if (!byeSent_) lastWord = Bye{"desync at tick " + t};
  leave(lastWord, config_.peerTimeoutSeconds, SessionError(SessionError::Kind::Desync, line, details));
}

std::string LockstepSession::silentFor(Clock::time_point now) const {
  return secondsText(std::chrono::duration<double>(now - lastHeard_).count());
}

void LockstepSession::waitFor(const std::function<bool()>& ready, const std::string& what) {
  if (ready()) return;
  const Clock::time_point start = Clock::now();
  const auto timeout = std::chrono::duration<double>(config_.peerTimeoutSeconds);
  Clock::time_point nextReport = start + std::chrono::milliseconds(500);
  while (!ready()) {
    const Clock::time_point now = Clock::now();
    // A side that said Bye before it found the desync (its game was over) still sends its state after.
    const bool stateMayFollow = desyncTick_ && peerSaidBye_ && !peerDisconnected_;
    if (peerGone_ && !stateMayFollow) {
      fail(SessionError::Kind::PeerLost, peerGoneWhy_ + " while this side waited for " + what, "");
    }
    if (now - lastHeard_ >= timeout) {
      fail(SessionError::Kind::PeerLost,
           "the peer has been silent for " + silentFor(now) + " s (the limit is " +
               secondsText(config_.peerTimeoutSeconds) + " s) while this side waited for " + what,
           "you were silent for " + silentFor(now) + " s");
    }
    if (now >= nextReport) {
      say("waiting for " + peerName() + ": " + what + " (" +
          secondsText(std::chrono::duration<double>(now - start).count()) + " s so far)");
      nextReport = now + std::chrono::seconds(1);
    }
    waitingRound(what, start);
    const auto slice = std::min<Clock::duration>(
        nextReport - now, std::chrono::duration_cast<Clock::duration>(lastHeard_ + timeout - now));
    handle(transport_.poll(std::clamp(std::chrono::duration<double>(slice).count(), 0.001, roundSeconds(0.25)),
                           context_));
  }
  if (handshaken_) {
    const double waited = std::chrono::duration<double>(Clock::now() - start).count();
    waited_ += waited;
    longestWait_ = std::max(longestWait_, waited);
  }
}

void LockstepSession::handle(TransportEvent event) {
  if (event.spectator) {
    handleSpectator(event);
    return;
  }
  switch (event.kind) {
    case TransportEvent::Kind::None:
      return;
    case TransportEvent::Kind::Connected:
      lastHeard_ = Clock::now();
      return;
    case TransportEvent::Kind::Disconnected:
      if (!peerGone_) peerGoneWhy_ = "the peer disconnected";
      peerGone_ = peerDisconnected_ = true;
      return;
    case TransportEvent::Kind::Garbage:
      fail(SessionError::Kind::Protocol, "the peer sent garbage: " + event.error, "you sent garbage: " + event.error);
    case TransportEvent::Kind::Received:
      lastHeard_ = Clock::now();
      handleMessage(*event.message);
      return;
  }
}

void LockstepSession::handleMessage(Message& message) {
  auto outOfTurn = [&](const std::string& why) {
    fail(SessionError::Kind::Protocol, "the peer broke the protocol: " + why, "you broke the protocol: " + why);
  };
  // Bye is a peer's last word; more after it would only keep this side reading. But for its state: the
  // hashes of the last ticks may be compared only after a side has said Bye.
  if (peerSaidBye_ && !(desyncTick_ && std::holds_alternative<Snapshot>(message))) {
    outOfTurn(std::string(messageName(message)) + " after its Bye");
  }
  if (auto* hello = std::get_if<Hello>(&message)) {
    if (!peerHello_ || peerHello_->has_value()) outOfTurn("a second Hello");
    *peerHello_ = std::move(*hello);
    return;
  }
  if (auto* refuse = std::get_if<Refuse>(&message)) {
    fail(SessionError::Kind::Refused, "the peer refused the game, saying: " + refuse->reason, "");
  }
  if (auto* bye = std::get_if<Bye>(&message)) {
    peerGone_ = peerSaidBye_ = true;
    peerGoneWhy_ = "the peer left (" + bye->reason + ")";
    return;
  }
  if (!handshaken_) outOfTurn(std::string(messageName(message)) + " before its Hello");
  if (auto* commands = std::get_if<Commands>(&message)) {
    receiveCommands(*commands);
  } else if (auto* hash = std::get_if<Hash>(&message)) {
    receiveHash(*hash);
  } else if (auto* snapshot = std::get_if<Snapshot>(&message)) {
    receiveSnapshot(*snapshot);
  }
}

void LockstepSession::receiveCommands(Commands& m) {
  const auto why = [&](const std::string& text) {
    const std::string line =
        "Commands for tick " + std::to_string(m.tick) + " of team " + std::to_string(m.team) + ": " + text;
    fail(SessionError::Kind::Protocol, "the peer broke the protocol: " + line, "you broke the protocol: " + line);
  };
  if (m.team != peerTeam_) why("it plays " + peerName());
  if (m.tick != nextPeerCommands_) why("expected tick " + std::to_string(nextPeerCommands_) + " next");
  // A side sends its hash of tick t before its commands for t + d (it plays t before it asks its source
  // for t + d). Without the hash, the peer would make this side keep its states (for a desync's report)
  // for ever. Checked before the next rule: it depends on the peer's messages alone.
  if (m.tick >= delay_ && int64_t(nextPeerHash_) <= int64_t(m.tick) - int64_t(delay_) && !peerFinalHash_) {
    why("its hash for tick " + std::to_string(nextPeerHash_) +
        " has not come (a side sends its hash of tick t before "
        "its commands for tick t + the input delay)");
  }
  // It cannot be further ahead: it would have played ticks this side has not sent it commands for.
  // This also bounds what a hostile peer can make this side keep.
  if (int64_t(m.tick) > sentThrough_ + 1 + int64_t(delay_)) {
    why("more than the input delay ahead of the ticks this side has sent (through " + std::to_string(sentThrough_) +
        ")");
  }
  peerCommands_[m.tick] = std::move(m.commands);
  ++nextPeerCommands_;
}

void LockstepSession::receiveHash(const Hash& h) {
  const auto why = [&](const std::string& text) {
    const std::string line = "Hash for tick " + std::to_string(h.tick) + ": " + text;
    fail(SessionError::Kind::Protocol, "the peer broke the protocol: " + line, "you broke the protocol: " + line);
  };
  if (peerFinalHash_) why("after its final one");
  if (int64_t(h.tick) > sentThrough_ + 1) why("a tick it cannot have played yet");
  if (h.tick == nextPeerHash_) {
    nextPeerHash_ += hashEvery_;
  } else if (int64_t(h.tick) > lastPeerHash_ && h.tick < nextPeerHash_) {
    peerFinalHash_ = true;  // off the interval: the state its game ended with
  } else {
    why("expected tick " + std::to_string(nextPeerHash_) + " next");
  }
  lastPeerHash_ = h.tick;
  if (desyncTick_) return;  // only the peer's state is awaited now
  if (auto it = myHashes_.find(h.tick); it != myHashes_.end()) {
    SideState mine = std::move(it->second);
    myHashes_.erase(it);
    compare(h.tick, std::move(mine), h.stateHash);
  } else {
    peerHashes_[h.tick] = h.stateHash;
  }
}

void LockstepSession::receiveSnapshot(Snapshot& m) {
  const auto why = [&](const std::string& text) {
    const std::string line = "Snapshot for tick " + std::to_string(m.tick) + ": " + text;
    fail(SessionError::Kind::Protocol, "the peer broke the protocol: " + line, "you broke the protocol: " + line);
  };
  // The peer's hash of the tick comes before its state, so this side has found the desync first.
  if (!desyncTick_) why("no desync was found");
  if (m.tick != *desyncTick_) why("the desync is at tick " + std::to_string(*desyncTick_));
  if (peerState_) why("a second one");
  peerState_ = SideState{0, m.worldHash, std::move(m.state)};
}

}  // namespace rts::net
