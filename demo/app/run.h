// The two ways to run a game: headless (frames to PNG, or nothing) and in a window.
#pragma once

#include <string>

#include "app/options.h"
#include "game/game.h"

namespace rts {
namespace replay {
class Recorder;
}

/// rattle-demo's exit statuses beyond 0 (done), 1 (an error) and 2 (bad options): how a networked
/// game ended early (demo/README.md, "Network play").
inline constexpr int kExitRefused = 3;   ///< the handshake refused the game (a setting differs)
inline constexpr int kExitDesync = 4;    ///< the two sides' state hashes differ
inline constexpr int kExitPeerLost = 5;  ///< the peer could not be reached, disconnected, went silent or left early
inline constexpr int kExitProtocol = 6;  ///< the peer sent garbage or broke the protocol

/// Runs options.ticks ticks with the scripted opponent playing both teams, or with --host or --join
/// this side's team against the peer's over the network. `mapJson`: the map file's bytes (the
/// handshake compares their digest). Returns the exit status. `recorder` (may be null) is told every
/// tick's commands and finished at the end (a networked game that ends early: with the ticks played).
int runHeadless(Game& game, const Options& options, const std::string& mapJson, replay::Recorder* recorder);
/// Opens an SDL2 window; the person plays team 0 and the scripted opponent team 1, or with --host or
/// --join the person plays this side's team against the peer's (with --watch: follows the host's
/// game). Returns the exit status, as runHeadless does; a person who quits a network game leaves it
/// (the peer is told) and the status is 0.
int runWindow(Game& game, const Options& options, const std::string& mapJson, replay::Recorder* recorder);

/// The closing paragraph: ticks, units left, shots, wall hits, crossings, median engine step time.
/// `medianFrameSeconds`: to draw and write a frame; `medianDrawSeconds`: to draw it (scene and OSMesa).
void printSummary(const Game& game, const Options& options, int framesWritten, double medianFrameSeconds,
                  double medianDrawSeconds);

/// A progress line on stderr, at most a few times a second; `done` ends it.
void progress(const Game& game, long totalTicks, bool done);

}  // namespace rts
