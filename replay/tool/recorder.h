// Records a game as it is played: the header when the game starts, then one TICK record (and a
// keyframe when due) after every tick, and END! when it is done. It only reads the game, so recording
// changes nothing in it. The file is written as FILE.part and renamed to FILE by finish(), so a run
// that dies half-way leaves no file that looks complete.
#pragma once

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "format/replay_writer.h"
#include "game/game.h"

namespace rts::replay {

struct RecordingInfo {
  std::string mapName;  ///< shown by `rattle-replay info`
  std::string mapJson;  ///< the map file's bytes, exactly (the game must have been built from them)
  uint64_t seed = 0;
  uint8_t opponentTeams = 3;  ///< which teams the scripted opponent played
  uint32_t keyframeEvery = 30;
  std::string recordedBy;
};

class Recorder {
 public:
  /// Opens FILE.part and writes everything up to the state at tick 0 (call before the first tick).
  /// Throws std::runtime_error naming the file when it cannot be written.
  Recorder(const std::string& path, const RecordingInfo& info, const Game& game);
  ~Recorder();

  /// After Game::tick(): `applied` are the commands given to Game::apply before it.
  void afterTick(const Game& game, const std::vector<Command>& applied);
  /// Writes END!, closes the file and renames it to its name. Throws on an I/O error.
  void finish(const Game& game);
  const std::string& path() const { return path_; }

 private:
  std::string path_, partPath_;
  std::ofstream out_;
  std::unique_ptr<ReplayWriter> writer_;
  bool finished_ = false;
};

}  // namespace rts::replay
