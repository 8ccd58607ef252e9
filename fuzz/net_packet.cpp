// Fuzz target: the lockstep protocol's packet decoder (rts::net::decode, net/protocol.h) on arbitrary bytes.
//
// Each input is decoded three times: before the handshake (no game: commands may name no unit and no
// gate, a Snapshot holds nothing), in the largest game a replay allows (every unit id and gate a command
// may name), and in the small game of the Snapshot seed (3 units, 1 gate, 2 doorways, 2 rooms: a
// Snapshot decodes only in a game of its own sizes, and no state of the largest game fits a packet).
// Every decode must end in one of two ways:
//  - an error: one line, not empty, at most 2 KiB, starting with the message's name once the type byte
//    names one;
//  - a message that survives a round trip: encoded again, it decodes, and encodes to the same bytes a
//    second time.
// Anything else is a finding: an exception or abort, a sanitizer report, a hang (-timeout), or a peak
// heap beyond kHeapPerByte times the input's size plus a fixed allowance.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "format/limits.h"
#include "fuzz_support.h"
#include "net/protocol.h"

namespace {

constexpr size_t kHeapPerByte = 32;
constexpr size_t kHeapAllowance = 64 << 10;
constexpr size_t kMaxMessageBytes = 2048;

const char* const kNames[] = {"Hello", "Refuse", "Commands", "Hash", "Bye", "Snapshot", "Ticks"};

void checkError(const uint8_t* data, size_t size, const std::string& error) {
  RATTLE_FUZZ_CHECK(!error.empty(), "the error says nothing");
  RATTLE_FUZZ_CHECK(error.size() <= kMaxMessageBytes, "the error is unreasonably long");
  RATTLE_FUZZ_CHECK(error.find('\n') == std::string::npos, "the error is more than one line");
  if (size > 0 && data[0] >= 1 && data[0] <= 7) {
    const char* name = kNames[data[0] - 1];
    const size_t n = std::strlen(name);
    RATTLE_FUZZ_CHECK(error.compare(0, n, name) == 0 && error.size() > n && (error[n] == '.' || error[n] == ':'),
                      error.c_str());
  }
}

void check(const uint8_t* data, size_t size, const rts::net::DecodeContext& context) {
  rattle_fuzz::HeapMeter meter;
  const rts::net::Decoded d = rts::net::decode(data, size, context);
  const size_t peak = meter.stop();
  if (peak > kHeapPerByte * size + kHeapAllowance) {
    std::fprintf(stderr, "\npeak heap %zu bytes for a %zu-byte input (limit %zu per byte + %zu)\n", peak, size,
                 kHeapPerByte, kHeapAllowance);
    rattle_fuzz::failed("the packet decoder's heap outgrew its input", nullptr);
  }
  if (!d.ok()) {
    checkError(data, size, d.error);
    return;
  }
  // Whatever decodes, encode takes back (it refuses only what decode would refuse).
  const std::vector<uint8_t> once = rts::net::encode(*d.message);
  const rts::net::Decoded again = rts::net::decode(once.data(), once.size(), context);
  if (!again.ok()) {
    std::fprintf(stderr, "\ndecoding the encoded message again: %s\n", again.error.c_str());
    rattle_fuzz::failed("a message the decoder accepted, encoded again, does not decode", nullptr);
  }
  RATTLE_FUZZ_CHECK(rts::net::encode(*again.message) == once, "encoding the message again gives other bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check(data, size, rts::net::DecodeContext{});
  check(data, size,
        rts::net::DecodeContext{2 * rts::replay::kMaxUnitsPerTeam, rts::replay::kMaxGates, rts::replay::kMaxDoorways,
                                rts::replay::kMaxRooms});
  // net_test::snapshotGame() (net/tests/net_test_support.h): the seed snapshot's game.
  check(data, size, rts::net::DecodeContext{3, 1, 2, 2});
  return 0;
}
