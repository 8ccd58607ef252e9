// rattle-bench: the command line.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine.h"
#include "scenes.h"

namespace rattle_bench {

/// The arena scene's step: the demo game's fixed tick (rts::Game::kTickSeconds; arena_run.cpp checks that
/// they agree). The only --dt the arena scene takes.
inline constexpr double kArenaTickSeconds = 1.0 / 30;

struct Options {
  SceneParams scene;
  std::string engine = "hybrid";
  double dt = 1.0 / 60.0;
  std::string dtText = "1/60";  ///< as given, for messages
  double seconds = 2.0;
  std::string secondsText = "2";  ///< as given, for messages
  bool csv = false;
  bool reference = true;  ///< run the exact reference (--no-reference skips it)
  int measureEvery = 1;   ///< measure overlaps and tunnelling after every k-th step (and the last)
  /// Simulated seconds at the start whose steps are not timed; < 0: the first tenth of the steps.
  double warmUp = -1;
  std::string warmUpText;  ///< as given, for messages
  bool quiet = false;     ///< no progress line on stderr
  /// Wall-clock seconds after which the run stops at the end of the step under way (0: no limit); the row
  /// then covers the steps run and says it was stopped (stopped_at_time_limit).
  double timeLimit = 0;
  EngineSettings settings;
  bool help = false;
  bool version = false;
};

/// A bad command line; the message names the option and the value.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Parses argv (without argv[0]). Throws UsageError.
Options parseOptions(const std::vector<std::string>& args);

/// The --help text.
std::string helpText();

}  // namespace rattle_bench
