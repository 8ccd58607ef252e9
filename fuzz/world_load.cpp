// libFuzzer target: World::load on saves changed in place. A save is checksummed, so random bytes stop at
// the checksum; this target starts from a real save instead (one of three small worlds, one per mode,
// chosen by the first byte), applies the input's changes to it (pairs of an offset and a byte to xor in),
// puts the checksum right, and loads. Whatever loads must step without a crash or a sanitizer report,
// save and load again to the same bytes; whatever does not load must throw rattle::Error. The save's
// event budget (WorldDef::maxEventsPerStep) is set to 20,000 first, as the world_api target's: a changed
// position can pile bodies into a corner, and a step of a million events under the sanitizers outlasts
// libFuzzer's 10 s limit (a timeout in CI's first run) without being a fault.
#include <rattle/rattle.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_support.h"

namespace {

std::vector<uint8_t> smallSave(rattle::StepMode mode) {
  using namespace rattle;
  WorldDef def;
  def.mode = mode;
  def.gravity = {0, -9.81};
  World w(def);
  const BodyId box = w.createBody({});
  w.createFixture(box, {.geometry = Polyline{{{0, 6}, {0, 0}, {4, 0}, {4, 6}}}, .restitution = 0.5});
  w.createFixture(box, {.geometry = Polygon{{{0, 0}, {4, 0}, {4, 1}}}, .sensor = true});
  for (int i = 0; i < 4; ++i) {
    const BodyId b = w.createBody({.type = BodyType::Dynamic, .position = {0.7 + 0.9 * i, 1.0 + 0.8 * i}});
    w.createFixture(b, {.geometry = Circle{{0, 0}, 0.4}, .restitution = 0.3});
  }
  const BodyId k = w.createBody({.type = BodyType::Kinematic, .position = {2, 5}, .velocity = {0.3, 0}});
  w.createFixture(k, {.geometry = Segment{{-0.5, 0}, {0.5, 0}}});
  w.destroyBody(w.createBody({}));
  for (int i = 0; i < 50; ++i) w.step(1.0 / 60);
  return w.save();
}

void reseal(std::vector<uint8_t>& bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (size_t i = 0; i + 8 < bytes.size(); ++i) {
    h ^= bytes[i];
    h *= 0x100000001b3ull;
  }
  for (int i = 0; i < 8; ++i) bytes[bytes.size() - 8 + i] = static_cast<uint8_t>(h >> (8 * i));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<uint8_t> saves[3] = {smallSave(rattle::StepMode::Hybrid),
                                                smallSave(rattle::StepMode::Predictive),
                                                smallSave(rattle::StepMode::Discrete)};
  if (size < 1) return 0;
  std::vector<uint8_t> bytes = saves[data[0] % 3];
  // The rest: (offset low, offset high, xor) triples; an offset past the end cuts the save there.
  for (size_t i = 1; i + 2 < size; i += 3) {
    const size_t at = (size_t{data[i]} | size_t{data[i + 1]} << 8);
    if (at + 8 >= bytes.size()) {
      bytes.resize(std::max<size_t>(9, bytes.size() - 1 - data[i + 2] % 16));
    } else {
      bytes[at] ^= data[i + 2];
    }
  }
  // WorldDef::maxEventsPerStep, after "RTLW", the version, the mode, gravity, restingSpeed and
  // collapseTime (World::save's order, api/world_save.cpp).
  constexpr size_t kBudgetAt = 4 + 4 + 1 + 16 + 8 + 8;
  constexpr uint32_t kEventBudget = 20000;
  if (bytes.size() >= kBudgetAt + 4 + 8) {
    for (size_t i = 0; i < 4; ++i) bytes[kBudgetAt + i] = uint8_t(kEventBudget >> (8 * i));
  }
  reseal(bytes);
  try {
    rattle::World w = rattle::World::load(bytes);
    for (int i = 0; i < 3; ++i) w.step(1.0 / 60);
    const std::vector<uint8_t> again = w.save();
    RATTLE_FUZZ_CHECK(rattle::World::load(again).save() == again, "a loaded world's save does not load to itself");
  } catch (const rattle::Error&) {
  }
  return 0;
}
