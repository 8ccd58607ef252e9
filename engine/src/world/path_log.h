// Private: the paths bodies took through a step, piece by piece, for the modes that find sensor events
// after the step instead of during it (hybrid and predictive; see sensor_paths.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "rattle/vec2.h"

namespace rattle::detail {

// A body's motion from `start` until the next piece starts: position + velocity h + acceleration h^2/2,
// h = t - start (detail::WorldState::positionAt).
struct PathPiece {
  double start = 0;
  Vec2 position, velocity, acceleration;
};

struct PathLog {
  bool active = false;              // the world has sensors: changes are being recorded this step
  std::vector<PathPiece> first;     // by body index: the motion at the step's start
  std::vector<uint8_t> asleepAtStart;  // by body index
  std::vector<uint32_t> lastPiece;  // by body index: its latest piece in `changes`, or kNoPiece (`first`)
  struct Change {
    uint32_t body;
    PathPiece piece;
  };
  std::vector<Change> changes;  // in the order they happened (so in time order for each body)
  static constexpr uint32_t kNoPiece = 0xFFFFFFFFu;

  const PathPiece& latest(uint32_t body) const {
    return lastPiece[body] == kNoPiece ? first[body] : changes[lastPiece[body]].piece;
  }
  /// Records the body's motion from its local time on, unless it is the motion already recorded.
  void record(uint32_t body, const PathPiece& p) {
    const PathPiece& l = latest(body);
    if (l.start == p.start && l.position == p.position && l.velocity == p.velocity &&
        l.acceleration == p.acceleration) {
      return;
    }
    lastPiece[body] = static_cast<uint32_t>(changes.size());
    changes.push_back({body, p});
  }
};

}  // namespace rattle::detail
