// Routes between regions. A region is a room of the map or, for everything outside the rooms, the open
// field; doorways and gates are portals between two regions. A route is the list of portals to cross,
// found by Dijkstra over portal midpoints: with a handful of portals a route costs microseconds, so
// every unit gets its own when it is ordered, and again when it is stuck.
//
// Inside a convex room a straight line reaches any doorway on its edge; in the field, units slide
// along buildings in their way (the engine has no friction), which is enough for this map.
#pragma once

#include <vector>

#include "map/map.h"

namespace rts {

struct Portal {
  Vec2 a, b;        ///< the opening, from one post to the other
  Vec2 middle;
  Vec2 along;       ///< unit vector from a to b
  Vec2 normal;      ///< unit, perpendicular; region[1] is on its side
  double halfWidth = 0;
  int region[2] = {0, 0};
  int doorway = -1;  ///< index into the map's doorways, or -1
  int gate = -1;     ///< index into the map's gates, or -1
};

/// One portal to pass, and the side (+1 or -1 along the portal's normal) to come out on.
struct Leg {
  int portal = 0;
  int side = 1;
};

class Navigation {
 public:
  explicit Navigation(const Map& map);

  /// The room containing p, or fieldRegion() when none does.
  int regionOf(Vec2 p) const;
  int fieldRegion() const { return int(rooms_.size()); }
  /// +1 or -1: which side of portal `portal` p is on.
  int side(int portal, Vec2 p) const;
  /// The portals to cross, in order, from `from` to `to`; `gateOpen[g]` says whether gate g may be used.
  /// Empty when both are in one region. `found` is false when no route exists.
  std::vector<Leg> route(Vec2 from, Vec2 to, const std::vector<bool>& gateOpen, bool* found = nullptr) const;
  const std::vector<Portal>& portals() const { return portals_; }

 private:
  std::vector<std::vector<Vec2>> rooms_;
  std::vector<Portal> portals_;
};

}  // namespace rts
