// Spectators (issue 9, point 9): a third session joins a game under way from its host, starts from the
// host's state at a tick where the players' worlds load from their saves too (ReloadWorld), and follows
// it with the players' hashes; it never holds the players up, whether it leaves, is refused, or watches
// through the faulty relay.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <thread>

#include "lockstep_test_support.h"
#include "net/faulty_relay.h"

namespace {

using namespace net_test;
using rts::net::SessionError;
using rts::net::Transport;

struct Trio {
  SideResult host, joiner, spectator;
  uint32_t joinedAt = 0;
  uint32_t hostTickWhenWatching = 0;  // how far the host had played when the spectator began to connect
};

// The players each in a thread of their own, as two processes; the spectator in a third, connecting
// once the host has played `watchFrom` ticks, to the host directly or through `relay` (its port).
Trio playWithSpectator(const GameSettings& s, uint32_t watchFrom, uint32_t leaveAfter = 0,
                       const GameSettings* spectatorSettings = nullptr,
                       const rts::net::FaultModel* relayModel = nullptr) {
  std::unique_ptr<Transport> host = Transport::host(0, true);
  const uint16_t port = host->localPort();
  std::unique_ptr<rts::net::FaultyRelay> relay;
  if (relayModel) {
    relay = std::make_unique<rts::net::FaultyRelay>(0, "127.0.0.1", port, *relayModel);
    relay->start();
  }
  std::atomic<uint32_t> hostTicks{0};
  std::future<SideResult> hostSide =
      std::async(std::launch::async, [&] { return playSide(*host, 0, s, &hostTicks); });
  std::future<SideResult> joinerSide = std::async(std::launch::async, [&] {
    std::unique_ptr<Transport> joiner = Transport::join("127.0.0.1", port);
    return playSide(*joiner, 1, s);
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (hostTicks.load() < watchFrom && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  Trio t;
  t.hostTickWhenWatching = hostTicks.load();
  std::unique_ptr<Transport> watcher = Transport::join("127.0.0.1", relay ? relay->port() : port);
  t.spectator = watchSide(*watcher, spectatorSettings ? *spectatorSettings : s, leaveAfter, &t.joinedAt);
  t.joiner = joinerSide.get();
  t.host = hostSide.get();
  if (relay) relay->stop();
  return t;
}

GameSettings pacedGame() {
  GameSettings s;
  s.ticks = 300;
  s.tickSeconds = 0.004;  // about 1.2 s of play: time for a spectator to come in under way
  return s;
}

TEST(NetSpectator, ASpectatorJoiningUnderWayFollowsToTheEndWithThePlayersHashes) {
  const GameSettings s = pacedGame();
  const Trio t = playWithSpectator(s, 100);
  ASSERT_TRUE(t.host.finished) << describe(t.host);
  ASSERT_TRUE(t.joiner.finished) << describe(t.joiner);
  ASSERT_TRUE(t.spectator.finished) << describe(t.spectator);
  // It came in under way, at the first tick whose commands the host had not sent when its hello arrived
  // (the input delay after the tick it came at, as the host said then), and started from the host's state
  // there: it played no tick before. (How many ticks the host plays while a spectator connects is the
  // machine's timing, not the protocol's: a bound of 20 ticks, 80 ms, failed on a loaded 2-core machine.)
  EXPECT_GE(t.joinedAt, 100u);
  EXPECT_GE(t.joinedAt, t.hostTickWhenWatching);
  EXPECT_TRUE(contains(t.host.log, "a spectator is let in: it starts from this side's state at tick " +
                                       std::to_string(t.joinedAt)))
      << describe(t.host);
  EXPECT_LT(t.joinedAt, s.ticks);
  EXPECT_TRUE(contains(t.host.log, "a spectator is watching from tick " + std::to_string(t.joinedAt)))
      << describe(t.host);
  EXPECT_TRUE(
      contains(t.spectator.log, "watching from tick " + std::to_string(t.joinedAt) + ", the host's state loaded"))
      << describe(t.spectator);
  EXPECT_EQ(t.spectator.ticksPlayed, s.ticks);
  EXPECT_EQ(t.spectator.finalHash, t.host.finalHash);
  EXPECT_EQ(t.spectator.finalHash, t.joiner.finalHash);
  // Both players took the ReloadWorld at that tick, as one local game with it does.
  EXPECT_EQ(reloadTickOf(t.host), t.joinedAt);
  EXPECT_EQ(reloadTickOf(t.joiner), t.joinedAt);
  EXPECT_EQ(t.host.finalHash, playDelayedLocal(s, t.joinedAt).finalHash);
  // A hash every tick it played, each compared with the host's (which the joiner's matched).
  EXPECT_EQ(t.spectator.hashesCompared, s.ticks - t.joinedAt);
  // The same commands at the same ticks, in the same order, as the players applied from then on.
  std::vector<rts::Command> fromThen;
  for (const rts::Command& c : t.host.applied) {
    if (c.tick >= t.joinedAt) fromThen.push_back(c);
  }
  ASSERT_EQ(t.spectator.applied.size(), fromThen.size());
  for (size_t i = 0; i < fromThen.size(); ++i) {
    EXPECT_EQ(t.spectator.applied[i].tick, fromThen[i].tick) << i;
    EXPECT_EQ(t.spectator.applied[i].team, fromThen[i].team) << i;
    EXPECT_EQ(t.spectator.applied[i].type, fromThen[i].type) << i;
    EXPECT_EQ(t.spectator.applied[i].units, fromThen[i].units) << i;
  }
  std::printf("[ watch    ] joined at tick %u of %u; players %.2f s, spectator %.2f s\n", t.joinedAt, s.ticks,
              t.host.seconds, t.spectator.seconds);
}

TEST(NetSpectator, ASpectatorThatLeavesDoesNotStopThePlayers) {
  const GameSettings s = pacedGame();
  const Trio t = playWithSpectator(s, 60, 150);
  EXPECT_EQ(t.spectator.error, "left on purpose") << describe(t.spectator);
  EXPECT_EQ(t.spectator.ticksPlayed, 150u);
  ASSERT_TRUE(t.host.finished) << describe(t.host);
  ASSERT_TRUE(t.joiner.finished) << describe(t.joiner);
  EXPECT_TRUE(contains(t.host.log, "the spectator left; the game goes on")) << describe(t.host);
  EXPECT_EQ(t.host.finalHash, t.joiner.finalHash);
  EXPECT_EQ(t.host.finalHash, playDelayedLocal(s, t.joinedAt).finalHash);
  // Its leaving cost the players no wait of the peer timeout's order.
  EXPECT_LT(t.host.longestWait, 2.0) << describe(t.host);
}

TEST(NetSpectator, ASpectatorOfAnotherGameIsRefusedOnBothSidesAndThePlayersGoOn) {
  const GameSettings s = pacedGame();
  GameSettings other = s;
  other.seed = 8;
  other.ticks = 301;
  const Trio t = playWithSpectator(s, 30, 0, &other);
  EXPECT_EQ(t.spectator.kind, SessionError::Kind::Refused) << describe(t.spectator);
  EXPECT_EQ(t.spectator.error, "the handshake failed: seed: mine 8, theirs 1; ticks: mine 301, theirs 300");
  EXPECT_TRUE(contains(t.host.log, "a spectator was refused: seed: mine 1, theirs 8; ticks: mine 300, theirs 301"))
      << describe(t.host);
  ASSERT_TRUE(t.host.finished) << describe(t.host);
  ASSERT_TRUE(t.joiner.finished) << describe(t.joiner);
  EXPECT_EQ(t.host.finalHash, t.joiner.finalHash);
}

// A spectator whose game parts from the players' (it orders a unit itself, outside the game) ends as a
// player's desync does, at the first hash that differs; the players go on.
TEST(NetSpectator, ASpectatorsDesyncAfterItJoinedIsFoundAtTheFirstTickThatDiffers) {
  const GameSettings s = pacedGame();
  GameSettings mine = s;
  mine.perturbAfter = 200;
  const Trio t = playWithSpectator(s, 60, 0, &mine);
  ASSERT_LT(t.joinedAt, 200u);
  EXPECT_EQ(t.spectator.kind, SessionError::Kind::Desync) << describe(t.spectator);
  EXPECT_EQ(t.spectator.error.rfind("desync at tick 201: mine ", 0), 0u) << describe(t.spectator);
  EXPECT_NE(t.spectator.error.find(", the host's "), std::string::npos) << describe(t.spectator);
  EXPECT_NE(t.spectator.details.find("the host sends a spectator its state only at the tick it joined"),
            std::string::npos)
      << t.spectator.details;
  EXPECT_EQ(t.spectator.ticksPlayed, 201u);
  ASSERT_TRUE(t.host.finished) << describe(t.host);
  ASSERT_TRUE(t.joiner.finished) << describe(t.joiner);
  EXPECT_EQ(t.host.finalHash, t.joiner.finalHash);
}

// A spectator that joins when the game is nearly over (no tick left whose commands the host has not sent:
// with an input delay of 150, none after tick 150 of 300) is turned away with a line, and the players go
// on as without it: no ReloadWorld.
TEST(NetSpectator, ASpectatorTooLateToStartIsTurnedAwayAndThePlayersGoOn) {
  GameSettings s = pacedGame();
  s.inputDelay = 150;
  const Trio t = playWithSpectator(s, 200);
  EXPECT_EQ(t.spectator.kind, SessionError::Kind::Refused) << describe(t.spectator);
  EXPECT_NE(t.spectator.error.find("the game ends before a spectator could start"), std::string::npos)
      << describe(t.spectator);
  ASSERT_TRUE(t.host.finished) << describe(t.host);
  ASSERT_TRUE(t.joiner.finished) << describe(t.joiner);
  EXPECT_TRUE(contains(t.host.log, "a spectator came too late")) << describe(t.host);
  EXPECT_EQ(reloadTickOf(t.host), std::nullopt);
  EXPECT_EQ(t.host.finalHash, t.joiner.finalHash);
  EXPECT_EQ(t.host.finalHash, playDelayedLocal(s).finalHash);
}

// The spectator's link drops 10% of the datagrams each way, doubles 5%, holds 5% back and delays every
// one by 50 to 200 ms; the players play directly. It still ends with their final hash; the players do
// not wait for it (the host lingers at the very end, after the game, until the spectator has it all).
TEST(NetSpectator, ASpectatorThroughTheFaultyRelayEndsWithTheSameFinalHash) {
  GameSettings s = pacedGame();
  s.tickSeconds = 0.01;  // 3 s of play: the spectator's handshake takes a few trips through the relay
  const rts::net::FaultModel model;
  const Trio t = playWithSpectator(s, 30, 0, nullptr, &model);
  ASSERT_TRUE(t.host.finished) << describe(t.host);
  ASSERT_TRUE(t.joiner.finished) << describe(t.joiner);
  ASSERT_TRUE(t.spectator.finished) << describe(t.spectator);
  EXPECT_EQ(t.spectator.finalHash, t.host.finalHash);
  EXPECT_EQ(t.spectator.finalHash, t.joiner.finalHash);
  EXPECT_EQ(t.spectator.hashesCompared, s.ticks - t.joinedAt);
  EXPECT_GT(t.joinedAt, 0u);
  std::printf("[ watch    ] through the relay: joined at tick %u; spectator %.2f s, waited %.2f s\n", t.joinedAt,
              t.spectator.seconds, t.spectator.waited);
}

}  // namespace

namespace {

// A spectator that comes before the second player has no game to watch: the host turns it away and
// waits on for its player, and the game is played as without it.
TEST(NetSpectator, ASpectatorBeforeThePlayerIsTurnedAwayAndTheHostWaitsOn) {
  GameSettings s;
  s.units = 6;
  s.ticks = 60;
  std::unique_ptr<Transport> host = Transport::host(0, true);
  const uint16_t port = host->localPort();
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  std::unique_ptr<Transport> early = Transport::join("127.0.0.1", port);
  const SideResult watcher = watchSide(*early, s);
  EXPECT_EQ(watcher.kind, SessionError::Kind::Refused) << describe(watcher);
  EXPECT_EQ(watcher.error,
            "the host refused the spectator, saying: no game to watch yet: a player has not joined (watch once the "
            "game has started)");
  std::unique_ptr<Transport> joiner = Transport::join("127.0.0.1", port);
  const SideResult red = playSide(*joiner, 1, s);
  const SideResult blue = hostSide.get();
  ASSERT_TRUE(blue.finished) << describe(blue);
  ASSERT_TRUE(red.finished) << describe(red);
  EXPECT_EQ(blue.finalHash, red.finalHash);
  EXPECT_EQ(blue.finalHash, playDelayedLocal(s).finalHash);
  EXPECT_TRUE(contains(blue.log, "a spectator came before a player joined: it is turned away")) << describe(blue);
}

}  // namespace

namespace {

// A spectator that says its Hello and then reads nothing (its ENet is never serviced, so nothing the host
// sends it is acknowledged) is dropped once it is kMaxSpectatorBacklog messages behind; the players go
// on, and the host keeps nothing more for it.
TEST(NetSpectator, ASpectatorThatFallsBehindIsDroppedAndThePlayersGoOn) {
  GameSettings s;
  s.units = 6;
  s.ticks = 1500;
  std::unique_ptr<Transport> host = Transport::host(0, true);
  const uint16_t port = host->localPort();
  std::atomic<uint32_t> hostTicks{0};
  std::future<SideResult> hostSide =
      std::async(std::launch::async, [&] { return playSide(*host, 0, s, &hostTicks); });
  std::future<SideResult> joinerSide = std::async(std::launch::async, [&] {
    std::unique_ptr<Transport> joiner = Transport::join("127.0.0.1", port);
    return playSide(*joiner, 1, s);
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (hostTicks.load() < 10 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  std::unique_ptr<Transport> stalled = Transport::join("127.0.0.1", port);
  ASSERT_EQ(pollFor(*stalled, rts::net::TransportEvent::Kind::Connected, 10).kind,
            rts::net::TransportEvent::Kind::Connected);
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  stalled->send(rts::net::spectatorHello(*makeGame(s, mapJson), mapJson, s.seed, s.inputDelay, s.hashEvery, s.ticks));
  const SideResult red = joinerSide.get();
  const SideResult blue = hostSide.get();
  ASSERT_TRUE(blue.finished) << describe(blue);
  ASSERT_TRUE(red.finished) << describe(red);
  EXPECT_TRUE(contains(blue.log, "a spectator is watching from tick ")) << describe(blue);
  EXPECT_TRUE(contains(blue.log, "the spectator fell behind (1025 messages not acknowledged); it is dropped")) << describe(blue);
  EXPECT_EQ(blue.finalHash, red.finalHash);
  ASSERT_TRUE(reloadTickOf(blue).has_value());
  EXPECT_EQ(reloadTickOf(red), reloadTickOf(blue));
  EXPECT_EQ(blue.finalHash, playDelayedLocal(s, reloadTickOf(blue)).finalHash);
  EXPECT_LT(blue.longestWait, 2.0) << describe(blue);
}

}  // namespace
