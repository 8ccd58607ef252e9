// What the World API changed since the last step. The predictive mode keeps its predictions from one
// step to the next and reads this to know what to predict again: after a change of structure (a body or
// fixture created or destroyed, a filter, a static or kinematic body moved) it starts afresh; the dynamic
// bodies touched (moved, given a velocity, woken, given a mass) are predicted again. Every mutator of
// World writes here (api/world.cpp), the step reads it, and World::step clears it.
#pragma once

#include <rattle/world.h>

#include <cstdint>
#include <vector>

#include "common/out_of_memory.h"

namespace rattle::detail {

struct ChangeLog {
  bool structureChanged = true;
  // Moves on when a fixture is created on or destroyed with a static or kinematic body, and when a
  // static body moves: the predictive mode keeps its listing of static fixtures by cell (and of kinematic
  // fixtures) while it stays, so a change of structure among dynamic bodies (a shot fired) does not list
  // a map's walls again. Filters are not listed.
  uint64_t staticVersion = 0;
  bool restitutionChanged = false;  // World::setRestitution since the last step
  // Moves on when a fixture is destroyed (never cleared): what a stepper keeps by fixture index (the
  // islands' warm start) is void then, as indices are reused.
  uint64_t fixtureRemovals = 0;
  std::vector<uint32_t> touchedBodies;

  void staticsChanged(BodyType type) {
    if (type != BodyType::Dynamic) ++staticVersion;
  }
  void touched(uint32_t body, BodyType type) {
    if (type == BodyType::Dynamic) {
      touchedBodies.push_back(body);
    } else {
      structureChanged = true;
      // A kinematic body's motion is not listed (every prediction looks at each kinematic fixture).
      if (type == BodyType::Static) ++staticVersion;
    }
  }
  /// Room in touchedBodies for `count` more, so that the touched calls that follow cannot fail.
  void roomToTouch(size_t count) { detail::roomFor(touchedBodies, count); }
  /// After a step: nothing changed since.
  void clear() {
    structureChanged = false;
    restitutionChanged = false;
    touchedBodies.clear();
  }
};

}  // namespace rattle::detail
