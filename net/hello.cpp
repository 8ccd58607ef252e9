#include "net/hello.h"

#include <stdexcept>

#include "format/checksum.h"
#include "game/game.h"

namespace rts::net {

std::string engineVersion() { return std::string("rattle ") + RATTLE_NET_ENGINE_VERSION; }

Hello playerHello(const Game& game, std::string_view mapJson, uint64_t seed, uint8_t team, uint16_t inputDelayTicks,
                  uint16_t hashIntervalTicks, uint32_t ticks) {
  Hello h;
  h.engineVersion = engineVersion();
  h.mapDigest = replay::fnv1a64(mapJson);
  h.seed = seed;
  h.unitsPerTeam = uint32_t(game.config().unitsPerTeam);
  h.stepMode = game.config().stepMode;
  h.inputDelayTicks = inputDelayTicks;
  h.hashIntervalTicks = hashIntervalTicks;
  h.role = Role::Player;
  h.team = team;
  h.ticks = ticks;
  h.steering = game.config().steering;
  return h;
}

Hello spectatorHello(const Game& game, std::string_view mapJson, uint64_t seed, uint16_t inputDelayTicks,
                     uint16_t hashIntervalTicks, uint32_t ticks) {
  Hello h = playerHello(game, mapJson, seed, 0, inputDelayTicks, hashIntervalTicks, ticks);
  h.role = Role::Spectator;
  return h;
}

}  // namespace rts::net
