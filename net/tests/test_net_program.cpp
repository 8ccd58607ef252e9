// rattle-demo --host and --join as programs: two processes play one game headless and print the same
// final hash line, both record replays that verify and hold the same commands, the same through the
// faulty relay, a mismatch is refused with exit status 3 on both sides, and the options are checked;
// rattle-relay says how to use it. One side in a window: test_net_window.cpp.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "format/replay_reader.h"
#include "lockstep_test_support.h"
#include "net/faulty_relay.h"
#include "program_test_support.h"

namespace {

using namespace net_test;

const std::string kGame =
    "--map " + sourcePath("assets/maps/small.json") + " --units 6 --ticks 120 --no-render --quiet";

TEST(NetProgram, TwoProcessesPlayOneGameAndRecordTheSameCommands) {
  const std::string hostReplay = scratch("host.replay"), joinReplay = scratch("join.replay");
  HostProcess host(kGame + " --seed 5 --record " + hostReplay);
  ASSERT_GT(host.port(), 0) << host.finish().output;
  const Outcome joiner = run(RATTLE_DEMO_BINARY, "--join 127.0.0.1:" + std::to_string(host.port()) + " " + kGame +
                                                     " --seed 5 --record " + joinReplay);
  const Outcome hosted = host.finish();
  ASSERT_EQ(hosted.status, 0) << hosted.output;
  ASSERT_EQ(joiner.status, 0) << joiner.output;
  const std::string line = finalLine(hosted.output);
  EXPECT_EQ(line.rfind("Network game over after 120 ticks: final state hash ", 0), 0u) << hosted.output;
  EXPECT_EQ(finalLine(joiner.output), line);
  // The summary's own hash says the same.
  EXPECT_NE(hosted.output.find("Final state hash " + line.substr(line.find("hash ") + 5, 16)), std::string::npos);

  // Both replays verify, and they hold the same ticks: commands and hashes.
  for (const std::string& file : {hostReplay, joinReplay}) {
    const Outcome verified = run(RATTLE_REPLAY_BINARY, "verify " + file);
    EXPECT_EQ(verified.status, 0) << verified.output;
    EXPECT_TRUE(has(verified, "all 120 ticks match")) << verified.output;
  }
  const rts::replay::ReadResult a = rts::replay::readReplayFile(hostReplay),
                                b = rts::replay::readReplayFile(joinReplay);
  ASSERT_TRUE(a.ok()) << a.error.describe();
  ASSERT_TRUE(b.ok()) << b.error.describe();
  EXPECT_EQ(a.replay->config.recordedBy, "rattle-demo --host");
  EXPECT_EQ(b.replay->config.recordedBy, "rattle-demo --join");
  EXPECT_EQ(a.replay->config.opponentTeams, 1);
  EXPECT_EQ(b.replay->config.opponentTeams, 2);
  ASSERT_EQ(a.replay->ticks.size(), 120u);
  ASSERT_EQ(b.replay->ticks.size(), 120u);
  size_t commands = 0;
  for (size_t t = 0; t < a.replay->ticks.size(); ++t) {
    const rts::replay::TickRecord &x = a.replay->ticks[t], &y = b.replay->ticks[t];
    EXPECT_EQ(x.stateHash, y.stateHash) << "tick " << x.tick;
    ASSERT_EQ(x.commands.size(), y.commands.size()) << "tick " << x.tick;
    for (size_t i = 0; i < x.commands.size(); ++i) {
      expectSameCommand(x.commands[i], y.commands[i]);
      EXPECT_EQ(x.commands[i].gate, y.commands[i].gate);
      // Team 0's before team 1's, on both sides.
      if (i > 0) {
        EXPECT_LE(x.commands[i - 1].team, x.commands[i].team);
      }
    }
    commands += x.commands.size();
  }
  EXPECT_GT(commands, 0u);
  // The first three ticks (the input delay) have none.
  for (size_t t = 0; t < 3; ++t) EXPECT_TRUE(a.replay->ticks[t].commands.empty()) << t;
}

/// The seconds a side says it waited for the other in all ("waited 1.23 s for ..."), or -1.
double waitedIn(const std::string& output) {
  const size_t at = output.find("; waited ");
  return at == std::string::npos ? -1 : std::atof(output.c_str() + at + std::strlen("; waited "));
}

// The joiner connects to the relay (in this process), which forwards to the host with 10% of the
// datagrams lost, 5% doubled, 5% held back and 50-200 ms of delay. An input delay of 30 ticks: see
// test_net_relay.cpp for why; 120 ticks take a few seconds.
TEST(NetProgram, TwoProcessesPlayOneGameThroughTheFaultyRelay) {
  const std::string game = kGame + " --seed 9 --input-delay 30 --peer-timeout 15";
  HostProcess host(game);
  ASSERT_GT(host.port(), 0) << host.finish().output;
  rts::net::FaultyRelay relay(0, "127.0.0.1", uint16_t(host.port()), rts::net::FaultModel{});
  relay.start();
  const Outcome joiner = run(RATTLE_DEMO_BINARY, "--join 127.0.0.1:" + std::to_string(relay.port()) + " " + game);
  const Outcome hosted = host.finish();
  relay.stop();
  ASSERT_EQ(hosted.status, 0) << hosted.output;
  ASSERT_EQ(joiner.status, 0) << joiner.output;
  const std::string line = finalLine(hosted.output);
  EXPECT_EQ(line.rfind("Network game over after 120 ticks: final state hash ", 0), 0u) << hosted.output;
  EXPECT_EQ(finalLine(joiner.output), line);
  // Both say how long they waited, and through this network they did.
  EXPECT_GT(waitedIn(hosted.output), 0) << hosted.output;
  EXPECT_GT(waitedIn(joiner.output), 0) << joiner.output;
  std::printf("[ relay    ] waited: host %.2f s, joiner %.2f s\n", waitedIn(hosted.output), waitedIn(joiner.output));
  EXPECT_GT(relay.towardsHost().dropped + relay.towardsJoiner().dropped, 0u);
}

// A third process watches a game under way: it comes in once the players have started, plays the game
// so far and follows it, and ends with their final hash; all three print what the game cost the network.
TEST(NetProgram, AThirdProcessWatchesAGameUnderWay) {
  // Long enough that the watcher, started once the players play, finds the game under way on a loaded
  // machine: the players run some 13,000 ticks a second, and a game of 9,000 was sometimes over before
  // a watcher starved of CPU time connected (it then waited 10 s for a host that had left).
  const std::string game =
      "--map " + sourcePath("assets/maps/small.json") + " --units 6 --ticks 45000 --no-render --quiet --seed 3";
  HostProcess host(game + " --record " + scratch("host.replay"));
  ASSERT_GT(host.port(), 0) << host.finish().output;
  const std::string at = "127.0.0.1:" + std::to_string(host.port());
  Background joiner("--join " + at + " " + game, scratch("join.log"));
  ASSERT_TRUE(host.readUntil("playing blue (team 0) against red (team 1)")) << host.finish().output;
  // A spectator starts under way, and a replay at tick 0: the two do not go together.
  const Outcome recording =
      run(RATTLE_DEMO_BINARY, "--watch " + at + " " + game + " --record " + scratch("watch.replay"));
  EXPECT_EQ(recording.status, 2) << recording.output;
  EXPECT_TRUE(has(recording, "--watch cannot go with --record")) << recording.output;
  const Outcome watcher = run(RATTLE_DEMO_BINARY, "--watch " + at + " " + game);
  const Outcome joined = joiner.finish();
  const Outcome hosted = host.finish();
  ASSERT_EQ(hosted.status, 0) << hosted.output;
  ASSERT_EQ(joined.status, 0) << joined.output;
  ASSERT_EQ(watcher.status, 0) << watcher.output;
  const std::string line = finalLine(hosted.output);
  EXPECT_EQ(finalLine(joined.output), line);
  EXPECT_EQ(finalLine(watcher.output),
            "Network game over after 45000 ticks: final state hash " + hashIn(line) + ", the same as the host's.");
  const size_t joinedAt = watcher.output.find("joined at tick ");
  ASSERT_NE(joinedAt, std::string::npos) << watcher.output;
  const long tick = std::atol(watcher.output.c_str() + joinedAt + std::strlen("joined at tick "));
  EXPECT_GT(tick, 0) << watcher.output;
  EXPECT_TRUE(has(hosted, "rattle-demo: a spectator is watching from tick " + std::to_string(tick))) << hosted.output;
  EXPECT_TRUE(has(watcher, "watching from tick " + std::to_string(tick) + ", the host's state loaded ("))
      << watcher.output;
  for (const Outcome* o : {&hosted, &joined, &watcher}) {
    EXPECT_TRUE(has(*o, "Network traffic over 45000 ticks (1500.0 s of game time;")) << o->output;
    EXPECT_TRUE(has(*o, "UDP socket, ENet's headers, acknowledgements, pings and resends included: sent ")) << o->output;
  }
  EXPECT_TRUE(has(hosted, "To the spectator (1 served): ")) << hosted.output;
  // The host's replay holds the ReloadWorld it issued for the spectator, and verifies: its world loaded
  // from its save there, as replaying the command does.
  const Outcome verified = run(RATTLE_REPLAY_BINARY, "verify " + scratch("host.replay"));
  EXPECT_EQ(verified.status, 0) << verified.output;
  EXPECT_TRUE(has(verified, "all 45000 ticks match")) << verified.output;
}

TEST(NetProgram, TheRelayProgramSaysHowToUseIt) {
  const Outcome help = run(RATTLE_RELAY_BINARY, "--help");
  EXPECT_EQ(help.status, 0);
  for (const char* part : {"--to HOST:PORT", "--listen PORT", "--seed N", "(default 26)", "--drop P", "(default 0.10)",
                           "--duplicate P", "(default 0.05)", "--reorder P", "--delay MIN-MAX", "(default 50-200)"}) {
    EXPECT_TRUE(has(help, part)) << part;
  }
  struct Case {
    const char* arguments;
    const char* message;
  };
  for (const Case& c : {
           Case{"", "rattle-relay: --to HOST:PORT is required"},
           Case{"--to localhost", "rattle-relay: --to localhost: expected HOST:PORT"},
           Case{"--to localhost:0", "rattle-relay: --to localhost:0: expected a port from 1 to 65535"},
           Case{"--to localhost:9 --listen 1.5", "rattle-relay: --listen 1.5: expected a port from 0 to 65535"},
           Case{"--to localhost:9 --drop 1.5", "rattle-relay: --drop 1.5: expected a probability from 0 to 1"},
           Case{"--to localhost:9 --delay 200-50", "rattle-relay: --delay 200-50: MIN is above MAX"},
           Case{"--to localhost:9 --frobnicate 1", "rattle-relay: --frobnicate: unknown option"},
       }) {
    const Outcome o = run(RATTLE_RELAY_BINARY, c.arguments);
    EXPECT_EQ(o.status, 2) << c.arguments << ": " << o.output;
    EXPECT_TRUE(has(o, c.message)) << c.arguments << ": " << o.output;
  }
  const Outcome unresolved = run(RATTLE_RELAY_BINARY, "--to no-such-host.invalid:9 --seconds 1");
  EXPECT_EQ(unresolved.status, 1) << unresolved.output;
  EXPECT_TRUE(has(unresolved, "rattle-relay: cannot resolve the host name 'no-such-host.invalid'"))
      << unresolved.output;
}

TEST(NetProgram, AMismatchIsRefusedOnBothSidesWithStatus3) {
  HostProcess host(kGame + " --seed 5 --input-delay 4");
  ASSERT_GT(host.port(), 0) << host.finish().output;
  const Outcome joiner =
      run(RATTLE_DEMO_BINARY, "--join 127.0.0.1:" + std::to_string(host.port()) + " " + kGame + " --seed 6");
  const Outcome hosted = host.finish();
  EXPECT_EQ(hosted.status, 3) << hosted.output;
  EXPECT_EQ(joiner.status, 3) << joiner.output;
  EXPECT_TRUE(has(
      hosted, "rattle-demo: the handshake failed: seed: mine 5, theirs 6; input delay: mine 4 ticks, theirs 3 ticks\n"))
      << hosted.output;
  EXPECT_TRUE(has(
      joiner, "rattle-demo: the handshake failed: seed: mine 6, theirs 5; input delay: mine 3 ticks, theirs 4 ticks\n"))
      << joiner.output;
  EXPECT_EQ(finalLine(hosted.output), "none");
}

TEST(NetProgram, NobodyThereIsStatus5WithinThePeerTimeout) {
  // A port nobody answers on: one a host held a moment ago, now closed.
  uint16_t port = 0;
  {
    const std::unique_ptr<rts::net::Transport> gone = rts::net::Transport::host(0);
    port = gone->localPort();
  }
  const Outcome o =
      run(RATTLE_DEMO_BINARY, "--join 127.0.0.1:" + std::to_string(port) + " " + kGame + " --peer-timeout 0.5");
  EXPECT_EQ(o.status, 5) << o.output;
  EXPECT_TRUE(has(o, "rattle-demo: cannot connect: no answer after ")) << o.output;
}

TEST(NetProgram, OptionsAreChecked) {
  struct Case {
    const char* arguments;
    const char* message;
  };
  for (const Case& c : {
           Case{"--host 70000", "--host 70000: expected a port from 0 to 65535"},
           Case{"--host --join localhost", "--join: a side either hosts, joins or watches, once"},
           Case{"--join localhost --watch localhost", "--watch: a side either hosts, joins or watches, once"},
           Case{"--watch", "--watch (missing): expected HOST or HOST:PORT"},
           Case{"--watch localhost:0", "--watch localhost:0: the port after ':' must be a whole number from 1 to 65535"},
           Case{"--watch localhost --window --no-render", "--window and --no-render cannot go together"},
           Case{"--join", "--join (missing): expected HOST or HOST:PORT"},
           Case{"--join a:b:c", "--join a:b:c: expected HOST or HOST:PORT"},
           Case{"--join localhost:0", "--join localhost:0: the port after ':' must be a whole number from 1 to 65535"},
           Case{"--input-delay 3", "--input-delay needs --host, --join or --watch"},
           Case{"--host --input-delay 301", "--input-delay 301: expected a whole number from 0 to 300"},
           Case{"--host --hash-every 0", "--hash-every 0: expected a whole number from 1 to 65535"},
           Case{"--join x --peer-timeout 0", "--peer-timeout 0: expected seconds from 0.1 to 3600"},
       }) {
    const Outcome o = run(RATTLE_DEMO_BINARY, c.arguments);
    EXPECT_EQ(o.status, 2) << c.arguments << ": " << o.output;
    EXPECT_TRUE(has(o, c.message)) << c.arguments << ": " << o.output;
  }
  const Outcome help = run(RATTLE_DEMO_BINARY, "--help");
  for (const char* part :
       {"--host [PORT]", "default 47800", "--join HOST[:PORT]", "--watch HOST[:PORT]", "--input-delay N", "(default 3", "--hash-every K",
        "(default 1)", "--peer-timeout S", "(default 10)", "3 the handshake refused", "4 desync",
        "5 the peer could not be", "6 the peer sent garbage", "or with --window by you",
        "or you quit it in a window (the\n  peer is told)"}) {
    EXPECT_TRUE(has(help, part)) << part;
  }
  const Outcome unresolved = run(RATTLE_DEMO_BINARY, "--join no-such-host.invalid --no-render --ticks 1");
  EXPECT_EQ(unresolved.status, 1) << unresolved.output;
  EXPECT_TRUE(has(unresolved, "rattle-demo: cannot resolve the host name 'no-such-host.invalid'")) << unresolved.output;
}

}  // namespace
