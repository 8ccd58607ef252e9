// Hostile replays: cut short, bit-flipped, the wrong magic or version, huge counts, unknown commands,
// enormous strings, chunks out of order. Every one is a ReadError naming where and why; none crashes.
// (The memory bound is measured in test_replay_allocation.cpp.)
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <limits>

#include "format/byte_writer.h"
#include "replay_test_support.h"

namespace {

using namespace rts::replay;
using namespace replay_test;

// Expects an error whose description contains `what`, at an offset inside the file.
void expectError(const std::string& bytes, const std::string& what) {
  const ReadResult r = readReplay(bytes);
  ASSERT_FALSE(r.ok()) << "accepted; expected: " << what;
  EXPECT_NE(r.error.describe().find(what), std::string::npos) << r.error.describe();
  EXPECT_LE(r.error.offset, bytes.size());
}

TEST(ReplayHostile, EveryTruncationIsAnError) {
  const std::string bytes = smallReplay(40, 5);
  ASSERT_TRUE(readReplay(bytes).ok());
  for (size_t n = 0; n < bytes.size(); ++n) {
    const ReadResult r = readReplay(bytes.substr(0, n));
    ASSERT_FALSE(r.ok()) << "cut at " << n;
    ASSERT_FALSE(r.error.message.empty());
    ASSERT_LE(r.error.offset, n) << r.error.describe();
  }
  // The pointer + size entry point, with nothing at all.
  EXPECT_FALSE(readReplay(nullptr, 0).ok());
  EXPECT_FALSE(readReplay(reinterpret_cast<const uint8_t*>(bytes.data()), 0).ok());
}

TEST(ReplayHostile, AssetReplaysCutAnywhereAreErrors) {
  for (const auto& entry : std::filesystem::directory_iterator(sourcePath("assets/replays"))) {
    if (entry.path().extension() != ".replay") continue;
    const std::string bytes = readFile(entry.path().string());
    for (size_t n = 0; n < bytes.size(); n += 977) EXPECT_FALSE(readReplay(bytes.substr(0, n)).ok()) << entry.path() << " cut at " << n;
    EXPECT_FALSE(readReplay(bytes.substr(0, bytes.size() - 1)).ok());
  }
}

TEST(ReplayHostile, EverySingleBitFlipIsAnError) {
  const std::string bytes = smallReplay(20, 5);
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      std::string flipped = bytes;
      flipped[i] = char(flipped[i] ^ (1 << bit));
      const ReadResult r = readReplay(flipped);
      ASSERT_FALSE(r.ok()) << "byte " << i << " bit " << bit;
    }
  }
  // A flip inside a payload is caught by the chunk's CRC, and the message says so.
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  const ReadResult r = readReplay(flipped);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.describe().find("CRC-32 mismatch"), std::string::npos) << r.error.describe();
}

TEST(ReplayHostile, WrongMagicOrVersion) {
  const std::string bytes = smallReplay(5, 5);
  std::string other = bytes;
  other[0] = 'X';
  expectError(other, "byte 0: magic: not a rattle replay");
  expectError("PNG\r\n", "not a rattle replay");
  expectError(assemble(chunksOf(bytes), 2), "byte 8: format version: version 2; this build reads version 1 only");
  expectError(assemble(chunksOf(bytes), 0xFFFF), "version 65535");
}

TEST(ReplayHostile, ChunksOutOfOrderMissingOrUnknown) {
  const std::string bytes = smallReplay(10, 5);
  const std::vector<Chunk> chunks = chunksOf(bytes);
  std::vector<Chunk> c = chunks;
  std::swap(c[0], c[1]);
  expectError(assemble(c), "expected the BILD chunk");
  c = chunks;
  c.pop_back();
  expectError(assemble(c), "the file ends before the END! chunk");
  c = chunks;
  c[firstChunk(c, "TICK")].tag = "ZZZZ";
  expectError(assemble(c), "'ZZZZ': unknown chunk");
  c = chunks;
  c.erase(c.begin() + long(firstChunk(c, "TICK")));
  expectError(assemble(c), "ticks must count up from 1 without gaps");
  // A keyframe due at tick 5 that is missing.
  c = chunks;
  for (size_t i = 5; i < c.size(); ++i) {
    if (c[i].tag == "KEYF") {
      c.erase(c.begin() + long(i));
      break;
    }
  }
  expectError(assemble(c), "tick 5 has no keyframe");
  expectError(bytes + "x", "1 bytes after the END! chunk");
  // A chunk length beyond every limit.
  std::string huge = bytes.substr(0, 14) + std::string("\xF0\xFF\xFF\xFF", 4) + bytes.substr(18);
  expectError(huge, "at most 67108864");
}

TEST(ReplayHostile, HugeCountsAreRefusedBeforeAnythingIsAllocated) {
  const std::vector<Chunk> chunks = chunksOf(smallReplay(5, 5));
  const size_t tick = firstChunk(chunks, "TICK");
  auto tickWith = [&](const std::function<void(ByteWriter&)>& rest) {
    ByteWriter w;
    w.varint(1);
    w.u64(0);
    w.u64(0);
    rest(w);
    std::vector<Chunk> c = chunks;
    c[tick].payload = w.data();
    return assemble(c);
  };
  expectError(tickWith([](ByteWriter& w) { w.varint(0xFFFFFFFFull); }), "tick 1 command count: 4294967295 items cannot fit");
  expectError(tickWith([](ByteWriter& w) { w.varint(UINT64_MAX); }), "tick 1 command count: 18446744073709551615 is out of range");
  // A move naming every unit there is, and then some.
  expectError(tickWith([](ByteWriter& w) {
                w.varint(1);
                w.u8(1);
                w.u8(0);
                w.varint(1'000'000);
              }),
              "tick 1 command 0 unit count: 1000000 is out of range");
  // Shots in the digests.
  expectError(tickWith([](ByteWriter& w) {
                w.varint(0);
                w.u16(0);
                for (int u = 0; u < 8; ++u) w.u16(0);
                w.varint(1u << 30);
              }),
              "shot count: 1073741824 items cannot fit");
  // A game of 200000 units a team whose tick holds no digests for them.
  std::vector<Chunk> c = chunks;
  ByteWriter conf;
  conf.u64(1);
  conf.varint(200'000);
  conf.u8(0);
  conf.u8(1);
  conf.u8(3);
  conf.varint(5);
  conf.varint(400'000);
  conf.varint(1);
  conf.varint(1);
  conf.varint(1);
  conf.str("x");
  c[firstChunk(c, "CONF")].payload = conf.data();
  expectError(assemble(c), "400000 units cannot fit in the bytes left");
  // Counts beyond the limits themselves.
  ByteWriter conf2;
  conf2.u64(1);
  conf2.varint(1'000'000'000);
  c[firstChunk(c, "CONF")].payload = conf2.data();
  expectError(assemble(c), "CONF unitsPerTeam: 1000000000 is out of range (1 to 200000)");
}

TEST(ReplayHostile, UnknownCommandTypesAndBadFields) {
  const std::vector<Chunk> chunks = chunksOf(smallReplay(5, 5));
  const size_t tick = firstChunk(chunks, "TICK");
  auto oneCommand = [&](const std::function<void(ByteWriter&)>& command) {
    ByteWriter w;
    w.varint(1);
    w.u64(0);
    w.u64(0);
    w.varint(1);
    command(w);
    std::vector<Chunk> c = chunks;
    c[tick].payload = w.data();
    return assemble(c);
  };
  expectError(oneCommand([](ByteWriter& w) {
                w.u8(9);
                w.u8(0);
                w.u8(0);
              }),
              "tick 1 command 0 type: unknown command type 9 (1 move, 2 stop, 3 toggle gate, 4 reload world)");
  expectError(oneCommand([](ByteWriter& w) {
                w.u8(1);
                w.u8(7);
                w.varint(0);
              }),
              "tick 1 command 0 team: 7: expected 0 or 1");
  expectError(oneCommand([](ByteWriter& w) {
                w.u8(2);
                w.u8(0);
                w.varint(1);
                w.varint(8);
              }),
              "tick 1 command 0 unit 0: 8 is out of range (0 to 7)");
  expectError(oneCommand([](ByteWriter& w) {
                w.u8(1);
                w.u8(0);
                w.varint(1);
                w.varint(0);
                w.f64(std::numeric_limits<double>::quiet_NaN());
                w.f64(1);
              }),
              "tick 1 command 0 target.x: not a finite number");
  expectError(oneCommand([](ByteWriter& w) {
                w.u8(3);
                w.u8(0);
                w.varint(5);
              }),
              "tick 1 command 0 gate: 5 is out of range (0 to 0)");
  // An eleven-byte varint.
  expectError(oneCommand([](ByteWriter& w) {
                w.u8(3);
                w.u8(0);
                w.bytes(std::string(10, '\xFF') + "\x01");
              }),
              "varint longer than");
}

TEST(ReplayHostile, EnormousStringsAreRefused) {
  const std::vector<Chunk> chunks = chunksOf(smallReplay(5, 5));
  std::vector<Chunk> c = chunks;
  ByteWriter build;
  build.varint(1);
  build.varint(uint64_t(1) << 62);  // a key "of 2^62 bytes"
  c[0].payload = build.data();
  expectError(assemble(c), "BILD fact 0 key: string of 4611686018427387904 bytes; at most 64 allowed");
  ByteWriter build2;
  build2.varint(1);
  build2.str("compiler");
  build2.str(std::string(5000, 'g'));
  c[0].payload = build2.data();
  expectError(assemble(c), "value: string of 5000 bytes; at most 1024 allowed");
  c = chunks;
  ByteWriter map;
  map.varint(1'000'000'000'000ull);
  c[firstChunk(c, "MAPJ")].payload = map.data();
  expectError(assemble(c), "MAPJ name: string of 1000000000000 bytes; at most 256 allowed");
  // A map whose bytes were changed after its hash was taken.
  c = chunks;
  std::string& m = c[firstChunk(c, "MAPJ")].payload;
  m[m.size() - 3] ^= 1;
  expectError(assemble(c), "MAPJ hash: the embedded map's FNV-1a hash does not match");
}

TEST(ReplayHostile, FilesThatDoNotExistOrAreNotFiles) {
  ReadResult r = readReplayFile("/nonexistent/x.replay");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error.field, "file");
  EXPECT_NE(r.error.message.find("cannot open"), std::string::npos);
  r = readReplayFile(testing::TempDir());
  EXPECT_FALSE(r.ok());
}

}  // namespace
