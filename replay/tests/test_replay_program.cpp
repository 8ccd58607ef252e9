// rattle-replay and rattle-demo --record as programs: help, exit statuses, messages.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>

#include "format/checksum.h"
#include "replay_test_support.h"

namespace {

using namespace rts::replay;
using namespace replay_test;

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr
};

Outcome run(const std::string& binary, const std::string& arguments) {
  const std::string log = scratch("output.log");
  const std::string command = binary + " " + arguments + " > " + log + " 2>&1";
  Outcome r;
  const int raw = std::system(command.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.output = readFile(log);
  return r;
}

Outcome replayTool(const std::string& arguments) { return run(RATTLE_REPLAY_BINARY, arguments); }

bool has(const Outcome& o, const std::string& text) { return o.output.find(text) != std::string::npos; }

// Where the first byte is that a terminal could act on: a C0 control other than the newline, DEL, the
// lone byte 0x9b (CSI in an 8-bit terminal), a C1 control in UTF-8 (C2 80 to C2 9F) or the right-to-left
// override U+202E (E2 80 AE). npos when there is none.
size_t firstControlByte(const std::string& s) {
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if ((c < 0x20 && c != '\n') || c == 0x7f || c == 0x9b) return i;
    if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) <= 0x9f) return i;
    if (s.compare(i, 3, "\xe2\x80\xae") == 0) return i;
  }
  return std::string::npos;
}

TEST(ReplayProgram, HelpOnEverySubcommand) {
  Outcome o = replayTool("--help");
  EXPECT_EQ(o.status, 0);
  for (const char* sub : {"info", "verify", "render", "record"}) {
    EXPECT_TRUE(has(o, sub)) << sub;
    Outcome s = replayTool(std::string(sub) + " --help");
    EXPECT_EQ(s.status, 0) << sub;
    EXPECT_TRUE(has(s, std::string("usage: rattle-replay ") + sub)) << s.output;
    EXPECT_TRUE(has(s, "Exit status")) << sub;
  }
}

TEST(ReplayProgram, BadUsageIsStatus2) {
  Outcome o = replayTool("frobnicate");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(has(o, "unknown command 'frobnicate'")) << o.output;
  o = replayTool("verify");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(has(o, "expected a replay FILE")) << o.output;
  o = replayTool("render " + sourcePath("assets/replays/arena.replay"));
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(has(o, "--frames DIR is required")) << o.output;
  o = replayTool("render x --frames d --size 10by10");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(has(o, "--size 10by10")) << o.output;
  o = replayTool("record --map m --seed -1 --ticks 3 f");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(has(o, "--seed -1: expected a whole number")) << o.output;
}

TEST(ReplayProgram, InfoDescribesAnAsset) {
  Outcome o = replayTool("info --commands " + sourcePath("assets/replays/projectile-storm.replay"));
  EXPECT_EQ(o.status, 0) << o.output;
  for (const char* part : {"storm.json", "50 units per team", "ticks     300", "commands  20 (20 move", "compiler", "0 move blue 29.5 6 0,2,4"}) {
    EXPECT_TRUE(has(o, part)) << part << " in " << o.output;
  }
}

TEST(ReplayProgram, MalformedFilesAreStatus2WithTheOffsetAndField) {
  const std::string bytes = smallReplay(10, 5);
  const std::string cut = scratch("cut.replay");
  writeFile(cut, bytes.substr(0, bytes.size() / 2));
  for (const char* sub : {"info", "verify", "render --frames /tmp/never"}) {
    Outcome o = replayTool(std::string(sub) + " " + cut);
    EXPECT_EQ(o.status, 2) << sub << ": " << o.output;
    EXPECT_TRUE(has(o, "not a valid replay: byte ")) << o.output;
    EXPECT_TRUE(has(o, "truncated")) << o.output;
  }
  Outcome o = replayTool("verify /nonexistent.replay");
  EXPECT_EQ(o.status, 2);
  EXPECT_TRUE(has(o, "/nonexistent.replay: cannot open")) << o.output;
}

// A replay is untrusted: its strings (map name, recordedBy, build facts) must not carry escape sequences
// to the terminal of whoever runs info or verify on it.
TEST(ReplayProgram, StringsFromTheFileReachTheTerminalWithoutControlBytes) {
  // An OSC that sets the window title, a CSI that clears the screen, an 8-bit CSI alone and as UTF-8 (C2 9B),
  // a carriage return, a tab, DEL, a right-to-left override.
  const std::string evil = "\x1b]0;owned\x07\x1b[2J\x9b" "31m\xc2\x9b" "1m\r\t\x7f\xe2\x80\xae";
  Replay r = parsed(smallReplay(10, 5));
  r.mapName = "small.json" + evil;
  r.config.recordedBy = "rattle-demo" + evil;
  ASSERT_FALSE(r.build.empty());
  r.build[0].value += evil;  // differs from this build: verify lists it
  r.build.push_back({"evil" + evil, "value" + evil});
  const std::string file = scratch("evil.replay");
  writeFile(file, encodeReplay(r));

  Outcome o = replayTool("info " + file);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(firstControlByte(o.output), std::string::npos) << o.output;
  // The strings are shown, their control bytes replaced, not dropped.
  EXPECT_TRUE(has(o, "small.json?]0;owned??[2J?31m?1m????")) << o.output;
  EXPECT_TRUE(has(o, "recorded by rattle-demo?]0;owned?")) << o.output;
  EXPECT_TRUE(has(o, "evil?]0;owned?")) << o.output;

  o = replayTool("verify --quiet " + file);
  EXPECT_EQ(o.status, 0) << o.output;  // the game itself is untouched
  EXPECT_TRUE(has(o, "recorded by a different build")) << o.output;
  EXPECT_TRUE(has(o, "evil?]0;owned?")) << o.output;
  EXPECT_EQ(firstControlByte(o.output), std::string::npos) << o.output;

  // The map name also labels the errors of a bad embedded map.
  r.mapJson = "{\"type\": \"map\"}";
  r.mapHash = fnv1a64(r.mapJson);
  writeFile(file, encodeReplay(r));
  o = replayTool("verify --quiet " + file);
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_TRUE(has(o, "the replay's map (small.json?]0;owned?")) << o.output;
  EXPECT_EQ(firstControlByte(o.output), std::string::npos) << o.output;
}

TEST(ReplayProgram, ADirectoryIsNamedAsOne) {
  const std::string dir = scratch("dir");
  std::filesystem::create_directories(dir);
  for (const char* sub : {"info", "verify", "render --frames /tmp/never"}) {
    Outcome o = replayTool(std::string(sub) + " " + dir);
    EXPECT_EQ(o.status, 2) << sub << ": " << o.output;
    EXPECT_TRUE(has(o, dir + ": is a directory, not a replay file")) << o.output;
    EXPECT_FALSE(has(o, "bytes")) << o.output;
  }
  Outcome o = replayTool("record --map " + dir + " --seed 1 --ticks 3 " + scratch("never.replay"));
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, dir + ": is a directory, not a map file")) << o.output;
  EXPECT_FALSE(std::filesystem::exists(scratch("never.replay")));
  EXPECT_FALSE(std::filesystem::exists(scratch("never.replay.part")));
  // A directory read as a command script would be an empty one; as the output, the game would be played
  // to its end before the finished file could not be renamed onto it.
  const std::string map = " --map " + sourcePath("assets/maps/small.json") + " --seed 1 --ticks 3 --quiet ";
  o = replayTool("record --script " + dir + map + scratch("never.replay"));
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, dir + ": is a directory, not a command script")) << o.output;
  o = replayTool("record" + map + dir);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, dir + ": is a directory; the replay needs a file name")) << o.output;
  EXPECT_FALSE(has(o, "recorded")) << o.output;
  o = run(RATTLE_DEMO_BINARY, "--no-render --record " + dir + map);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, dir + ": is a directory; the replay needs a file name")) << o.output;
  EXPECT_FALSE(has(o, "Ran 3 ticks")) << o.output;
  EXPECT_FALSE(std::filesystem::exists(dir + ".part"));
}

TEST(ReplayProgram, VerifyPassesAnAssetAndFailsATamperedCopyNamingTheTick) {
  const std::string asset = sourcePath("assets/replays/doorway-rush.replay");
  Outcome o = replayTool("verify " + asset);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(has(o, "all 360 ticks match")) << o.output;

  Replay r = parsed(readFile(asset));
  // The red rush of tick 120 (record 121) sent elsewhere.
  ASSERT_FALSE(r.ticks[120].commands.empty());
  r.ticks[120].commands[0].target.y += 3;
  const std::string tampered = scratch("tampered.replay");
  writeFile(tampered, encodeReplay(r));
  o = replayTool("verify --quiet " + tampered);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, "diverges at tick 121 of 360 (ticks 1 to 120 match)")) << o.output;
  EXPECT_TRUE(has(o, "bodies that differ at tick 121")) << o.output;
  EXPECT_TRUE(has(o, "order.target.y: recorded")) << o.output;
}

TEST(ReplayProgram, VerifySaysNoTickMatchesWhenTheFirstDiffers) {
  Replay r = parsed(readFile(sourcePath("assets/replays/doorway-rush.replay")));
  r.ticks[0].stateHash ^= 1;
  const std::string tampered = scratch("first-tick.replay");
  writeFile(tampered, encodeReplay(r));
  Outcome o = replayTool("verify --quiet " + tampered);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, "diverges at tick 1 of 360 (no tick matches)")) << o.output;
}

// The reader refuses a gate the map lacks, so a recording must never hold one: the script is refused at
// that line, before anything is written. The README's example script, with its trailing comments, works.
TEST(ReplayProgram, RecordRefusesAScriptGateTheMapLacksAndTakesTheReadmeScript) {
  const std::string script = scratch("gate1.txt"), file = scratch("gate1.replay");
  std::filesystem::remove(file);  // the scratch directory outlives a run; the second part writes it
  writeFile(script, "# one gate on arena.json\n0 move blue 42 8\n0 gate blue 1\n");
  const std::string map = " --map " + sourcePath("assets/maps/arena.json") + " --seed 1 --ticks 3 --quiet ";
  Outcome o = replayTool("record --script " + script + map + file);
  EXPECT_EQ(o.status, 1) << o.output;
  EXPECT_TRUE(has(o, script + ":3: gate 1: the map's gates are 0 to 0")) << o.output;
  EXPECT_FALSE(std::filesystem::exists(file));
  EXPECT_FALSE(std::filesystem::exists(file + ".part"));

  const std::string readme = readFile(sourcePath("replay/README.md"));
  const size_t start = readme.find("# TICK move TEAM X Y");
  ASSERT_NE(start, std::string::npos);
  const std::string example = readme.substr(start, readme.find("```", start) - start);
  writeFile(script, example);
  o = replayTool("record --script " + script + " --map " + sourcePath("assets/maps/arena.json") +
                 " --seed 1 --ticks 301 --units 50 --opponent none --quiet " + file);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(has(o, "recorded 301 ticks, 3 commands")) << o.output;
  o = replayTool("render --quiet " + file + " --frames " + scratch("never") + " --to 302");
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_TRUE(has(o, "--to 302: the replay has 301 ticks")) << o.output;
}

TEST(ReplayProgram, RecordThenRenderThenVerify) {
  const std::string file = scratch("rec.replay");
  Outcome o = replayTool("record --quiet --map " + sourcePath("assets/maps/small.json") + " --seed 5 --ticks 40 --units 6 " + file);
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(has(o, "recorded 40 ticks")) << o.output;
  o = replayTool("verify " + file);
  EXPECT_EQ(o.status, 0) << o.output;
  const std::string frames = scratch("frames");
  o = replayTool("render --quiet " + file + " --frames " + frames + " --from 10 --to 30 --every 10 --size 160x96");
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(has(o, "3 frames in")) << o.output;
  for (const char* f : {"/frame_000010.png", "/frame_000020.png", "/frame_000030.png"}) {
    EXPECT_TRUE(std::filesystem::exists(frames + f)) << f;
  }
  EXPECT_FALSE(std::filesystem::exists(frames + "/frame_000000.png"));
}

TEST(ReplayProgram, TheDemoRecordsWhatItPlays) {
  const std::string file = scratch("demo.replay");
  Outcome plain = run(RATTLE_DEMO_BINARY, "--map " + sourcePath("assets/maps/small.json") + " --units 5 --ticks 60 --no-render --quiet --seed 4");
  Outcome recorded = run(RATTLE_DEMO_BINARY, "--map " + sourcePath("assets/maps/small.json") + " --units 5 --ticks 60 --no-render --quiet --seed 4 --record " + file);
  ASSERT_EQ(recorded.status, 0) << recorded.output;
  auto finalHash = [](const std::string& s) {
    const size_t at = s.find("Final state hash ");
    return at == std::string::npos ? std::string("none") : s.substr(at, 33);
  };
  EXPECT_EQ(finalHash(plain.output), finalHash(recorded.output)) << "recording changed the game";
  EXPECT_TRUE(has(recorded, "replay written to " + file)) << recorded.output;
  const Replay r = parsed(readFile(file));
  EXPECT_EQ(r.tickCount(), 60u);
  EXPECT_EQ(r.config.seed, 4u);
  EXPECT_EQ(r.config.recordedBy, "rattle-demo");
  Outcome o = replayTool("verify " + file);
  EXPECT_EQ(o.status, 0) << o.output;
  // --help mentions it.
  o = run(RATTLE_DEMO_BINARY, "--help");
  EXPECT_TRUE(has(o, "--record FILE")) << o.output;
}

TEST(ReplayProgram, TheWindowRecordsThePersonsOrders) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) {
    FAIL() << "xvfb-run is missing: scripts/install-deps.sh installs it (package xvfb)";
  }
  const std::string script = scratch("input.txt"), file = scratch("window.replay");
  writeFile(script,
            "5 drag 20 20 330 370\n"  // select the blue units in the west room (640x360 on a 40x24 map)
            "6 rclick 560 180\n"      // send them east
            "30 key g\n");            // work the gate
  Outcome o = run("xvfb-run -a -s '-screen 0 800x600x24' " RATTLE_DEMO_BINARY,
                  "--window --map " + sourcePath("assets/maps/small.json") + " --units 3 --size 640x360 --ticks 60 --input " + script +
                      " --record " + file);
  ASSERT_EQ(o.status, 0) << o.output;
  const Replay r = parsed(readFile(file));
  EXPECT_EQ(r.tickCount(), 60u);
  EXPECT_EQ(r.config.recordedBy, "rattle-demo --window");
  EXPECT_EQ(r.config.opponentTeams, 2) << "the opponent plays red only";
  int personMoves = 0, personGates = 0;
  for (const TickRecord& t : r.ticks) {
    for (const rts::Command& c : t.commands) {
      personMoves += c.team == 0 && c.type == rts::CommandType::Move;
      personGates += c.team == 0 && c.type == rts::CommandType::ToggleGate;
    }
  }
  EXPECT_EQ(personMoves, 1);
  EXPECT_EQ(personGates, 1);
  o = replayTool("verify " + file);
  EXPECT_EQ(o.status, 0) << o.output;
}

}  // namespace
