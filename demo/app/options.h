// The command line of rattle-demo.
#pragma once

#include <rattle/types.h>

#include <cstdint>
#include <string>

#include "game/steering.h"
#include "net/transport.h"

namespace rts {

struct Options {
  std::string map;            ///< map file; empty: the default arena
  long ticks = 600;           ///< ticks to run; a window alone: quit after this many (0: run until closed)
  bool ticksGiven = false;
  uint64_t seed = 1;
  std::string framesDir = "out/demo";
  int every = 10;             ///< write a frame every N ticks
  int width = 1280, height = 720;
  int supersample = 2;        ///< the window uses 1 unless asked: software OpenGL at 4 samples is slow
  bool supersampleGiven = false;
  int units = 100;            ///< per team
  bool render = true;
  bool window = false;
  int fogTeam = 0;            ///< whose view the frames show; -1: no fog
  bool showSight = true;
  bool showTimes = true;      ///< the measured step time in the HUD (off: reproducible frames)
  rattle::StepMode mode = rattle::StepMode::Hybrid;
  Steering steering = Steering::KeepApart;  ///< --steering: keep-apart (default) or naive
  std::string screenshot;     ///< window: save the last frame shown
  std::string inputScript;    ///< window: scripted input events (for tests)
  bool quiet = false;
  std::string record;         ///< write a replay of the game to this file (replay/FORMAT.md)
  int keyframeEvery = 30;     ///< the replay's keyframe interval, in ticks
  bool framesGiven = false, fogGiven = false;

  // Network play, headless or in the window (demo/README.md, "Network play").
  enum class Network { None, Host, Join, Watch } network = Network::None;
  uint16_t port = net::kDefaultPort;  ///< --host: the port to listen on (0: any free one); --join, --watch: the host's
  std::string joinHost;       ///< --join, --watch: the host's name or address
  int inputDelay = 3;         ///< ticks between issuing a command and applying it
  int hashEvery = 1;          ///< ticks between state hash comparisons
  double peerTimeout = 10;    ///< seconds of silence after which the peer is given up on
  /// The team this side plays: the host blue (0), the joiner red (1); a spectator plays none (0).
  int team() const { return network == Network::Join ? 1 : 0; }
};

/// What parsing decided: run with the options, exit with a status (after --help), or a usage error.
struct ParseResult {
  enum class Action { Run, Exit } action = Action::Run;
  int exitCode = 0;
  Options options;
};

/// Parses argv. Prints --help to stdout and errors (naming the option and the value) to stderr.
ParseResult parseOptions(int argc, char** argv);

}  // namespace rts
