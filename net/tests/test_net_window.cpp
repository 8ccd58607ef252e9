// Network play in the window, as programs under Xvfb: a person (an input script) in a window joins a
// headless host and plays red; both end with the same final hash, and their replays verify and hold the
// same commands, the person's orders among them. A person who quits early leaves the game: the window
// exits 0 and the host ends at once with "the peer left" (status 5). A window closed while it waits for
// a player exits 0 too. A host and a spectator in windows.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "format/replay_reader.h"
#include "lockstep_test_support.h"
#include "program_test_support.h"

namespace {

using namespace net_test;

bool haveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

/// rattle-demo in a window on a virtual display.
const std::string kWindowed =
    std::string("xvfb-run -a -s '-screen 0 800x600x24' ") + RATTLE_DEMO_BINARY + " --window --size 640x360";
/// The same as run() takes it: `timeout` ends it should a peer never come.
const std::string kWindowedRun = "timeout 120 " + kWindowed;

/// A 640x360 window on small.json (40x24): a drag over the whole window selects every unit of the
/// person's team, a right-click in the west room sends them there. Space is pressed: in a network game it
/// does not pause (if it did, the game would never reach its last tick and the host would give up).
std::string writeScript(const std::string& name, const std::string& more) {
  const std::string path = scratch(name);
  std::ofstream out(path);
  out << "# frame event arguments (window pixels)\n"
         "3 drag 1 1 638 358\n"
         "4 rclick 100 180\n"
         "20 key space\n"
      << more;
  return path;
}

const std::string kGame = "--map " + sourcePath("assets/maps/small.json") + " --units 4 --seed 7";

TEST(NetWindow, APersonInAWindowPlaysRedAgainstAHeadlessHost) {
  if (!haveXvfb()) FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  const std::string hostReplay = scratch("host.replay"), joinReplay = scratch("join.replay");
  const std::string script = writeScript("input.txt", "60 rclick 560 180\n");
  HostProcess host(kGame + " --ticks 100 --no-render --quiet --record " + hostReplay);
  ASSERT_GT(host.port(), 0) << host.finish().output;
  const Outcome window = run(kWindowedRun, "--join 127.0.0.1:" + std::to_string(host.port()) + " " + kGame +
                                            " --ticks 100 --input " + script + " --record " + joinReplay);
  const Outcome hosted = host.finish();
  ASSERT_EQ(hosted.status, 0) << hosted.output;
  ASSERT_EQ(window.status, 0) << window.output;
  const std::string line = finalLine(hosted.output);
  EXPECT_EQ(line.rfind("Network game over after 100 ticks: final state hash ", 0), 0u) << hosted.output;
  EXPECT_EQ(finalLine(window.output), line) << window.output;
  EXPECT_TRUE(has(window, "Ran 100 ticks")) << window.output;
  EXPECT_TRUE(has(window, "rattle-demo: playing red (team 1) against blue (team 0)")) << window.output;
  EXPECT_TRUE(has(window, "state hashes compared with the peer's; waited ")) << window.output;
  EXPECT_TRUE(has(window, "Network traffic over 100 ticks")) << window.output;

  for (const std::string& file : {hostReplay, joinReplay}) {
    const Outcome verified = run(RATTLE_REPLAY_BINARY, "verify " + file);
    EXPECT_EQ(verified.status, 0) << verified.output;
    EXPECT_TRUE(has(verified, "all 100 ticks match")) << verified.output;
  }
  const rts::replay::ReadResult a = rts::replay::readReplayFile(hostReplay),
                                b = rts::replay::readReplayFile(joinReplay);
  ASSERT_TRUE(a.ok()) << a.error.describe();
  ASSERT_TRUE(b.ok()) << b.error.describe();
  EXPECT_EQ(b.replay->config.recordedBy, "rattle-demo --join --window");
  EXPECT_EQ(b.replay->config.opponentTeams, 0) << "the person played red, the peer blue";
  ASSERT_EQ(a.replay->ticks.size(), 100u);
  ASSERT_EQ(b.replay->ticks.size(), 100u);
  size_t redMoves = 0;
  for (size_t t = 0; t < a.replay->ticks.size(); ++t) {
    const rts::replay::TickRecord &x = a.replay->ticks[t], &y = b.replay->ticks[t];
    EXPECT_EQ(x.stateHash, y.stateHash) << "tick " << x.tick;
    ASSERT_EQ(x.commands.size(), y.commands.size()) << "tick " << x.tick;
    for (size_t i = 0; i < x.commands.size(); ++i) {
      expectSameCommand(x.commands[i], y.commands[i]);
      if (x.commands[i].team == 1) {
        EXPECT_EQ(x.commands[i].type, rts::CommandType::Move);
        // Red's units (ids alternate between the teams: red's are odd), and nobody else's.
        EXPECT_FALSE(x.commands[i].units.empty());
        EXPECT_LE(x.commands[i].units.size(), 4u);
        for (uint32_t id : x.commands[i].units) EXPECT_EQ(id % 2, 1u) << id;
        ++redMoves;
      }
    }
  }
  // The two right-clicks, each applied the input delay after its frame.
  EXPECT_EQ(redMoves, 2u);
}

TEST(NetWindow, APersonWhoQuitsLeavesAndTheHostEndsAtOnceWithStatus5) {
  if (!haveXvfb()) FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  const std::string joinReplay = scratch("join.replay");
  const std::string script = writeScript("input.txt", "40 key q\n");
  // A long timeout: the host must learn of the end from the window's Bye, not from its silence.
  HostProcess host(kGame + " --ticks 120 --no-render --quiet --peer-timeout 60");
  ASSERT_GT(host.port(), 0) << host.finish().output;
  const Outcome window = run(kWindowedRun, "--join 127.0.0.1:" + std::to_string(host.port()) + " " + kGame +
                                            " --ticks 120 --peer-timeout 60 --input " + script + " --record " +
                                            joinReplay);
  const auto windowEnded = std::chrono::steady_clock::now();
  const Outcome hosted = host.finish();
  const double hostLater = std::chrono::duration<double>(std::chrono::steady_clock::now() - windowEnded).count();
  EXPECT_EQ(window.status, 0) << window.output;
  EXPECT_EQ(hosted.status, 5) << hosted.output;
  EXPECT_LT(hostLater, 10.0) << hosted.output;
  EXPECT_TRUE(has(window, "Network game left at tick ")) << window.output;
  EXPECT_TRUE(has(window, ": you quit")) << window.output;
  EXPECT_TRUE(has(window, "rattle-demo: leaving the game: the player quit at tick ")) << window.output;
  EXPECT_EQ(finalLine(window.output), "none");
  EXPECT_TRUE(has(hosted, "rattle-demo: the peer left (the player quit at tick ")) << hosted.output;
  EXPECT_EQ(finalLine(hosted.output), "none");

  // The window's replay holds the ticks it played, and verifies.
  const size_t at = window.output.find("Network game left at tick ");
  ASSERT_NE(at, std::string::npos);
  const long ticks = std::atol(window.output.c_str() + at + std::strlen("Network game left at tick "));
  EXPECT_GT(ticks, 30);
  EXPECT_LT(ticks, 120);
  const Outcome verified = run(RATTLE_REPLAY_BINARY, "verify " + joinReplay);
  EXPECT_EQ(verified.status, 0) << verified.output;
  EXPECT_TRUE(has(verified, "all " + std::to_string(ticks) + " ticks match")) << verified.output;
}

// The window stays responsive while it waits: closed (here by SIGTERM, which SDL turns into a quit
// request) while its host waits for a player to join, it leaves with status 0, saying so, and its last
// picture (with the banner naming the wait) is saved.
TEST(NetWindow, AWindowClosedWhileItWaitsForAPlayerLeavesWithStatus0) {
  if (!haveXvfb()) FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  const std::string shot = scratch("shot.png");
  std::remove(shot.c_str());
  const Outcome window =
      run("xvfb-run -a -s '-screen 0 800x600x24' timeout --preserve-status -s TERM 4 " RATTLE_DEMO_BINARY,
          "--window --size 320x180 --host 0 " + kGame + " --screenshot " + shot);
  EXPECT_EQ(window.status, 0) << window.output;
  EXPECT_TRUE(has(window, "rattle-demo: hosting on UDP port ")) << window.output;
  EXPECT_TRUE(has(window, "Network game left at tick 0: you quit while waiting for the other player to connect.\n"))
      << window.output;
  // A PNG of the window's size: the signature, then IHDR's width and height (big-endian).
  const std::string png = readFile(shot);
  ASSERT_GE(png.size(), 24u) << shot;
  EXPECT_EQ(png.substr(1, 3), "PNG");
  auto at = [&](size_t i) { return uint32_t(uint8_t(png[i])) << 24 | uint32_t(uint8_t(png[i + 1])) << 16 |
                                   uint32_t(uint8_t(png[i + 2])) << 8 | uint32_t(uint8_t(png[i + 3])); };
  EXPECT_EQ(at(16), 320u);
  EXPECT_EQ(at(20), 180u);
}

// A host in a window with nobody at it (no script: it plays at 30 ticks a second, by the clock), a
// headless joiner, and a spectator in a window: the spectator comes in under way, plays the game so far
// faster than the clock to catch up, follows it, and ends with the players' final hash.
TEST(NetWindow, AHostAndASpectatorInWindows) {
  if (!haveXvfb()) FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  const std::string game = kGame + " --ticks 240";
  HostProcess host(game, kWindowed);
  ASSERT_GT(host.port(), 0) << host.finish().output;
  const std::string at = "127.0.0.1:" + std::to_string(host.port());
  Background joiner("--join " + at + " " + game + " --no-render --quiet", scratch("join.log"));
  ASSERT_TRUE(host.readUntil("playing blue (team 0) against red (team 1)")) << host.finish().output;
  const Outcome watcher = run(kWindowedRun, "--watch " + at + " " + game);
  const Outcome joined = joiner.finish();
  const Outcome hosted = host.finish();
  ASSERT_EQ(hosted.status, 0) << hosted.output;
  ASSERT_EQ(joined.status, 0) << joined.output;
  ASSERT_EQ(watcher.status, 0) << watcher.output;
  const std::string line = finalLine(hosted.output);
  EXPECT_EQ(line.rfind("Network game over after 240 ticks: final state hash ", 0), 0u) << hosted.output;
  EXPECT_EQ(finalLine(joined.output), line);
  EXPECT_EQ(finalLine(watcher.output),
            "Network game over after 240 ticks: final state hash " + hashIn(line) + ", the same as the host's.");
  const size_t joinedAt = watcher.output.find("joined at tick ");
  ASSERT_NE(joinedAt, std::string::npos) << watcher.output;
  EXPECT_GT(std::atol(watcher.output.c_str() + joinedAt + std::strlen("joined at tick ")), 0) << watcher.output;
  EXPECT_TRUE(has(hosted, "To the spectator (1 served): ")) << hosted.output;
}

}  // namespace
