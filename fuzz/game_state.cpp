// libFuzzer target: Game::restoreState on states changed in place, as a spectator gets them from a host
// (net/README.md, "Spectators"). It starts from a real state (the small map's game after 40 ticks, one
// per step mode, chosen by the first byte), applies the input's changes (triples: offset low, offset
// high, a byte to xor in; an offset past the end cuts the state there), and restores it into a game of
// the same map and config. A state taken must tick and save again; one refused must throw GameError and
// leave the game as it was. make test runs its seeds and kept findings through rattle-game-state-inputs
// (fuzz/world_api_inputs.cpp), in an ordinary build.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/map_loader.h"

namespace {

// As fuzz_support.h's RATTLE_FUZZ_CHECK, which needs the sanitizer's headers; this target also runs
// in an ordinary build.
void check(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "\nrattle fuzz check failed: %s\n", what);
  std::abort();
}

rts::GameConfig configFor(rattle::StepMode mode) {
  rts::GameConfig c;
  c.unitsPerTeam = 3;
  c.stepMode = mode;
  return c;
}

const rts::Map& smallMap() {
  static const rts::Map map = rts::loadMap(std::string(RATTLE_SOURCE_DIR) + "/assets/maps/small.json");
  return map;
}

std::string stateAfter40Ticks(rattle::StepMode mode) {
  rts::Game g(smallMap(), configFor(mode));
  rts::ScriptedOpponent opponent(5);
  rts::TickLoop loop(g);
  loop.add(opponent);
  for (int t = 0; t < 40; ++t) loop.tick();
  return g.saveState();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const rattle::StepMode modes[3] = {rattle::StepMode::Hybrid, rattle::StepMode::Predictive,
                                            rattle::StepMode::Discrete};
  static const std::string states[3] = {stateAfter40Ticks(modes[0]), stateAfter40Ticks(modes[1]),
                                        stateAfter40Ticks(modes[2])};
  if (size < 1) return 0;
  std::string bytes = states[data[0] % 3];
  for (size_t i = 1; i + 2 < size; i += 3) {
    const size_t at = size_t{data[i]} | size_t{data[i + 1]} << 8;
    if (at >= bytes.size()) {
      bytes.resize(bytes.size() - std::min<size_t>(bytes.size(), 1 + data[i + 2] % 64));
    } else {
      bytes[at] = char(uint8_t(bytes[at]) ^ data[i + 2]);
    }
  }
  rts::Game game(smallMap(), configFor(modes[data[0] % 3]));
  const std::string before = game.saveState();
  try {
    game.restoreState(bytes);
  } catch (const rts::GameError&) {
    check(game.saveState() == before, "a refused state changed the game");
    return 0;
  }
  for (int t = 0; t < 3; ++t) game.tick();
  const std::string again = game.saveState();
  rts::Game other(smallMap(), configFor(modes[data[0] % 3]));
  other.restoreState(again);
  check(other.saveState() == again, "a game's state does not restore to itself");
  return 0;
}
