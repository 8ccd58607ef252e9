// rattle-replay verify, as a function: re-run a replay and compare every tick with the recording.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "format/replay.h"
#include "tool/replay_run.h"

namespace rts::replay {

struct VerifyReport {
  std::vector<std::string> buildDifferences;  ///< empty: recorded by a build like this one
  uint32_t ticks = 0;                         ///< ticks in the replay
  uint32_t ticksMatched = 0;                  ///< ticks that matched before the first divergence
  std::optional<TickCheck> divergence;        ///< the first tick that differs (hashes, digests or keyframe)
  /// The first keyframe at or after the divergence, compared field by field (when the divergence was
  /// not itself at a keyframe: then `divergence` holds the fields).
  std::optional<TickCheck> keyframeAfter;
  bool ok() const { return !divergence; }
  /// The report as text: build differences first, then the outcome.
  std::string text(const std::string& name) const;
};

/// `progress(tick, total)` is called after every tick. Throws ReplaySetupError.
VerifyReport verifyReplay(const Replay& replay, const std::function<void(uint32_t, uint32_t)>& progress = {});

/// A hash as 16 hex digits.
std::string hex64(uint64_t v);

}  // namespace rts::replay
