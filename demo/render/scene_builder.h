// Game -> Scene: what the player of `fogTeam` would be shown.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "game/game.h"
#include "render/scene.h"

namespace rts {

struct SceneOptions {
  int fogTeam = 0;               ///< whose view: 0 or 1; -1 shows everything (no fog)
  bool showSight = true;         ///< sight ranges (each team's outline)
  int fogRays = 48;              ///< rays per unit for the fog outline (0: plain disks, ignore walls)
  std::vector<uint8_t> selected;  ///< by unit id (the window's selection); may be empty
  bool hasSelectionBox = false;
  Vec2 selectionA, selectionB;
  bool paused = false;
  /// One more HUD line under the others when not empty: the window's network game (whom it waits for).
  std::string banner;
  /// Show the measured engine step time in the HUD. It is a wall-clock measurement, so frames that
  /// must be reproducible byte for byte (tests, golden frames) turn it off.
  bool showTimes = true;
};

Scene buildScene(const Game& game, const SceneOptions& options);

/// The HUD lines: tick, units per team, shots, crossings, engine step time; rooms held.
std::vector<std::string> hudLines(const Game& game, bool paused, bool showTimes);

}  // namespace rts
