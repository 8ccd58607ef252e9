// Fuzz target: the demo's map reader (rts::parseMap) on arbitrary bytes.
//
// Every input must end in one of two ways: a Map that keeps the promises map.h makes (both teams can
// spawn, every coordinate finite and inside +-1e6 pixels, every geometry valid for the engine), or a
// MapError with a short message that starts with the file's name. Anything else is a finding: another
// exception (uncaught, so libFuzzer reports it), a sanitizer report, a hang (-timeout), or a peak heap
// beyond kHeapPerByte times the input's size (plus a fixed allowance for small inputs).
#include <rattle/geometry.h>

#include <cmath>
#include <string>
#include <string_view>

#include "fuzz_support.h"
#include "map/map_loader.h"

namespace {

constexpr size_t kHeapPerByte = 32;
constexpr size_t kHeapAllowance = 64 << 10;
constexpr size_t kMaxMessageBytes = 2048;

bool finite(rattle::Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }

void checkMap(const rts::Map& map) {
  RATTLE_FUZZ_CHECK(map.width > 0 && map.height > 0 && std::isfinite(map.width) && std::isfinite(map.height), nullptr);
  bool team[2] = {false, false};
  for (const rts::MapSpawn& s : map.spawns) {
    RATTLE_FUZZ_CHECK(s.team == 0 || s.team == 1, nullptr);
    RATTLE_FUZZ_CHECK(finite(s.position), nullptr);
    team[s.team] = true;
  }
  RATTLE_FUZZ_CHECK(team[0] && team[1], "a map was accepted without a spawn point for each team");
  for (const rts::MapWall& w : map.walls) {
    RATTLE_FUZZ_CHECK(finite(w.origin), nullptr);
    RATTLE_FUZZ_CHECK(!rattle::validationError(w.shape), "an accepted wall's geometry fails the engine's validation");
  }
  for (const rts::MapDoorway& d : map.doorways) RATTLE_FUZZ_CHECK(finite(d.a) && finite(d.b), nullptr);
  for (const rts::MapRoom& r : map.rooms) RATTLE_FUZZ_CHECK(!rattle::validationError(rattle::Geometry{rattle::Polygon{r.polygon}}), nullptr);
  for (const rts::MapGate& g : map.gates) {
    RATTLE_FUZZ_CHECK(finite(g.origin) && finite(g.openOffset), nullptr);
    RATTLE_FUZZ_CHECK(std::isfinite(g.period) && g.speed > 0 && std::isfinite(g.speed), nullptr);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.json";
  rattle_fuzz::HeapMeter meter;
  try {
    const rts::Map map = rts::parseMap(text, source);
    checkMap(map);
  } catch (const rts::MapError& e) {
    const std::string_view message = e.what();
    RATTLE_FUZZ_CHECK(message.substr(0, source.size()) == source, "the message does not name the file first");
    RATTLE_FUZZ_CHECK(message.size() > source.size() + 2, "the message says nothing");
    RATTLE_FUZZ_CHECK(message.size() <= kMaxMessageBytes, "the message is unreasonably long");
  }
  const size_t peak = meter.stop();
  if (peak > kHeapPerByte * size + kHeapAllowance) {
    std::fprintf(stderr, "\npeak heap %zu bytes for a %zu-byte input (limit %zu per byte + %zu)\n", peak, size,
                 kHeapPerByte, kHeapAllowance);
    rattle_fuzz::failed("the map reader's heap outgrew its input", nullptr);
  }
  return 0;
}
