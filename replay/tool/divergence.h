// What differs between a recording and a re-run: which bodies (from the per-tick digests) and, where a
// keyframe holds the exact state, which fields and by how much.
#pragma once

#include <string>
#include <vector>

#include "format/replay.h"
#include "game/game.h"

namespace rts::replay {

/// One field of one body that differs.
struct FieldDiff {
  std::string body;      ///< "unit 17 (blue)", "shot 203 (red)", "gate 0 (keep gate)", "counters"
  std::string field;     ///< "position.x", "hitPoints", ...
  std::string recorded;  ///< the value in the replay, exactly (%.17g for doubles)
  std::string actual;    ///< the value in this run
  std::string delta;     ///< "+1.78e-15, 1 ulp" (ulps while at most 2^20), "-1", or "" when not a number
};

/// The names of the bodies whose digests differ (and of bodies present in one only). `game` names them.
std::vector<std::string> digestDifferences(const Digests& recorded, const Digests& actual, const Game& game);

/// Every field that differs, body by body in order: counters, units, shots, gates.
std::vector<FieldDiff> snapshotDifferences(const Snapshot& recorded, const Snapshot& actual, const Game& game);

/// "unit 17 (blue)" and the like.
std::string unitName(const Game& game, uint32_t id);
std::string gateName(const Game& game, size_t gate);

/// How many representable doubles lie between a and b (0 when equal; saturates at INT64_MAX).
int64_t ulpDistance(double a, double b);

}  // namespace rts::replay
