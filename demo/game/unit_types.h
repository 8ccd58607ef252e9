// Unit types: the numbers that make a unit. Add a row to add a type (see docs/rts-template.md): the
// physics, the rules and the renderer read everything from here. GameConfig::unitTypes says which
// units get which type; the default game makes every unit a trooper.
#pragma once

#include <array>
#include <cstdint>

namespace rts {

struct UnitType {
  const char* name;
  double radius;       ///< body disk, world units
  double density;      ///< mass per area (heavier units push lighter ones aside)
  double speed;        ///< top speed, world units per second
  double sight;        ///< radius of the sight sensor, world units
  int hitPoints;       ///< hits it takes before it dies
  double reload;       ///< seconds between shots
  double shotSpeed;    ///< projectile speed, world units per second
  double shotRadius;   ///< projectile disk, world units
  double range;        ///< how far a projectile flies before it is gone, world units
};

inline constexpr std::array<UnitType, 2> kUnitTypes = {{
    // A projectile covers 2 world units per tick at 30 ticks per second: several wall thicknesses,
    // which a step-and-check engine would skip straight through.
    {"trooper", 0.5, 1.0, 6.0, 10.0, 3, 1.0, 60.0, 0.15, 11.0},
    // Nearly twice a trooper's size, with a shot twice as wide. The default game deals none; the tests
    // deal it to check that placing, navigation and shots follow each unit's own type.
    {"heavy", 0.9, 2.0, 4.0, 11.0, 8, 1.5, 50.0, 0.3, 12.0},
}};

}  // namespace rts
