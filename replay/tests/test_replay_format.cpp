// The format: primitives, checksums, and a real replay read back and written out byte for byte.
#include <gtest/gtest.h>

#include "format/byte_reader.h"
#include "format/byte_writer.h"
#include "format/checksum.h"
#include "format/command_codec.h"
#include "format/snapshot_codec.h"
#include "replay_test_support.h"
#include "tool/command_script.h"

namespace {

using namespace rts::replay;
using replay_test::parsed;
using replay_test::smallReplay;

TEST(ReplayFormat, ChecksumsAreTheStandardOnes) {
  EXPECT_EQ(crc32("123456789", 9), 0xCBF43926u);  // the CRC-32 check value
  EXPECT_EQ(fnv1a64(""), 0xCBF29CE484222325ull);
  EXPECT_EQ(fnv1a64("a"), 0xAF63DC4C8601EC8Cull);
}

TEST(ReplayFormat, PrimitivesRoundTrip) {
  ByteWriter w;
  const uint64_t varints[] = {0, 1, 127, 128, 300, 0xFFFFFFFFull, UINT64_MAX};
  const int64_t zigzags[] = {0, -1, 1, -64, 64, INT64_MIN, INT64_MAX};
  for (uint64_t v : varints) w.varint(v);
  for (int64_t v : zigzags) w.zigzag(v);
  w.f64(-0.0);
  w.str("hello");
  ByteReader r(w.data(), 100);
  for (uint64_t v : varints) EXPECT_EQ(r.varint("v"), v);
  for (int64_t v : zigzags) EXPECT_EQ(r.zigzag("z", INT64_MIN, INT64_MAX), v);
  EXPECT_TRUE(std::signbit(r.f64("f")));
  EXPECT_EQ(r.str("s", 5), "hello");
  EXPECT_TRUE(r.atEnd());
  EXPECT_EQ(r.offset(), 100 + w.size());
}

TEST(ReplayFormat, ARealReplayReadsBackAndWritesOutByteForByte) {
  const std::string bytes = smallReplay(40, 5);
  const Replay r = parsed(bytes);
  EXPECT_EQ(r.version, 1);
  EXPECT_EQ(r.tickCount(), 40u);
  EXPECT_EQ(r.config.unitsPerTeam, 4u);
  EXPECT_EQ(r.config.unitCount, 8u);
  EXPECT_EQ(r.config.keyframeEvery, 5u);
  EXPECT_EQ(r.config.seed, 3u);
  EXPECT_EQ(r.mapName, "small.json");
  EXPECT_EQ(r.mapJson, replay_test::readFile(replay_test::sourcePath("assets/maps/small.json")));
  ASSERT_EQ(r.keyframes.size(), 9u);
  for (size_t k = 0; k < r.keyframes.size(); ++k) EXPECT_EQ(r.keyframes[k].tick, 5 * k);
  EXPECT_GT(r.commandCount(), 0u);
  for (const TickRecord& t : r.ticks) {
    EXPECT_EQ(t.digests.units.size(), 8u);
    for (const rts::Command& c : t.commands) EXPECT_EQ(c.tick, t.tick - 1);
  }
  // The keyframes' digests are the ones recorded for their ticks.
  for (const Keyframe& k : r.keyframes) {
    if (k.tick > 0) {
      EXPECT_EQ(digestsOf(k.state), r.ticks[k.tick - 1].digests) << "tick " << k.tick;
    }
  }
  EXPECT_EQ(encodeReplay(r), bytes) << "the streaming writer and encodeReplay disagree";
  bool hasBuildFacts = false;
  for (const BuildFact& f : r.build) hasBuildFacts |= f.key == "compiler" && !f.value.empty();
  EXPECT_TRUE(hasBuildFacts);
}

TEST(ReplayFormat, AnOffScheduleLastKeyframeIsAllowed) {
  const Replay r = parsed(smallReplay(12, 5));  // keyframes at 0, 5, 10 and the last tick, 12
  ASSERT_EQ(r.keyframes.size(), 4u);
  EXPECT_EQ(r.keyframes.back().tick, 12u);
}

TEST(ReplayFormat, SnapshotsRoundTrip) {
  const Replay r = parsed(smallReplay(30, 10));
  for (const Keyframe& k : r.keyframes) {
    ByteWriter w;
    encodeSnapshot(w, k.state);
    ByteReader in(w.data(), 0);
    EXPECT_EQ(decodeSnapshot(in, r.config, "test"), k.state);
    EXPECT_TRUE(in.atEnd());
  }
}

// ReloadWorld (a spectator's start: net/README.md) has no fields but a reserved 0, so that every command
// takes at least three bytes.
TEST(ReplayFormat, AReloadWorldCommandRoundTripsAndItsReservedByteIsZero) {
  rts::Command c;
  c.team = 1;
  c.type = rts::CommandType::ReloadWorld;
  ByteWriter w;
  encodeCommand(w, c);
  EXPECT_EQ(w.data(), std::string("\x04\x01\x00", 3));
  ReplayConfig config;
  config.unitCount = 8;
  ByteReader r(w.data(), 0);
  const rts::Command back = decodeCommand(r, config, 12, "command");
  EXPECT_EQ(back.type, rts::CommandType::ReloadWorld);
  EXPECT_EQ(back.team, 1);
  EXPECT_EQ(back.tick, 12u);
  EXPECT_TRUE(r.atEnd());
  const std::string reservedOne("\x04\x01\x01", 3);
  ByteReader bad(reservedOne, 0);
  try {
    decodeCommand(bad, config, 12, "command");
    ADD_FAILURE() << "a reserved byte of 1 was read";
  } catch (const FormatError& e) {
    EXPECT_EQ(e.field(), "command reserved");
  }
}

TEST(ReplayFormat, CommandScriptsNameTheLineOfAMistake) {
  EXPECT_EQ(
      CommandScript::parse("# nothing\n\n0 move blue 3 4\n5 stop red 0-3,7\n9 gate 1 0\n12 reload blue\n", "s").size(),
      4u);
  auto error = [](const std::string& text) {
    try {
      CommandScript::parse(text, "s.commands");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("0 move blue 3 4\nx move blue 1 1\n"), "s.commands:2: 'x': expected a tick number");
  EXPECT_EQ(error("0 jump blue\n"), "s.commands:1: 'jump': expected move, stop, gate or reload");
  EXPECT_EQ(error("0 move green 1 1\n"), "s.commands:1: 'green': expected a team (blue, red, 0 or 1)");
  EXPECT_EQ(error("0 move blue 1 nan\n"), "s.commands:1: move: '1 nan': expected two numbers");
  EXPECT_EQ(error("0 stop blue 5-2\n"), "s.commands:1: '5-2': an empty range");
  EXPECT_EQ(error("0 gate blue 0 extra\n"), "s.commands:1: 'extra': unexpected text at the end of the line");
  // A comment may follow a command on its line.
  EXPECT_EQ(CommandScript::parse("0 move blue 42 8 0-39   # to the doorway\n300 gate red 0#open\n", "s").size(), 2u);
  EXPECT_EQ(error("0 stop blue 1 2 # two words\n"), "s.commands:1: '2': unexpected text at the end of the line");
}

}  // namespace
