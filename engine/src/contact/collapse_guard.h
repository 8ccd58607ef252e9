// Private: the collapse guard without gravity, shared by resolve() (hybrid_step.cpp) and its copy for
// two plain disks (plain_collision.h).
#pragma once

#include <algorithm>

namespace rattle::detail {

// Dynamic bodies with restitution below 1 and nothing else to hold them (no gravity, nobody driven) can
// collide infinitely often in finite time: inelastic collapse (McNamara & Young, Phys. Fluids A 4, 496,
// 1992), a row of four disks at restitution 0.05 already. A body that has taken more than a sixteenth of
// the step's event budget has its touching cluster held as a jam (jam.cpp); where the jam is refused, it
// collides elastically for the rest of the step, as the
// TC model does within WorldDef::collapseTime of a collision (Luding & McNamara, Granular Matter 1, 113,
// 1998): it never adds energy, and it ends the collapse. Sequences that converge take far fewer: a light
// disk caught between two heavy ones (1000 times its mass, restitution 0) settles after 35,251
// collisions, below the default budget's 62,500.
inline int collapseCollisions(int maxEventsPerStep) { return std::max(64, maxEventsPerStep / 16); }

}  // namespace rattle::detail
