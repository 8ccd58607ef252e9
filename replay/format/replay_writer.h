// Writes replays: chunk by chunk to a stream while a game runs (ReplayWriter), or a whole Replay at
// once (encodeReplay, for tools and tests). Both produce exactly what replay_reader.h reads.
#pragma once

#include <ostream>
#include <string>

#include "format/replay.h"

namespace rts::replay {

/// Streams a replay. Call begin, then tick for every tick (with the keyframe when one is due:
/// keyframeDue tells), then end. Throws std::runtime_error when the stream fails.
class ReplayWriter {
 public:
  explicit ReplayWriter(std::ostream& out) : out_(out) {}

  /// Magic, version, BILD, MAPJ, CONF, INIT and the keyframe of tick 0.
  void begin(const std::vector<BuildFact>& build, const std::string& mapName, const std::string& mapJson,
             const ReplayConfig& config, uint64_t initialStateHash, uint64_t initialWorldHash, const Snapshot& initial);
  /// Whether tick `tick` needs a keyframe on the schedule (a multiple of keyframeEvery).
  bool keyframeDue(uint32_t tick) const { return tick % config_.keyframeEvery == 0; }
  /// One TICK chunk; `keyframe` (may be null) follows it as a KEYF chunk.
  void tick(const TickRecord& record, const Snapshot* keyframe);
  /// The last tick's keyframe if it was not on the schedule, then END!. `last` is the state after the
  /// last tick written.
  void end(const Snapshot& last);
  uint32_t ticksWritten() const { return ticks_; }

 private:
  void chunk(const char tag[4], const std::string& payload);
  std::ostream& out_;
  ReplayConfig config_;
  uint32_t ticks_ = 0;
  uint32_t lastKeyframe_ = 0;
  uint64_t lastHash_ = 0;
};

/// The whole replay as bytes (recomputing nothing: the digests, hashes and keyframes are written as
/// they are in `replay`, so a test can change one field and get a well-formed file).
std::string encodeReplay(const Replay& replay);

/// A chunk as bytes: tag, length, payload, CRC-32.
std::string encodeChunk(const char tag[4], const std::string& payload);

}  // namespace rts::replay
