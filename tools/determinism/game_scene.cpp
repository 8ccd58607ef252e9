#include "game_scene.h"

namespace rattle_trace {

namespace {

rts::GameConfig configOf(rattle::StepMode mode, int unitsPerTeam) {
  rts::GameConfig config;
  config.unitsPerTeam = unitsPerTeam;
  config.stepMode = mode;
  return config;
}

}  // namespace

GameScene::GameScene(const rts::Map& map, rattle::StepMode mode, int unitsPerTeam, uint64_t seed)
    : game_(map, configOf(mode, unitsPerTeam)), opponent_(seed), loop_(game_) {
  loop_.add(opponent_);
}

uint64_t GameScene::tick() {
  loop_.tick();
  return game_.stateHash();
}

}  // namespace rattle_trace
