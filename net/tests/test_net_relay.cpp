// Lockstep through a bad network (issue 26, point 7): two sessions in one process, the joiner connected
// to the host through net/faulty_relay.h, which drops 10% of the datagrams each way, sends 5% twice, holds
// 5% back behind later ones and delays every one by 50 to 200 ms. The game must come out exactly as
// without the relay; only the waiting grows.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <future>

#include "lockstep_test_support.h"
#include "net/faulty_relay.h"

namespace {

using namespace net_test;
using rts::net::FaultModel;
using rts::net::FaultyRelay;
using rts::net::RelayCounts;
using rts::net::Transport;

struct RelayedPair {
  SideResult host, joiner;
  RelayCounts towardsHost, towardsJoiner;
  double seconds = 0;
};

// Each side in its own thread with its own transport, game and session, as two processes; the joiner
// talks to the relay's port, which the system picked, as the host's.
RelayedPair playThroughRelay(const GameSettings& s, const FaultModel& model) {
  std::unique_ptr<Transport> host = Transport::host(0);
  FaultyRelay relay(0, "127.0.0.1", host->localPort(), model);
  relay.start();
  const auto start = std::chrono::steady_clock::now();
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  std::unique_ptr<Transport> joiner = Transport::join("127.0.0.1", relay.port());
  RelayedPair p;
  p.joiner = playSide(*joiner, 1, s);
  p.host = hostSide.get();
  p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  relay.stop();
  p.towardsHost = relay.towardsHost();
  p.towardsJoiner = relay.towardsJoiner();
  return p;
}

void print(const char* way, const RelayCounts& c) {
  std::printf("[ relay    ] %s: %llu datagrams, %llu dropped, %llu duplicated, %llu held back\n", way,
              static_cast<unsigned long long>(c.received), static_cast<unsigned long long>(c.dropped),
              static_cast<unsigned long long>(c.duplicated), static_cast<unsigned long long>(c.heldBack));
}

// The input delay. These sides do not wait for a clock between ticks, as a headless game does not: each
// plays until it needs the peer's commands, which can be no more than d ticks ahead of its own, so the
// game advances d ticks a trip through the relay. A trip is 50-200 ms, and more when a datagram is lost:
// ENet's reliable channel delivers in order, so every later message waits for the resend (a round trip
// and more, at most twice ENet's first timeout: net/transport.cpp). With 2 datagrams a tick each way,
// most trips meet a loss, and one takes about 0.7 s. 600 ticks are then 600 / d trips: with the default
// d of 3, two minutes; with 15, about 25 s; with 30 (one second at 30 ticks a second, what a player
// behind this network would choose), about 13 s on two cores.
constexpr uint16_t kRelayInputDelay = 30;

TEST(NetRelay, A600TickGameThroughTheFaultyRelayIsTheGameWithoutIt) {
  GameSettings s;  // arena, 20 units a team: a tick costs well under a millisecond, the network is all
  s.seed = 4;
  s.ticks = 600;
  s.inputDelay = kRelayInputDelay;
  s.peerTimeout = 15;      // above any stall the relay causes; a real loss of the peer still ends the test
  const FaultModel model;  // 10% dropped, 5% duplicated, 5% held back, 50-200 ms, seed 26

  const RelayedPair p = playThroughRelay(s, model);
  std::printf(
      "[ relay    ] 600 ticks in %.1f s; waited for the peer: host %.2f s (longest %.2f s), joiner %.2f s "
      "(longest %.2f s)\n",
      p.seconds, p.host.waited, p.host.longestWait, p.joiner.waited, p.joiner.longestWait);
  print("towards the host", p.towardsHost);
  print("towards the joiner", p.towardsJoiner);
  RecordProperty("seconds", std::to_string(p.seconds));
  RecordProperty("host_waited_seconds", std::to_string(p.host.waited));
  RecordProperty("joiner_waited_seconds", std::to_string(p.joiner.waited));

  ASSERT_TRUE(p.host.finished) << describe(p.host);
  ASSERT_TRUE(p.joiner.finished) << describe(p.joiner);
  EXPECT_EQ(p.host.ticksPlayed, 600u);
  EXPECT_EQ(p.joiner.ticksPlayed, 600u);
  EXPECT_EQ(p.host.finalHash, p.joiner.finalHash);
  EXPECT_EQ(p.host.hashesCompared, 601u);  // every tick's, 0 to 600
  EXPECT_EQ(p.joiner.hashesCompared, 601u);

  // The same game without the relay: as one loop plays it, and over ENet on localhost directly.
  const LocalGame local = playDelayedLocal(s);
  EXPECT_EQ(p.host.finalHash, local.finalHash);
  EXPECT_EQ(p.host.applied.size(), local.applied.size());
  std::unique_ptr<Transport> host = Transport::host(0);
  std::future<SideResult> hostSide = std::async(std::launch::async, [&] { return playSide(*host, 0, s); });
  std::unique_ptr<Transport> joiner = Transport::join("127.0.0.1", host->localPort());
  const SideResult direct = playSide(*joiner, 1, s);
  ASSERT_TRUE(hostSide.get().finished);
  ASSERT_TRUE(direct.finished) << describe(direct);
  EXPECT_EQ(direct.finalHash, p.host.finalHash);

  // Both sides waited for the other: the relay's delay alone is 50 ms a datagram.
  EXPECT_GT(p.host.waited, 0.0);
  EXPECT_GT(p.joiner.waited, 0.0);
  // The relay did what it is for, both ways.
  for (const RelayCounts& c : {p.towardsHost, p.towardsJoiner}) {
    EXPECT_GT(c.received, 600u);
    EXPECT_GT(c.dropped, 0u);
    EXPECT_GT(c.duplicated, 0u);
    EXPECT_GT(c.heldBack, 0u);
    EXPECT_EQ(c.strangers, 0u);
  }
  EXPECT_LT(p.seconds, 60.0);
}

}  // namespace
