// rattle-replay record, as a function: a headless game played by the scripted opponent and/or a command
// script, recorded to a file.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include <rattle/types.h>

namespace rts::replay {

struct RecordRequest {
  std::string mapPath;
  uint64_t seed = 1;
  uint32_t ticks = 300;
  int unitsPerTeam = 100;
  rattle::StepMode mode = rattle::StepMode::Hybrid;
  bool weapons = true;
  unsigned opponentTeams = 3;  ///< bit t: the scripted opponent plays team t
  std::string scriptPath;      ///< a command script (command_script.h), or empty
  uint32_t keyframeEvery = 30;
  std::string output;
};

struct RecordOutcome {
  uint32_t ticks = 0;
  size_t commands = 0;
  uint64_t finalStateHash = 0;
};

/// Plays and records. Throws MapError, GameError or std::runtime_error with a message for the user.
RecordOutcome recordGame(const RecordRequest& request, const std::function<void(uint32_t, uint32_t)>& progress = {});

}  // namespace rts::replay
