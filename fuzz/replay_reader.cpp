// Fuzz target: the replay reader (rts::replay::readReplay) on arbitrary bytes.
//
// Each input is read twice: as it is, and with every chunk's CRC-32 made right wherever the chunk framing
// can be followed, so that mutations get past the checksums into the payload parsers. Every read must end
// in one of two ways:
//  - a ReadError at an offset inside the input, with a short message;
//  - a Replay that survives a round trip: written again (encodeReplay), it reads back, and writes the
//    same bytes a second time.
// Anything else is a finding: an exception or abort, a sanitizer report, a hang (-timeout), or a peak
// heap beyond kHeapPerByte times the input's size plus a fixed allowance (replay_reader.h promises about
// 32 bytes per byte).
#include <cstdio>
#include <cstring>
#include <string>

#include "format/checksum.h"
#include "format/replay_reader.h"
#include "format/replay_writer.h"
#include "fuzz_support.h"

namespace {

constexpr size_t kHeapPerByte = 32;
constexpr size_t kHeapAllowance = 64 << 10;
constexpr size_t kMaxMessageBytes = 2048;

uint32_t readU32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<uint8_t>(s[at + static_cast<size_t>(k)]);
  return v;
}

void writeU32(std::string& s, size_t at, uint32_t v) {
  for (int k = 0; k < 4; ++k) s[at + static_cast<size_t>(k)] = static_cast<char>((v >> (8 * k)) & 0xFF);
}

// The bytes with each chunk's CRC recomputed (FORMAT.md: magic 8, version 2, then chunks of tag 4,
// length u32, payload, crc u32 over tag, length and payload), as far as the lengths stay inside.
std::string withChecksumsFixed(std::string s) {
  size_t pos = 10;
  while (pos + 8 <= s.size()) {
    const size_t length = readU32(s, pos + 4);
    if (length > s.size() - pos - 8 || s.size() - pos - 8 - length < 4) break;
    writeU32(s, pos + 8 + length, rts::replay::crc32(s.data() + pos, 8 + length));
    pos += 8 + length + 4;
  }
  return s;
}

void check(const uint8_t* data, size_t size) {
  rattle_fuzz::HeapMeter meter;
  const rts::replay::ReadResult r = rts::replay::readReplay(data, size);
  const size_t peak = meter.stop();
  if (peak > kHeapPerByte * size + kHeapAllowance) {
    std::fprintf(stderr, "\npeak heap %zu bytes for a %zu-byte input (limit %zu per byte + %zu)\n", peak, size,
                 kHeapPerByte, kHeapAllowance);
    rattle_fuzz::failed("the replay reader's heap outgrew its input", nullptr);
  }
  if (!r.ok()) {
    RATTLE_FUZZ_CHECK(r.error.offset <= size, "the error's offset is outside the input");
    const std::string text = r.error.describe();
    RATTLE_FUZZ_CHECK(!r.error.message.empty(), "the error says nothing");
    RATTLE_FUZZ_CHECK(text.size() <= kMaxMessageBytes, "the error is unreasonably long");
    return;
  }
  const std::string once = rts::replay::encodeReplay(*r.replay);
  const rts::replay::ReadResult again = rts::replay::readReplay(once);
  if (!again.ok()) {
    std::fprintf(stderr, "\nre-reading the written replay: %s\n", again.error.describe().c_str());
    rattle_fuzz::failed("a replay the reader accepted, written again, does not read back", nullptr);
  }
  RATTLE_FUZZ_CHECK(rts::replay::encodeReplay(*again.replay) == once, "writing the replay again gives other bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check(data, size);
  if (size >= 10) {
    const std::string fixed = withChecksumsFixed(std::string(reinterpret_cast<const char*>(data), size));
    check(reinterpret_cast<const uint8_t*>(fixed.data()), fixed.size());
  }
  return 0;
}
