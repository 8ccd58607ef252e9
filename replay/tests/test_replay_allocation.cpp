// The reader's memory bound: every operator new in this binary is counted, and reading any replay,
// well-formed or hostile, must never hold more than kBytesPerByte times the file's size (plus a
// constant) at once.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "format/byte_writer.h"
#include "replay_test_support.h"

namespace {

std::atomic<size_t> gLive{0}, gPeak{0};
std::atomic<bool> gCounting{false};

constexpr size_t kHeader = 16;  // keeps what follows aligned for every fundamental type

}  // namespace

void* operator new(size_t size) {
  void* p = std::malloc(size + kHeader);
  if (!p) throw std::bad_alloc();
  *static_cast<size_t*>(p) = size;
  if (gCounting.load(std::memory_order_relaxed)) {
    const size_t live = gLive.fetch_add(size) + size;
    size_t peak = gPeak.load();
    while (live > peak && !gPeak.compare_exchange_weak(peak, live)) {
    }
  }
  return static_cast<char*>(p) + kHeader;
}

void operator delete(void* p) noexcept {
  if (!p) return;
  void* base = static_cast<char*>(p) - kHeader;
  const size_t size = *static_cast<size_t*>(base);
  if (gCounting.load(std::memory_order_relaxed)) gLive.fetch_sub(std::min(size, gLive.load()));
  std::free(base);
}

void operator delete(void* p, size_t) noexcept { operator delete(p); }

// The nothrow forms too (std::stable_sort's temporary buffer uses them and frees with the plain delete):
// under AddressSanitizer they would otherwise stay the sanitizer's, without the size header.
void* operator new(size_t size, const std::nothrow_t&) noexcept {
  try {
    return operator new(size);
  } catch (...) {
    return nullptr;
  }
}

void operator delete(void* p, const std::nothrow_t&) noexcept { operator delete(p); }

namespace {

using namespace rts::replay;
using namespace replay_test;

// What the reader promises (replay_reader.h): about 32 bytes per byte of file, plus a constant.
constexpr size_t kBytesPerByte = 32;
constexpr size_t kConstant = 64 << 10;

// The largest amount of memory held at once while reading `bytes`.
size_t peakWhileReading(const std::string& bytes) {
  gLive = 0;
  gPeak = 0;
  gCounting = true;
  {
    ReadResult r = readReplay(bytes);
    (void)r;
  }
  gCounting = false;
  return gPeak.load();
}

void expectBounded(const std::string& bytes, const std::string& what) {
  const size_t peak = peakWhileReading(bytes);
  std::printf("%s: %zu bytes, %zu held at most (%.1f per byte)\n", what.c_str(), bytes.size(), peak, double(peak) / double(bytes.size()));
  EXPECT_LE(peak, kBytesPerByte * bytes.size() + kConstant) << what << ": " << bytes.size() << " bytes held " << peak << " at once";
}

TEST(ReplayAllocation, ARealReplayStaysWithinTheBound) {
  const std::string bytes = smallReplay(60, 5);
  const size_t peak = peakWhileReading(bytes);
  EXPECT_LE(peak, kBytesPerByte * bytes.size() + kConstant);
  std::printf("small replay: %zu bytes, %zu held at most (%.1f per byte)\n", bytes.size(), peak, double(peak) / double(bytes.size()));
  for (const char* asset : {"arena.replay", "doorway-rush.replay", "projectile-storm.replay"}) {
    const std::string a = readFile(sourcePath(std::string("assets/replays/") + asset));
    const size_t p = peakWhileReading(a);
    EXPECT_LE(p, kBytesPerByte * a.size() + kConstant) << asset;
    std::printf("%s: %zu bytes, %zu held at most (%.1f per byte)\n", asset, a.size(), p, double(p) / double(a.size()));
  }
}

TEST(ReplayAllocation, TruncatedReplaysStayWithinTheBound) {
  const std::string bytes = smallReplay(30, 5);
  for (size_t n = 0; n < bytes.size(); n += 7) expectBounded(bytes.substr(0, n), "cut at " + std::to_string(n));
}

// The cheapest bytes per object the format allows, repeated: the worst case for the bound.
TEST(ReplayAllocation, TheDensestHostileFilesStayWithinTheBound) {
  const std::vector<Chunk> chunks = chunksOf(smallReplay(5, 5));
  const size_t tick = firstChunk(chunks, "TICK");
  // One tick of 100000 empty stop commands (3 bytes each), then garbage.
  ByteWriter w;
  w.varint(1);
  w.u64(0);
  w.u64(0);
  w.varint(100'000);
  for (int i = 0; i < 100'000; ++i) {
    w.u8(2);
    w.u8(0);
    w.varint(0);
  }
  std::vector<Chunk> c = chunks;
  c[tick].payload = w.data();
  expectBounded(assemble(c), "100000 stop commands");
  // 50000 ticks of nothing but the smallest TICK chunks (no keyframes due: every 10^8 ticks).
  c = std::vector<Chunk>(chunks.begin(), chunks.begin() + long(tick));
  ByteWriter conf;
  conf.u64(1);
  conf.varint(4);
  conf.u8(0);
  conf.u8(1);
  conf.u8(3);
  conf.varint(100'000'000);
  conf.varint(8);
  conf.varint(1);
  conf.varint(1);
  conf.varint(1);
  conf.str("x");
  c[firstChunk(c, "CONF")].payload = conf.data();
  for (uint32_t t = 1; t <= 50'000; ++t) {
    ByteWriter p;
    p.varint(t);
    p.u64(0);
    p.u64(0);
    p.varint(0);
    p.u16(0);
    for (int u = 0; u < 8; ++u) p.u16(0);
    p.varint(0);
    p.u16(0);
    c.push_back({"TICK", p.data()});
  }
  expectBounded(assemble(c), "50000 empty ticks");
  // A keyframe of dead units only (3 bytes each): the smallest keyframe entries.
  c = std::vector<Chunk>(chunks.begin(), chunks.begin() + long(tick));
  ByteWriter conf2;
  conf2.u64(1);
  conf2.varint(200'000);
  conf2.u8(0);
  conf2.u8(1);
  conf2.u8(3);
  conf2.varint(5);
  conf2.varint(400'000);
  conf2.varint(1);
  conf2.varint(1);
  conf2.varint(1);
  conf2.str("x");
  c[firstChunk(c, "CONF")].payload = conf2.data();
  ByteWriter key;
  key.varint(0);
  for (int i = 0; i < 6; ++i) key.zigzag(0);
  key.varint(0);
  key.varint(0);
  key.u8(0);
  for (int u = 0; u < 400'000; ++u) {
    key.u8(0);
    key.zigzag(0);
    key.zigzag(0);
  }
  key.varint(0);
  c[firstChunk(c, "KEYF")].payload = key.data();
  expectBounded(assemble(c), "a keyframe of 400000 dead units");
}

}  // namespace
