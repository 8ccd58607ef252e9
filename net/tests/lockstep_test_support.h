// Shared by the lockstep tests: a game from a map of assets/maps/, one side of a networked game played
// to its end (or its error), and a peer made by hand from a bare Transport.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/map_loader.h"
#include "net/delayed_source.h"
#include "net/hello.h"
#include "net/lockstep.h"
#include "net/spectator.h"
#include "net/transport.h"

namespace net_test {

inline std::string sourcePath(const std::string& relative) { return std::string(RATTLE_SOURCE_DIR) + "/" + relative; }

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The settings both sides of a game must share, and the ones each may choose.
struct GameSettings {
  std::string mapFile = "assets/maps/arena.json";
  uint64_t seed = 1;
  int units = 20;
  uint32_t ticks = 300;
  uint16_t inputDelay = 3;
  uint16_t hashEvery = 1;
  double peerTimeout = 10;
  /// The test's hook for a desync: after this many ticks the side orders one of its units somewhere
  /// itself, outside the lockstep (0: never).
  uint32_t perturbAfter = 0;
  rts::Steering steering = rts::Steering::KeepApart;
  /// A player sleeps this long after each tick (0: none, as rattle-demo headless): a game that lasts
  /// long enough for a spectator to join it under way.
  double tickSeconds = 0;
  /// The session's LockstepConfig::whileWaiting (a window's hook): empty as headless.
  std::function<bool(const std::string&, double)> whileWaiting;
};

/// The order that perturbs a game: the team's first unit, sent to the middle of the map.
inline rts::Command perturbation(const rts::Game& game, uint8_t team) {
  rts::Command c;
  c.tick = game.tickCount();
  c.team = team;
  c.type = rts::CommandType::Move;
  for (const rts::Unit& u : game.units()) {
    if (u.alive && u.team == team) {
      c.units.push_back(u.id);
      break;
    }
  }
  c.target = {game.map().width / 2, game.map().height / 2};
  return c;
}

inline std::unique_ptr<rts::Game> makeGame(const GameSettings& s, const std::string& mapJson) {
  rts::GameConfig config;
  config.unitsPerTeam = s.units;
  config.steering = s.steering;
  return std::make_unique<rts::Game>(rts::parseMap(mapJson, s.mapFile), config);
}

/// How one side's game ended.
struct SideResult {
  bool finished = false;  ///< played every tick and finish() passed
  rts::net::SessionError::Kind kind = rts::net::SessionError::Kind::PeerLost;
  std::string error;    ///< the SessionError's line, when not finished
  std::string details;  ///< the SessionError's details: a desync's report
  uint64_t finalHash = 0;
  uint32_t ticksPlayed = 0;
  uint32_t hashesCompared = 0;
  std::vector<rts::Command> applied;  ///< every command applied, in order (tick stamped)
  std::vector<std::string> log;       ///< the session's lines for a person
  double seconds = 0;                 ///< from the handshake's start to the end
  double waited = 0;                  ///< the session's waitedSeconds()
  double longestWait = 0;             ///< its longestWaitSeconds()
  std::string left;                   ///< LeftGame's what(), when whileWaiting asked to leave
};

/// One side of a networked game on `transport`: the scripted opponent for its team, through a TickLoop
/// with the session as its only source, as rattle-demo plays it.
inline SideResult playSide(rts::net::Transport& transport, uint8_t team, const GameSettings& s,
                           std::atomic<uint32_t>* ticksDone = nullptr) {
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  rts::ScriptedOpponent opponent(s.seed, 1u << team);
  SideResult r;
  rts::net::LockstepConfig config;
  config.hello = rts::net::playerHello(*game, mapJson, s.seed, team, s.inputDelay, s.hashEvery, s.ticks);
  config.acceptSpectator = team == 0;
  config.peerTimeoutSeconds = s.peerTimeout;
  config.joinWaitSeconds = 30;  // a test never waits for ever
  config.log = [&r](const std::string& line) { r.log.push_back(line); };
  config.whileWaiting = s.whileWaiting;
  rts::net::LockstepSession session(transport, opponent, config);
  const auto start = std::chrono::steady_clock::now();
  try {
    session.handshake(*game);
    rts::TickLoop loop(*game);
    loop.add(session);
    for (uint32_t t = 0; t < s.ticks; ++t) {
      const std::vector<rts::Command>& commands = loop.tick();
      r.applied.insert(r.applied.end(), commands.begin(), commands.end());
      session.afterTick(*game);
      if (game->tickCount() == s.perturbAfter) game->apply(perturbation(*game, team));
      if (ticksDone) ticksDone->store(game->tickCount());
      if (s.tickSeconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(s.tickSeconds));
    }
    session.finish(*game);
    r.finished = true;
  } catch (const rts::net::SessionError& e) {
    r.kind = e.kind();
    r.error = e.what();
    r.details = e.details();
  } catch (const rts::net::LeftGame& e) {
    r.left = e.what();
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.finalHash = game->stateHash();
  r.ticksPlayed = game->tickCount();
  r.hashesCompared = session.hashesCompared();
  r.waited = session.waitedSeconds();
  r.longestWait = session.longestWaitSeconds();
  return r;
}

/// A spectator of the game of `s` on `transport` (a joiner's, to the host), as rattle-demo --watch
/// plays it: the host's ticks through a TickLoop with the session as its only source. `leaveAfter`
/// (0: never): the spectator disconnects, without a word, once it has played that many ticks.
inline SideResult watchSide(rts::net::Transport& transport, const GameSettings& s, uint32_t leaveAfter = 0,
                            uint32_t* joinedAt = nullptr) {
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  SideResult r;
  rts::net::LockstepConfig config;
  config.hello = rts::net::spectatorHello(*game, mapJson, s.seed, s.inputDelay, s.hashEvery, s.ticks);
  config.peerTimeoutSeconds = s.peerTimeout;
  config.log = [&r](const std::string& line) { r.log.push_back(line); };
  rts::net::SpectatorSession session(transport, config);
  const auto start = std::chrono::steady_clock::now();
  try {
    session.handshake(*game);
    if (joinedAt) *joinedAt = session.joinedAt();
    rts::TickLoop loop(*game);
    loop.add(session);
    // From the tick it joined at: its game took the host's state there.
    while (game->tickCount() < s.ticks) {
      const std::vector<rts::Command>& commands = loop.tick();
      r.applied.insert(r.applied.end(), commands.begin(), commands.end());
      session.afterTick(*game);
      if (game->tickCount() == s.perturbAfter) game->apply(perturbation(*game, 0));
      if (leaveAfter != 0 && game->tickCount() == leaveAfter) {
        transport.close(0);
        r.error = "left on purpose";
        break;
      }
    }
    if (r.error.empty()) {
      session.finish(*game);
      r.finished = true;
    }
  } catch (const rts::net::SessionError& e) {
    r.kind = e.kind();
    r.error = e.what();
    r.details = e.details();
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.finalHash = game->stateHash();
  r.ticksPlayed = game->tickCount();
  r.hashesCompared = session.hashesCompared();
  r.waited = session.waitedSeconds();
  return r;
}

inline std::string describe(const SideResult& r) {
  std::string s = r.finished ? "finished" : "ended: " + r.error + "\n" + r.details;
  for (const std::string& l : r.log) s += "\n  " + l;
  return s;
}

/// The game without a network, played by one TickLoop with sources in the given order.
struct LocalGame {
  uint64_t finalHash = 0;
  std::vector<rts::Command> applied;
};

inline LocalGame playLocal(const GameSettings& s, const std::vector<rts::CommandSource*>& sources) {
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  rts::TickLoop loop(*game);
  for (rts::CommandSource* source : sources) loop.add(*source);
  LocalGame g;
  for (uint32_t t = 0; t < s.ticks; ++t) {
    const std::vector<rts::Command>& commands = loop.tick();
    g.applied.insert(g.applied.end(), commands.begin(), commands.end());
  }
  g.finalHash = game->stateHash();
  return g;
}

/// The networked game of `s` as one loop plays it: each team's scripted opponent behind the input delay,
/// team 0's first (test_net_lockstep.cpp shows the two are the same game).
/// Team 0's ReloadWorld at one tick, after team 0's other commands: what a host adds for its spectator.
class ReloadWorldAt : public rts::CommandSource {
 public:
  explicit ReloadWorldAt(std::optional<uint32_t> tick) : tick_(tick) {}
  void commandsFor(uint32_t tick, const rts::Game&, std::vector<rts::Command>& out) override {
    if (tick != tick_) return;
    rts::Command c;
    c.tick = tick;
    c.team = 0;
    c.type = rts::CommandType::ReloadWorld;
    out.push_back(c);
  }

 private:
  std::optional<uint32_t> tick_;
};

/// With `reloadAt`: the host took a spectator, whose state is of that tick (the ReloadWorld's).
inline LocalGame playDelayedLocal(const GameSettings& s, std::optional<uint32_t> reloadAt = std::nullopt) {
  rts::ScriptedOpponent blue(s.seed, 1), red(s.seed, 2);
  rts::net::DelayedSource blueLater(blue, s.inputDelay), redLater(red, s.inputDelay);
  ReloadWorldAt reload(reloadAt);
  return playLocal(s, {&blueLater, &reload, &redLater});
}

/// The tick of the ReloadWorld a side applied (the host took a spectator then), if any.
inline std::optional<uint32_t> reloadTickOf(const SideResult& r) {
  for (const rts::Command& c : r.applied) {
    if (c.type == rts::CommandType::ReloadWorld) return c.tick;
  }
  return std::nullopt;
}

/// What the session decodes the peer's packets with in `game`.
inline rts::net::DecodeContext contextOf(const rts::Game& game) {
  return {uint32_t(game.units().size()), uint32_t(game.map().gates.size()), uint32_t(game.doorways().size()),
          uint32_t(game.rooms().size())};
}

/// Polls a bare transport until `kind` comes (or `seconds` pass); returns what came last.
inline rts::net::TransportEvent pollFor(rts::net::Transport& t, rts::net::TransportEvent::Kind kind, double seconds,
                                        const rts::net::DecodeContext& context = {}) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  rts::net::TransportEvent e;
  while (std::chrono::steady_clock::now() < end) {
    e = t.poll(0.05, context);
    if (e.kind == kind) return e;
  }
  return e;
}

inline bool contains(const std::vector<std::string>& lines, const std::string& part) {
  for (const std::string& l : lines) {
    if (l.find(part) != std::string::npos) return true;
  }
  return false;
}

}  // namespace net_test
