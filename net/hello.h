// The Hello a player sends, from the game it built: what both sides must agree on before they play.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "net/protocol.h"

namespace rts {
class Game;
}

namespace rts::net {

/// "rattle 0.1.0": the engine's version, as a replay's `engine` build fact says it.
std::string engineVersion();

/// A player's Hello for `game` of `ticks` ticks, built from the map file `mapJson` (its bytes: the
/// digest is theirs) with `seed`; the steering is the game's.
Hello playerHello(const Game& game, std::string_view mapJson, uint64_t seed, uint8_t team, uint16_t inputDelayTicks,
                  uint16_t hashIntervalTicks, uint32_t ticks);

/// A spectator's Hello: the same fields, role spectator, team 0.
Hello spectatorHello(const Game& game, std::string_view mapJson, uint64_t seed, uint16_t inputDelayTicks,
                     uint16_t hashIntervalTicks, uint32_t ticks);

}  // namespace rts::net
