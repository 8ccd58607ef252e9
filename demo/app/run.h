// The two ways to run a game: headless (frames to PNG, or nothing) and in a window.
#pragma once

#include "app/options.h"
#include "game/game.h"

namespace rts {
namespace replay {
class Recorder;
}

/// Runs options.ticks ticks with the scripted opponent playing both teams. Returns the exit status.
/// `recorder` (may be null) is told every tick's commands and finished at the end.
int runHeadless(Game& game, const Options& options, replay::Recorder* recorder);
/// Opens an SDL2 window; the person plays team 0, the scripted opponent team 1. Returns the exit status.
int runWindow(Game& game, const Options& options, replay::Recorder* recorder);

/// The closing paragraph: ticks, units left, shots, wall hits, crossings, median engine step time.
/// `medianFrameSeconds`: to draw and write a frame; `medianDrawSeconds`: to draw it (scene and OSMesa).
void printSummary(const Game& game, const Options& options, int framesWritten, double medianFrameSeconds,
                  double medianDrawSeconds);

/// A progress line on stderr, at most a few times a second; `done` ends it.
void progress(const Game& game, long totalTicks, bool done);

}  // namespace rts
