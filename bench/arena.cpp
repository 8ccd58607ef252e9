// rattle-bench: playing the arena scene (see arena.h).
#include "arena.h"

#include <filesystem>

#include "map/map_loader.h"

namespace rattle_bench {

std::string defaultArenaMap() {
  const std::string built = RATTLE_BENCH_ARENA_MAP;
  return std::filesystem::exists(built) ? built : "assets/maps/arena.json";
}

namespace {

rts::GameConfig config(const ArenaParams& p) {
  rts::GameConfig c;
  c.unitsPerTeam = p.unitsPerTeam;
  c.stepMode = p.mode;
  return c;
}

}  // namespace

ArenaGame::ArenaGame(const ArenaParams& p)
    : game_(std::make_unique<rts::Game>(rts::loadMap(p.map.empty() ? defaultArenaMap() : p.map), config(p))),
      opponent_(p.seed),
      meter_(std::make_unique<ArenaMeter>(*game_)),
      loop_(*game_) {
  loop_.add(opponent_);
}

void ArenaGame::tick(bool measureOverlaps) {
  // The loop of rattle-demo's headless run (rts::TickLoop), so a seed gives the same game; the meter
  // reads the state between the commands and the tick.
  loop_.applyCommands();
  meter_->before(*game_);
  game_->tick();
  meter_->after(*game_, measureOverlaps);
}

}  // namespace rattle_bench
