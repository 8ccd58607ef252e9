// Frames of a replay: the demo's renderer (demo/render) drawing the replayed game at chosen ticks.
// Replay frames never show the measured step time, so the same replay gives the same PNG bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "format/replay.h"
#include "game/game.h"
#include "render/offscreen.h"

namespace rts::replay {

struct FrameOptions {
  int width = 1280, height = 720;
  int supersample = 2;
  int fogTeam = 0;  ///< -1: no fog
  bool showSight = true;
};

/// Draws the game as a frame: width x height RGBA pixels, top row first.
std::vector<uint8_t> drawFrame(OffscreenRenderer& renderer, const Game& game, const FrameOptions& options);

struct RenderRequest {
  std::string dir;  ///< frames go here as frame_NNNNNN.png (by tick)
  uint32_t from = 0, to = UINT32_MAX, every = 1;
  FrameOptions frame;
};

struct RenderOutcome {
  int framesWritten = 0;
  std::optional<uint32_t> firstDivergence;  ///< the first tick whose hashes differ from the recording
  std::string error;             ///< set when a frame could not be written
};

/// Plays the replay to `to` (or its end), writing the frames asked for. `progress(tick, last)` after
/// every tick. Throws ReplaySetupError and RenderError.
RenderOutcome renderReplay(const Replay& replay, const RenderRequest& request,
                           const std::function<void(uint32_t, uint32_t)>& progress = {});

}  // namespace rts::replay
