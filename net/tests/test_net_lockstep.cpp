// Two lockstep sessions in one process, over real ENet on localhost: a whole game, a refused
// handshake, a peer that goes silent, one that disconnects, one that sends garbage. Every host listens
// on a port the system picks (0), so tests running side by side never share one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <future>
#include <optional>
#include <thread>

#include "lockstep_test_support.h"
#include "net/delayed_source.h"
#include "tool/divergence.h"
#include "tool/snapshot.h"

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

// The game without a network, perturbed as the side playing `team` would be: the state hash of every
// tick, 0 to s.ticks, and the game as it is after the last.
struct LocalRun {
  std::vector<uint64_t> hashes;
  std::unique_ptr<rts::Game> game;
};

LocalRun playLocalPerturbed(const GameSettings& s, uint8_t team) {
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  LocalRun run{{}, makeGame(s, mapJson)};
  rts::Game& game = *run.game;
  rts::ScriptedOpponent blue(s.seed, 1), red(s.seed, 2);
  rts::net::DelayedSource blueLater(blue, s.inputDelay), redLater(red, s.inputDelay);
  rts::TickLoop loop(game);
  loop.add(blueLater);
  loop.add(redLater);
  run.hashes.push_back(game.stateHash());
  for (uint32_t t = 0; t < s.ticks; ++t) {
    loop.tick();
    run.hashes.push_back(game.stateHash());
    if (game.tickCount() == s.perturbAfter) game.apply(perturbation(game, team));
  }
  return run;
}

std::string exact(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

// After tick 100 the joiner orders a unit of its own outside the lockstep: from tick 101 on the two
// games differ. Each side sends its hash of a tick before it can know the other's, so both find the
// desync, at the same tick, each with its own hash first. Then each sends the other its state at that
// tick, though it may have played on, and both print the report rattle-replay verify would: the one body
// that differs and its fields, mine first.
TEST(NetLockstep, ADesyncIsFoundAndExplainedOnBothSidesAtTheFirstTickThatDiffers) {
  GameSettings host, joiner;
  host.units = joiner.units = 10;
  joiner.perturbAfter = 100;
  GameSettings upTo101 = host;
  upTo101.ticks = 101;
  const LocalRun same = playLocalPerturbed(upTo101, 0);
  upTo101.perturbAfter = 100;
  const LocalRun perturbed = playLocalPerturbed(upTo101, 1);
  size_t first = 0;
  while (first < same.hashes.size() && same.hashes[first] == perturbed.hashes[first]) ++first;
  ASSERT_EQ(first, 101u) << "the order changes the state hash of the next tick";

  const Pair p = playPair(host, joiner);
  std::printf("[ host     ] %s\n%s[ joiner   ] %s\n%s", p.host.error.c_str(), p.host.details.c_str(),
              p.joiner.error.c_str(), p.joiner.details.c_str());
  EXPECT_EQ(p.host.kind, SessionError::Kind::Desync) << describe(p.host);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::Desync) << describe(p.joiner);
  const std::string tick = "desync at tick 101: mine ";
  EXPECT_EQ(p.host.error, tick + hex(same.hashes[101]) + ", theirs " + hex(perturbed.hashes[101]));
  EXPECT_EQ(p.joiner.error, tick + hex(perturbed.hashes[101]) + ", theirs " + hex(same.hashes[101]));
  // Each played the tick that differs, and neither got further than the other's commands allow.
  EXPECT_GE(p.host.ticksPlayed, 101u);
  EXPECT_GE(p.joiner.ticksPlayed, 101u);
  EXPECT_LE(p.host.ticksPlayed, 101u + host.inputDelay);
  EXPECT_LE(p.joiner.ticksPlayed, 101u + host.inputDelay);

  // The report, from the two games as they were at tick 101 (read here from the games themselves): the
  // unit the joiner ordered, alone, with its order's target (the middle of the map on the joiner's side)
  // among its fields.
  const rts::Game &mine = *same.game, &theirs = *perturbed.game;
  uint32_t unit = 0;
  while (theirs.units()[unit].team != 1 || !theirs.units()[unit].alive) ++unit;
  ASSERT_TRUE(theirs.units()[unit].order.active);
  ASSERT_EQ(theirs.units()[unit].order.target.x, theirs.map().width / 2);
  const std::string name = "unit " + std::to_string(unit) + " (red)";
  const std::string world =
      "  engine world hash: mine " + hex(mine.worldHash()) + ", theirs " + hex(theirs.worldHash());
  const std::string bodies = "  bodies that differ at tick 101 (1): " + name + "\n  fields at tick 101:\n";
  const double a = mine.units()[unit].order.target.x, b = theirs.units()[unit].order.target.x;
  ASSERT_TRUE(mine.units()[unit].order.active);
  ASSERT_NE(a, b);
  char delta[32];
  std::snprintf(delta, sizeof delta, "%+.3g", b - a);
  EXPECT_EQ(p.host.details.rfind(world + "\n" + bodies, 0), 0u) << p.host.details;
  EXPECT_NE(p.host.details.find("    " + name + " order.target.x: mine " + exact(a) + ", theirs " + exact(b) + " (" +
                                delta + ")\n"),
            std::string::npos)
      << p.host.details;
  EXPECT_NE(p.host.details.find("    " + name + " position.x: mine "), std::string::npos) << p.host.details;
  std::snprintf(delta, sizeof delta, "%+.3g", a - b);
  const std::string joinerWorld =
      "  engine world hash: mine " + hex(theirs.worldHash()) + ", theirs " + hex(mine.worldHash());
  EXPECT_EQ(p.joiner.details.rfind(joinerWorld + "\n" + bodies, 0), 0u) << p.joiner.details;
  EXPECT_NE(p.joiner.details.find("    " + name + " order.target.x: mine " + exact(b) + ", theirs " + exact(a) + " (" +
                                  delta + ")\n"),
            std::string::npos)
      << p.joiner.details;
  // Only that unit: no other body is named.
  for (const std::string& details : {p.host.details, p.joiner.details}) {
    size_t lines = 0;
    for (size_t at = details.find("\n    "); at != std::string::npos; at = details.find("\n    ", at + 1)) {
      EXPECT_EQ(details.compare(at + 5, name.size() + 1, name + " "), 0) << details;
      ++lines;
    }
    EXPECT_GE(lines, 3u) << details;
  }
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

// The game's length and its steering change the game: the handshake compares them (issue 9), as the
// seed, and refuses on both sides before a tick is played.
TEST(NetLockstep, DifferentTickCountsAreRefusedOnBothSides) {
  GameSettings host, joiner;
  host.units = joiner.units = 4;
  host.ticks = 30;
  joiner.ticks = 31;
  const Pair p = playPair(host, joiner);
  EXPECT_EQ(p.host.kind, SessionError::Kind::Refused) << describe(p.host);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::Refused) << describe(p.joiner);
  EXPECT_EQ(p.host.error, "the handshake failed: ticks: mine 30, theirs 31");
  EXPECT_EQ(p.joiner.error, "the handshake failed: ticks: mine 31, theirs 30");
  EXPECT_EQ(p.host.ticksPlayed, 0u);
  EXPECT_EQ(p.joiner.ticksPlayed, 0u);
}

TEST(NetLockstep, DifferentSteeringIsRefusedOnBothSides) {
  GameSettings host, joiner;
  host.units = joiner.units = 4;
  joiner.steering = rts::Steering::Naive;
  const Pair p = playPair(host, joiner);
  EXPECT_EQ(p.host.kind, SessionError::Kind::Refused) << describe(p.host);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::Refused) << describe(p.joiner);
  EXPECT_EQ(p.host.error, "the handshake failed: steering: mine keep-apart, theirs naive");
  EXPECT_EQ(p.joiner.error, "the handshake failed: steering: mine naive, theirs keep-apart");
  EXPECT_EQ(p.host.ticksPlayed, 0u);
}

// Both naive: now that the handshake compares the steering, a networked game may be played with it,
// and it is the same game as one loop plays.
TEST(NetLockstep, TwoSidesWithNaiveSteeringPlayTheSameGame) {
  GameSettings s;
  s.units = 10;
  s.ticks = 120;
  s.steering = rts::Steering::Naive;
  const Pair p = playPair(s, s);
  ASSERT_TRUE(p.host.finished) << describe(p.host);
  ASSERT_TRUE(p.joiner.finished) << describe(p.joiner);
  EXPECT_EQ(p.host.finalHash, p.joiner.finalHash);
  EXPECT_EQ(p.host.finalHash, playDelayedLocal(s).finalHash);
  GameSettings keepApart = s;
  keepApart.steering = rts::Steering::KeepApart;
  EXPECT_NE(p.host.finalHash, playDelayedLocal(keepApart).finalHash);
}

// A hand-made joiner: connects, says a matching Hello, then does what the test says.
struct BarePeer {
  std::unique_ptr<Transport> transport;
  explicit BarePeer(uint16_t port) : transport(Transport::join("127.0.0.1", port)) {}
  void helloFor(const GameSettings& s) {
    ASSERT_EQ(pollFor(*transport, TransportEvent::Kind::Connected, 10).kind, TransportEvent::Kind::Connected);
    const std::string mapJson = readFile(sourcePath(s.mapFile));
    transport->send(
        rts::net::playerHello(*makeGame(s, mapJson), mapJson, s.seed, 1, s.inputDelay, s.hashEvery, s.ticks));
  }
  /// Keeps ENet going (acknowledging what comes, showing each message to `seen`) until the other side
  /// says Bye or leaves; returns the Bye's reason, or "" when there was none.
  std::string lastWords(const rts::net::DecodeContext& context,
                        const std::function<void(const rts::net::Message&)>& seen = {}) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < end) {
      const TransportEvent e = transport->poll(0.01, context);
      if (e.kind == TransportEvent::Kind::Disconnected) return "";
      if (e.message && seen) seen(*e.message);
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
  const rts::net::DecodeContext context = contextOf(*game);
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
// for tick 3 the host never gets past tick 3 (the input delay's free ticks), whatever the timing, and
// it takes commands up to tick 6 (its free ticks and the delay) before it has played any.
TEST(NetLockstep, MessagesOutOfTurnBreakTheProtocol) {
  GameSettings s;
  s.units = 4;
  s.hashEvery = 10;
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  const std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  const uint64_t start = game->stateHash();
  const rts::net::DecodeContext context = contextOf(*game);
  rts::net::Commands skipped;
  skipped.tick = 5;
  skipped.team = 1;
  rts::net::Commands otherTeam;
  otherTeam.tick = 3;
  otherTeam.team = 0;
  struct Case {
    std::vector<rts::net::Message> messages;
    std::string line;
    uint16_t hashEvery = 10;
    uint32_t maxTicks = 3;
  };
  const std::vector<Case> cases = {
      // Tick 10's state after the host has sent commands through tick 6 at most: it cannot be known yet.
      {{rts::net::Hash{0, start}, rts::net::Hash{10, 1}},
       "the peer broke the protocol: Hash for tick 10: a tick it cannot have played yet"},
      {{rts::net::Hash{0, start}, rts::net::Hash{0, start}},
       "the peer broke the protocol: Hash for tick 0: expected tick 10 next"},
      {{skipped}, "the peer broke the protocol: Commands for tick 5 of team 1: expected tick 3 next"},
      {{otherTeam}, "the peer broke the protocol: Commands for tick 3 of team 0: it plays team 1 (red)"},
      {{rts::net::Hello{}}, "the peer broke the protocol: a second Hello"},
      // With a hash every tick, the one for tick 1 comes before the commands for tick 4.
      {{rts::net::Hash{0, start}, rts::net::Commands{3, 1, {}}, rts::net::Commands{4, 1, {}}},
       "the peer broke the protocol: Commands for tick 4 of team 1: its hash for tick 1 has not come (a side sends "
       "its hash of tick t before its commands for tick t + the input delay)",
       1,
       4},
      // A state is sent only after hashes that differ.
      {{rts::net::Hash{0, start}, rts::net::Snapshot{0, game->worldHash(), rts::replay::snapshotOf(*game)}},
       "the peer broke the protocol: Snapshot for tick 0: no desync was found"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.line);
    GameSettings settings = s;
    settings.hashEvery = c.hashEvery;
    std::unique_ptr<Transport> host = Transport::host(0);
    std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, settings); });
    BarePeer peer(host->localPort());
    peer.helloFor(settings);
    for (const rts::net::Message& m : c.messages) peer.transport->send(m);
    const std::string told = peer.lastWords(context);
    const SideResult r = hostSide.get();
    EXPECT_EQ(told, "you" + c.line.substr(std::strlen("the peer")));
    EXPECT_EQ(r.error, c.line) << describe(r);
    EXPECT_EQ(r.kind, SessionError::Kind::Protocol);
    EXPECT_LE(r.ticksPlayed, c.maxTicks);
  }
}

std::string hashLine(uint32_t tick, uint64_t mine, uint64_t theirs) {
  return "desync at tick " + std::to_string(tick) + ": mine " + hex(mine) + ", theirs " + hex(theirs);
}

// A hand-made peer whose state at tick 0 differs from the host's in two known fields, and which says so
// only once the host has played on to tick 3: the host sends its state of tick 0 (kept for this), and
// its report names exactly those two fields, with the amounts.
TEST(NetLockstep, ADesyncIsExplainedFromThePeersStateFieldByField) {
  GameSettings s;
  s.units = 4;
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  const std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  const rts::net::DecodeContext context = contextOf(*game);
  rts::replay::Snapshot theirs = rts::replay::snapshotOf(*game);
  ASSERT_GE(theirs.units.size(), 8u);
  const int hitPoints = theirs.units[3].hitPoints;
  const double x = theirs.units[6].motion.px;
  theirs.units[3].hitPoints -= 1;
  theirs.units[6].motion.px = std::nextafter(x, 1e9);  // one ulp: rounding, as a real desync would be
  const std::string u3 = rts::replay::unitName(*game, 3), u6 = rts::replay::unitName(*game, 6);

  std::unique_ptr<Transport> host = Transport::host(0);
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  BarePeer peer(host->localPort());
  peer.helloFor(s);
  // The host plays the input delay's three free ticks at once, and sends a hash after each.
  for (bool played = false; !played;) {
    const TransportEvent e = pollFor(*peer.transport, TransportEvent::Kind::Received, 10, context);
    ASSERT_EQ(e.kind, TransportEvent::Kind::Received);
    const auto* hash = std::get_if<rts::net::Hash>(&*e.message);
    played = hash && hash->tick == 3;
  }
  peer.transport->send(rts::net::Hash{0, game->stateHash() + 1});
  peer.transport->send(rts::net::Snapshot{0, game->worldHash(), theirs});
  // The host's state comes first, then its Bye.
  std::optional<rts::net::Snapshot> hostState;
  const std::string told = peer.lastWords(context, [&](const rts::net::Message& m) {
    if (const auto* snapshot = std::get_if<rts::net::Snapshot>(&m)) hostState = *snapshot;
  });
  const SideResult r = hostSide.get();
  EXPECT_EQ(told, "desync at tick 0");
  ASSERT_TRUE(hostState.has_value());
  EXPECT_EQ(hostState->tick, 0u);
  EXPECT_EQ(hostState->worldHash, game->worldHash());
  EXPECT_EQ(hostState->state, rts::replay::snapshotOf(*game));

  EXPECT_EQ(r.kind, SessionError::Kind::Desync);
  EXPECT_EQ(r.error, hashLine(0, game->stateHash(), game->stateHash() + 1));
  const double after = std::nextafter(x, 1e9);
  char ulp[32];
  std::snprintf(ulp, sizeof ulp, "%+.3g", after - x);
  std::string expected = "  engine world hash: matches (the difference is in the game's own state)\n";
  expected += "  bodies that differ at tick 0 (2): " + u3 + ", " + u6 + "\n";
  expected += "  fields at tick 0:\n";
  expected += "    " + u3 + " hitPoints: mine " + std::to_string(hitPoints) + ", theirs " +
              std::to_string(hitPoints - 1) + " (-1)\n";
  expected += "    " + u6 + " position.x: mine " + exact(x) + ", theirs " + exact(after) + " (" + ulp + ", 1 ulp)\n";
  EXPECT_EQ(r.details, expected);
  EXPECT_EQ(r.ticksPlayed, 3u);
}

// A desync at the last tick is found as both sides end their games: one may have said Bye already, and
// its state follows its Bye. With a hash every 7 ticks the last (60) is compared off the interval, and the
// report says the games parted after tick 56.
TEST(NetLockstep, ADesyncAtTheLastTickIsExplainedToo) {
  for (const uint16_t every : {1, 7}) {
    SCOPED_TRACE("a hash every " + std::to_string(every) + " ticks");
    GameSettings host, joiner;
    host.units = joiner.units = 6;
    host.ticks = joiner.ticks = 60;
    host.hashEvery = joiner.hashEvery = every;
    joiner.perturbAfter = 59;
    const Pair p = playPair(host, joiner);
    for (const SideResult* r : {&p.host, &p.joiner}) {
      EXPECT_EQ(r->kind, SessionError::Kind::Desync) << describe(*r);
      EXPECT_EQ(r->error.rfind("desync at tick 60: mine ", 0), 0u) << describe(*r);
      EXPECT_EQ(r->ticksPlayed, 60u);
      EXPECT_NE(r->details.find("  bodies that differ at tick 60 (1): unit "), std::string::npos) << r->details;
      EXPECT_NE(r->details.find(" (red) order.target.x: mine "), std::string::npos) << r->details;
      const std::string parted =
          "  hashes are compared every 7 ticks: tick 56 matched, so the games parted at one of "
          "ticks 57 to 60\n";
      EXPECT_EQ(r->details.rfind(parted, 0) == 0, every == 7) << r->details;
    }
  }
}

// A state too large for a message is not sent, but the peer says so (a Snapshot without one) rather than
// leave this side waiting, and the report says why it names no bodies.
TEST(NetLockstep, AStateTooLargeToSendIsSaidSo) {
  GameSettings s;
  s.units = 4;
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  const std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  std::unique_ptr<Transport> host = Transport::host(0);
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  BarePeer peer(host->localPort());
  peer.helloFor(s);
  peer.transport->send(rts::net::Hash{0, game->stateHash() + 1});
  peer.transport->send(rts::net::Snapshot{0, game->worldHash() + 1, std::nullopt});
  EXPECT_EQ(peer.lastWords(contextOf(*game)), "desync at tick 0");
  const SideResult r = hostSide.get();
  EXPECT_EQ(r.kind, SessionError::Kind::Desync);
  EXPECT_EQ(r.error, hashLine(0, game->stateHash(), game->stateHash() + 1));
  EXPECT_EQ(r.details, "  engine world hash: mine " + hex(game->worldHash()) + ", theirs " +
                           hex(game->worldHash() + 1) +
                           "\n  bodies and fields: the peer's state at tick 0 is over the 1048562 bytes a message "
                           "carries; the two sides' replays (--record) hold every body's digest at every tick\n");
}

// When the peer's state does not come (it went silent, left or sent garbage), the game still ends as a
// desync, and the report says why there is nothing to compare.
TEST(NetLockstep, ADesyncWhoseStateDoesNotComeIsStillADesync) {
  GameSettings s;
  s.units = 4;
  s.peerTimeout = 1;
  const std::string mapJson = readFile(sourcePath(s.mapFile));
  const std::unique_ptr<rts::Game> game = makeGame(s, mapJson);
  for (const bool garbage : {false, true}) {
    SCOPED_TRACE(garbage ? "garbage" : "silence");
    std::unique_ptr<Transport> host = Transport::host(0);
    std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
    BarePeer peer(host->localPort());
    peer.helloFor(s);
    peer.transport->send(rts::net::Hash{0, game->stateHash() + 1});
    if (garbage) {
      // A state of another game: two units short.
      rts::replay::Snapshot other = rts::replay::snapshotOf(*game);
      other.units.resize(other.units.size() - 2);
      peer.transport->send(rts::net::Snapshot{0, game->worldHash(), other});
    }
    const std::string told = peer.lastWords(contextOf(*game));
    const SideResult r = hostSide.get();
    EXPECT_EQ(r.kind, SessionError::Kind::Desync);
    EXPECT_EQ(r.error, hashLine(0, game->stateHash(), game->stateHash() + 1));
    if (garbage) {
      EXPECT_EQ(r.details.rfind("  the peer's state at tick 0 did not come: the peer sent garbage: Snapshot", 0), 0u)
          << r.details;
      EXPECT_EQ(told.rfind("you sent garbage: Snapshot", 0), 0u) << told;
    } else {
      EXPECT_EQ(r.details.rfind("  the peer's state at tick 0 did not come: the peer has been silent for 1.", 0), 0u)
          << r.details;
      EXPECT_NE(r.details.find("while this side waited for its state at tick 0 (to explain the desync)\n"),
                std::string::npos)
          << r.details;
    }
  }
}

}  // namespace

namespace {

// A window's hook (LockstepConfig::whileWaiting): called on every round of a wait with whom and what,
// and the person quitting there leaves the game with a Bye, so the peer ends at once with "the peer
// left" instead of waiting out its timeout.
TEST(NetLockstep, LeavingDuringAWaitTellsThePeerWhichEndsAtOnce) {
  GameSettings hostSettings, joinerSettings;
  hostSettings.units = joinerSettings.units = 4;
  joinerSettings.tickSeconds = 0.5;  // a slow peer: the host waits half a second for every tick
  std::vector<std::pair<std::string, double>> rounds;
  hostSettings.whileWaiting = [&rounds](const std::string& what, double seconds) {
    rounds.emplace_back(what, seconds);
    // The handshake's waits are let pass; the first wait for the peer's commands to outlast 0.3 s is left.
    return what.find("its commands for tick") == std::string::npos || seconds < 0.3;
  };
  const Pair p = playPair(hostSettings, joinerSettings);
  EXPECT_FALSE(p.host.finished);
  EXPECT_EQ(p.host.left.rfind("waiting for team 1 (red): its commands for tick ", 0), 0u) << describe(p.host);
  EXPECT_TRUE(contains(p.host.log, "leaving the game: the player quit at tick ")) << describe(p.host);
  // Called on every round of the wait, some 60 a second: a window drawing there stays responsive.
  ASSERT_GE(rounds.size(), 10u);
  EXPECT_EQ(rounds.back().first.rfind("team 1 (red): its commands for tick ", 0), 0u) << rounds.back().first;
  EXPECT_GE(rounds.back().second, 0.3);
  EXPECT_LT(rounds.back().second, 0.5);

  EXPECT_FALSE(p.joiner.finished);
  EXPECT_EQ(p.joiner.kind, SessionError::Kind::PeerLost);
  EXPECT_EQ(p.joiner.error.rfind("the peer left (the player quit at tick " + std::to_string(p.host.ticksPlayed) + ")", 0),
            0u)
      << describe(p.joiner);
  EXPECT_LT(p.joiner.seconds, hostSettings.peerTimeout) << "found by the Bye, not by the timeout";
}

TEST(NetLockstep, AHostLeftBeforeAPlayerJoinedEndsWithoutOne) {
  GameSettings s;
  s.units = 4;
  s.whileWaiting = [](const std::string& what, double seconds) {
    return what != "the other player to connect" || seconds < 0.2;
  };
  std::unique_ptr<Transport> host = Transport::host(0);
  const SideResult r = playSide(*host, 0, s);
  EXPECT_FALSE(r.finished);
  EXPECT_EQ(r.left, "waiting for the other player to connect") << describe(r);
  EXPECT_EQ(r.ticksPlayed, 0u);
  EXPECT_LT(r.seconds, 2.0);
}

// Headless (no hook) the waits are as they were: the whole game plays through.
TEST(NetLockstep, AHookThatLetsEveryWaitPassChangesNothing) {
  GameSettings s;
  s.units = 6;
  s.ticks = 120;
  s.seed = 4;
  GameSettings hooked = s;
  int calls = 0;
  hooked.whileWaiting = [&calls](const std::string&, double) {
    ++calls;
    return true;
  };
  const Pair p = playPair(hooked, s);
  ASSERT_TRUE(p.host.finished) << describe(p.host);
  ASSERT_TRUE(p.joiner.finished) << describe(p.joiner);
  EXPECT_EQ(p.host.finalHash, p.joiner.finalHash);
  EXPECT_EQ(p.host.finalHash, playDelayedLocal(s).finalHash);
  EXPECT_GT(calls, 0);
}

}  // namespace
