// Two lockstep sessions in one process, over real ENet on localhost: a whole game, a refused
// handshake, a peer that goes silent, one that disconnects, one that sends garbage. Every host listens
// on a port the system picks (0), so tests running side by side never share one.
#include <gtest/gtest.h>

#include <cstring>
#include <future>
#include <thread>

#include "lockstep_test_support.h"
#include "net/delayed_source.h"

namespace {

using namespace net_test;
using rts::net::SessionError;
using rts::net::Transport;
using rts::net::TransportEvent;

struct Pair {
  SideResult host, joiner;
};

// Both sides, each in its own thread with its own transport, game and session, as two processes would.
Pair playPair(const GameSettings& hostSettings, const GameSettings& joinerSettings) {
  std::unique_ptr<Transport> host = Transport::host(0);
  const uint16_t port = host->localPort();
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, hostSettings); });
  std::unique_ptr<Transport> joiner = Transport::join("127.0.0.1", port);
  Pair p;
  p.joiner = playSide(*joiner, 1, joinerSettings);
  p.host = hostSide.get();
  return p;
}

std::string describe(const SideResult& r) {
  std::string s = r.finished ? "finished" : "ended: " + r.error;
  for (const std::string& l : r.log) s += "\n  " + l;
  return s;
}

void expectSameCommands(const std::vector<rts::Command>& a, const std::vector<rts::Command>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].tick, b[i].tick) << i;
    EXPECT_EQ(a[i].team, b[i].team) << i;
    EXPECT_EQ(a[i].type, b[i].type) << i;
    EXPECT_EQ(a[i].units, b[i].units) << i;
    EXPECT_EQ(a[i].target.x, b[i].target.x) << i;
    EXPECT_EQ(a[i].target.y, b[i].target.y) << i;
    EXPECT_EQ(a[i].gate, b[i].gate) << i;
  }
}

// The game without a network, played by one TickLoop with sources in the given order.
struct LocalGame {
  uint64_t finalHash = 0;
  std::vector<rts::Command> applied;
};

LocalGame playLocal(const GameSettings& s, const std::vector<rts::CommandSource*>& sources) {
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

TEST(NetLockstep, TwoSidesPlayTheSameGameAsOneLoopWithTheSameDelayAndOrder) {
  GameSettings s;  // arena, 20 units a team, 300 ticks, delay 3, a hash every tick
  s.seed = 11;
  const Pair p = playPair(s, s);
  ASSERT_TRUE(p.host.finished) << describe(p.host);
  ASSERT_TRUE(p.joiner.finished) << describe(p.joiner);
  EXPECT_EQ(p.host.ticksPlayed, 300u);
  EXPECT_EQ(p.joiner.ticksPlayed, 300u);
  EXPECT_EQ(p.host.finalHash, p.joiner.finalHash);
  // Every tick's hash, 0 to 300, was compared on both sides.
  EXPECT_EQ(p.host.hashesCompared, 301u);
  EXPECT_EQ(p.joiner.hashesCompared, 301u);
  expectSameCommands(p.host.applied, p.joiner.applied);

  // Both teams issued orders, so the test is about commands crossing the network, not an idle game.
  int byTeam[2] = {0, 0};
  for (const rts::Command& c : p.host.applied) ++byTeam[c.team & 1];
  EXPECT_GT(byTeam[0], 0);
  EXPECT_GT(byTeam[1], 0);

  // The networked game is the game a single loop plays with each team's opponent (a generator each)
  // behind the same input delay, team 0's source added first: the session applies team 0's set, then
  // team 1's, each issued d ticks earlier from the game as it was then.
  rts::ScriptedOpponent blue(s.seed, 1), red(s.seed, 2);
  rts::net::DelayedSource blueLater(blue, s.inputDelay), redLater(red, s.inputDelay);
  const LocalGame same = playLocal(s, {&blueLater, &redLater});
  EXPECT_EQ(same.finalHash, p.host.finalHash);
  expectSameCommands(same.applied, p.host.applied);

  // It is not the game of a plain headless run: there one opponent plays both teams from one
  // generator (the teams' draws interleave) and without delay, so the orders and the game differ.
  rts::ScriptedOpponent both(s.seed, 3);
  const LocalGame plain = playLocal(s, {&both});
  EXPECT_NE(plain.finalHash, p.host.finalHash);
}

TEST(NetLockstep, AHashIntervalAndNoDelayPlayTheSameGameToo) {
  GameSettings s;
  s.units = 8;
  s.ticks = 100;  // not a multiple of 7: the final state is compared off the interval
  s.inputDelay = 0;
  s.hashEvery = 7;
  const Pair p = playPair(s, s);
  ASSERT_TRUE(p.host.finished) << describe(p.host);
  ASSERT_TRUE(p.joiner.finished) << describe(p.joiner);
  EXPECT_EQ(p.host.finalHash, p.joiner.finalHash);
  EXPECT_EQ(p.host.hashesCompared, 16u);  // ticks 0, 7, ..., 98, and 100
  EXPECT_EQ(p.joiner.hashesCompared, 16u);
  rts::ScriptedOpponent blue(s.seed, 1), red(s.seed, 2);
  const LocalGame same = playLocal(s, {&blue, &red});
  EXPECT_EQ(same.finalHash, p.host.finalHash);
}

std::string hex(uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

// The state hash of every tick, 0 to s.ticks, of the game without a network, perturbed as the side
// playing `team` would be.
std::vector<uint64_t> hashesOfLocalGame(const GameSettings& s, uint8_t team) {
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  rts::ScriptedOpponent blue(s.seed, 1), red(s.seed, 2);
  rts::net::DelayedSource blueLater(blue, s.inputDelay), redLater(red, s.inputDelay);
  rts::TickLoop loop(*game);
  loop.add(blueLater);
  loop.add(redLater);
  std::vector<uint64_t> hashes{game->stateHash()};
  for (uint32_t t = 0; t < s.ticks; ++t) {
    loop.tick();
    hashes.push_back(game->stateHash());
    if (game->tickCount() == s.perturbAfter) game->apply(perturbation(*game, team));
  }
  return hashes;
}

// After tick 100 the joiner orders a unit of its own outside the lockstep: from tick 101 on the two
// games differ. Each side sends its hash of a tick before it can know the other's, so both find the
// desync, at the same tick, each with its own hash first.
TEST(NetLockstep, ADesyncIsFoundOnBothSidesAtTheFirstTickThatDiffers) {
  GameSettings host, joiner;
  host.units = joiner.units = 10;
  joiner.perturbAfter = 100;
  const std::vector<uint64_t> same = hashesOfLocalGame(host, 0), perturbed = hashesOfLocalGame(joiner, 1);
  size_t first = 0;
  while (first < same.size() && same[first] == perturbed[first]) ++first;
  ASSERT_EQ(first, 101u) << "the order changes the state hash of the next tick";

  const Pair p = playPair(host, joiner);
  EXPECT_EQ(p.host.kind, SessionError::Kind::Desync) << describe(p.host);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::Desync) << describe(p.joiner);
  const std::string tick = "desync at tick 101: mine ";
  EXPECT_EQ(p.host.error, tick + hex(same[101]) + ", theirs " + hex(perturbed[101]));
  EXPECT_EQ(p.joiner.error, tick + hex(perturbed[101]) + ", theirs " + hex(same[101]));
  // Each played the tick that differs, and neither got further than the other's commands allow.
  EXPECT_GE(p.host.ticksPlayed, 101u);
  EXPECT_GE(p.joiner.ticksPlayed, 101u);
  EXPECT_LE(p.host.ticksPlayed, 101u + host.inputDelay);
  EXPECT_LE(p.joiner.ticksPlayed, 101u + host.inputDelay);
}

TEST(NetLockstep, ADifferentSeedIsRefusedOnBothSidesNamingIt) {
  GameSettings host, joiner;
  host.seed = 7;
  joiner.seed = 8;
  const Pair p = playPair(host, joiner);
  EXPECT_FALSE(p.host.finished);
  EXPECT_FALSE(p.joiner.finished);
  EXPECT_EQ(p.host.kind, SessionError::Kind::Refused);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::Refused);
  EXPECT_EQ(p.host.error, "the handshake failed: seed: mine 7, theirs 8");
  EXPECT_EQ(p.joiner.error, "the handshake failed: seed: mine 8, theirs 7");
  EXPECT_EQ(p.host.ticksPlayed, 0u);
  EXPECT_EQ(p.joiner.ticksPlayed, 0u);
}

TEST(NetLockstep, DifferentTickCountsEndBothSidesAsPeerLost) {
  GameSettings host, joiner;
  host.units = joiner.units = 4;
  host.ticks = 30;
  joiner.ticks = 31;
  const Pair p = playPair(host, joiner);
  EXPECT_EQ(p.host.kind, SessionError::Kind::PeerLost) << describe(p.host);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::PeerLost) << describe(p.joiner);
  EXPECT_EQ(
      p.host.error,
      "the peer's game ended after tick 31 and this side's after tick 30: both must play the same number of ticks");
  EXPECT_EQ(
      p.joiner.error,
      "the peer's game ended after tick 30 and this side's after tick 31: both must play the same number of ticks");
}

// A hand-made joiner: connects, says a matching Hello, then does what the test says.
struct BarePeer {
  std::unique_ptr<Transport> transport;
  explicit BarePeer(uint16_t port) : transport(Transport::join("127.0.0.1", port)) {}
  void helloFor(const GameSettings& s) {
    ASSERT_EQ(pollFor(*transport, TransportEvent::Kind::Connected, 10).kind, TransportEvent::Kind::Connected);
    const std::string mapJson = readFile(sourcePath(s.mapFile));
    transport->send(rts::net::playerHello(*makeGame(s, mapJson), mapJson, s.seed, 1, s.inputDelay, s.hashEvery));
  }
  /// Keeps ENet going (acknowledging what comes) until the other side says Bye or leaves; returns the
  /// Bye's reason, or "" when there was none.
  std::string lastWords(const rts::net::DecodeContext& context) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < end) {
      const TransportEvent e = transport->poll(0.01, context);
      if (e.kind == TransportEvent::Kind::Disconnected) return "";
      if (const auto* bye = e.message ? std::get_if<rts::net::Bye>(&*e.message) : nullptr) return bye->reason;
    }
    return "";
  }
};

TEST(NetLockstep, ASilentPeerIsGivenUpOnAfterTheTimeout) {
  GameSettings s;
  s.units = 4;
  s.peerTimeout = 1;
  std::unique_ptr<Transport> host = Transport::host(0);
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  BarePeer peer(host->localPort());
  peer.helloFor(s);
  // Then nothing: not even ENet's acknowledgements, as a stopped or hung process.
  const SideResult r = hostSide.get();
  EXPECT_FALSE(r.finished);
  EXPECT_EQ(r.kind, SessionError::Kind::PeerLost);
  // The free ticks of the input delay are played; the first that needs the peer's commands is not.
  EXPECT_EQ(r.ticksPlayed, 3u);
  EXPECT_EQ(r.error.rfind("the peer has been silent for 1.", 0), 0u) << r.error;
  EXPECT_NE(r.error.find("(the limit is 1.0 s) while this side waited for its commands for tick 3"), std::string::npos)
      << r.error;
  // Said whom it waited for, after half a second.
  EXPECT_TRUE(contains(r.log, "waiting for team 1 (red): its commands for tick 3 (0.")) << describe(r);
  // The timeout, then at most a second of trying to say goodbye; nowhere near ENet's own 5 to 30 s.
  EXPECT_GE(r.seconds, 1.0);
  EXPECT_LT(r.seconds, 4.0);
}

TEST(NetLockstep, APeerThatDisconnectsEndsTheGameAtOnce) {
  GameSettings s;
  s.units = 4;
  std::unique_ptr<Transport> host = Transport::host(0);
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  BarePeer peer(host->localPort());
  peer.helloFor(s);
  peer.transport->close(2.0);
  const SideResult r = hostSide.get();
  EXPECT_EQ(r.kind, SessionError::Kind::PeerLost);
  EXPECT_EQ(r.error, "the peer disconnected while this side waited for its commands for tick 3") << describe(r);
  EXPECT_LT(r.seconds, s.peerTimeout / 2) << "found by the disconnect, not by the timeout";
}

TEST(NetLockstep, APeerThatSendsGarbageIsDroppedWithTheDecodeError) {
  GameSettings s;
  s.units = 4;
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  const std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  const rts::net::DecodeContext context{uint32_t(game->units().size()), uint32_t(game->map().gates.size())};
  // An unknown message type instead of a Hello; a Commands message cut short; a Move naming a unit the
  // game does not have (a decode error only the game's sizes reveal).
  rts::net::Commands move;
  move.tick = 3;
  move.team = 1;
  move.commands.push_back({3, 1, rts::CommandType::Move, {uint32_t(game->units().size())}, {1, 1}, 0});
  const std::vector<std::pair<bool, std::vector<uint8_t>>> cases = {
      {false, {9, 1, 2}}, {true, {3, 0, 0}}, {true, rts::net::encode(move)}};
  for (const auto& [afterHello, bytes] : cases) {
    const rts::net::Decoded expected = rts::net::decode(bytes.data(), bytes.size(), context);
    ASSERT_FALSE(expected.ok());
    SCOPED_TRACE(expected.error);
    std::unique_ptr<Transport> host = Transport::host(0);
    std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
    BarePeer peer(host->localPort());
    if (afterHello) {
      peer.helloFor(s);
    } else {
      ASSERT_EQ(pollFor(*peer.transport, TransportEvent::Kind::Connected, 10).kind, TransportEvent::Kind::Connected);
    }
    peer.transport->sendBytes(bytes);
    // It says so to the peer before it leaves.
    EXPECT_EQ(peer.lastWords(context), "you sent garbage: " + expected.error);
    const SideResult r = hostSide.get();
    EXPECT_EQ(r.kind, SessionError::Kind::Protocol);
    EXPECT_EQ(r.error, "the peer sent garbage: " + expected.error);
  }
}

// Each case is decided by the messages alone, not by when they arrive: without the peer's commands
// for tick 3 the host never gets past tick 3 (the input delay's free ticks), whatever the timing.
TEST(NetLockstep, MessagesOutOfTurnBreakTheProtocol) {
  GameSettings s;
  s.units = 4;
  s.hashEvery = 10;
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  const std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  const uint64_t start = game->stateHash();
  const rts::net::DecodeContext context{uint32_t(game->units().size()), uint32_t(game->map().gates.size())};
  rts::net::Commands skipped;
  skipped.tick = 5;
  skipped.team = 1;
  rts::net::Commands otherTeam;
  otherTeam.tick = 3;
  otherTeam.team = 0;
  const std::vector<std::pair<std::vector<rts::net::Message>, std::string>> cases = {
      // Tick 10's state after the host has sent commands through tick 6 at most: it cannot be known yet.
      {{rts::net::Hash{0, start}, rts::net::Hash{10, 1}},
       "the peer broke the protocol: Hash for tick 10: a tick it cannot have played yet"},
      {{rts::net::Hash{0, start}, rts::net::Hash{0, start}},
       "the peer broke the protocol: Hash for tick 0: expected tick 10 next"},
      {{skipped}, "the peer broke the protocol: Commands for tick 5 of team 1: expected tick 3 next"},
      {{otherTeam}, "the peer broke the protocol: Commands for tick 3 of team 0: it plays team 1 (red)"},
      {{rts::net::Hello{}}, "the peer broke the protocol: a second Hello"},
      {{rts::net::Hash{0, start + 1}},
       "desync at tick 0: mine " +
           [&] {
             char text[64];
             std::snprintf(text, sizeof text, "%016llx, theirs %016llx", (unsigned long long)start,
                           (unsigned long long)(start + 1));
             return std::string(text);
           }()},
  };
  for (const auto& [messages, line] : cases) {
    SCOPED_TRACE(line);
    std::unique_ptr<Transport> host = Transport::host(0);
    std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
    BarePeer peer(host->localPort());
    peer.helloFor(s);
    for (const rts::net::Message& m : messages) peer.transport->send(m);
    const std::string told = peer.lastWords(context);
    const SideResult r = hostSide.get();
    EXPECT_EQ(told, line.rfind("desync", 0) == 0 ? "desync at tick 0" : "you" + line.substr(std::strlen("the peer")));
    EXPECT_EQ(r.error, line) << describe(r);
    EXPECT_EQ(r.kind, line.rfind("desync", 0) == 0 ? SessionError::Kind::Desync : SessionError::Kind::Protocol);
    EXPECT_LE(r.ticksPlayed, 3u);
  }
}

}  // namespace
