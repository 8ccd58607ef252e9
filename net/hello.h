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

/// A player's Hello for `game`, built from the map file `mapJson` (its bytes: the digest is theirs)
/// with `seed`. The game's steering must be the default one: the handshake does not compare it, so a
/// game with another would desync; throws std::invalid_argument then.
Hello playerHello(const Game& game, std::string_view mapJson, uint64_t seed, uint8_t team, uint16_t inputDelayTicks,
                  uint16_t hashIntervalTicks);

}  // namespace rts::net
