// Orders, as data. Everything that changes the game from outside (the scripted opponent, a person in
// the window, a replay file) arrives as a Command stamped with the tick it applies to, so a game is
// exactly its map, its seed and its command log. Game::apply checks every field: a command may come
// from an untrusted replay.
//
// To add a command: a new CommandType, its fields here, a case in Game::apply (game.cpp) and, if the
// window should issue it, a binding in app/window.cpp. Keep the numbering stable: replays store it.
#pragma once

#include <rattle/vec2.h>

#include <cstdint>
#include <vector>

namespace rts {

using rattle::Vec2;

enum class CommandType : uint8_t {
  Move = 1,        ///< `units` go to `target`
  Stop = 2,        ///< `units` drop their orders
  ToggleGate = 3,  ///< gate number `gate` starts opening if closed, closing if open
  /// No fields: the engine's world is saved and loaded again before the tick (rattle::World::load), so
  /// that a spectator starting from the game's state at this tick (Game::saveState) steps as the
  /// players do. A lockstep host issues it when a spectator joins (net/README.md, "Spectators").
  ReloadWorld = 4,
};

struct Command {
  uint32_t tick = 0;  ///< the tick before which it applies
  uint8_t team = 0;   ///< who issued it; orders to the other team's units are ignored
  CommandType type = CommandType::Move;
  std::vector<uint32_t> units;  ///< unit ids (Move, Stop), as Game::units() numbers them
  Vec2 target;                  ///< world units (Move)
  uint32_t gate = 0;            ///< index into the map's gates (ToggleGate)
};

/// Where commands come from. The headless loop asks the scripted opponent; the window adds a person's
/// clicks; a replay reader (issue 6) can hand back a recorded log.
class CommandSource {
 public:
  virtual ~CommandSource() = default;
  /// Appends the commands for `tick` to `out`. Called once per tick, before Game::tick.
  virtual void commandsFor(uint32_t tick, const class Game& game, std::vector<Command>& out) = 0;
};

}  // namespace rts
