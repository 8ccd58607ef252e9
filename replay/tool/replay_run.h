// Plays a replay back: builds its game from the embedded map and configuration, applies the recorded
// commands before each tick (no opponent, no person), and checks each tick against the recording.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "format/replay.h"
#include "game/game.h"
#include "game/tick_loop.h"
#include "tool/divergence.h"

namespace rts::replay {

/// The replay's map or configuration cannot make a game (a bad embedded map, units that do not fit, a
/// game whose sizes differ from the ones recorded). The message says which.
class ReplaySetupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How one tick of the re-run compares with the recording.
struct TickCheck {
  uint32_t tick = 0;
  uint64_t recordedStateHash = 0, actualStateHash = 0;
  uint64_t recordedWorldHash = 0, actualWorldHash = 0;
  std::vector<std::string> bodies;  ///< bodies whose digests differ (empty at tick 0: no digests)
  bool keyframe = false;            ///< the recording has a keyframe here; `fields` compares it
  std::vector<FieldDiff> fields;
  bool ok() const { return recordedStateHash == actualStateHash && recordedWorldHash == actualWorldHash && bodies.empty() && fields.empty(); }
};

/// A recording's commands as a source: each tick's, as they were played.
class RecordedCommands : public CommandSource {
 public:
  /// `replay` must outlive the source.
  explicit RecordedCommands(const Replay& replay) : replay_(replay) {}
  /// Appends the commands recorded for `tick`; none past the recording's end.
  void commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) override;

 private:
  const Replay& replay_;
};

class ReplayRun {
 public:
  /// Builds the game. Throws ReplaySetupError. `replay` must outlive the run.
  explicit ReplayRun(const Replay& replay);
  ~ReplayRun();

  const Game& game() const { return *game_; }
  uint32_t tick() const { return game_->tickCount(); }
  uint32_t lastTick() const { return replay_.tickCount(); }
  bool done() const { return tick() >= lastTick(); }

  /// The state before the first tick against the recording's INIT and first keyframe.
  TickCheck checkInitial() const;
  /// Applies the next tick's recorded commands, ticks, and compares. With `check` false it only plays
  /// (faster: no snapshot, no digests) and returns the hashes alone.
  TickCheck step(bool check = true);

 private:
  const Keyframe* keyframeAt(uint32_t tick) const;
  const Replay& replay_;
  std::unique_ptr<Game> game_;
  RecordedCommands recorded_;
  TickLoop loop_;
  size_t nextKeyframe_ = 0;
};

/// The game a replay describes, unplayed (for `info` and the runner). Throws ReplaySetupError.
std::unique_ptr<Game> buildGame(const Replay& replay);

}  // namespace rts::replay
