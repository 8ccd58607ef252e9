// The discrete mode (being written).
#include "world_impl.h"

namespace rattle {

void World::Impl::stepDiscrete(double dt) { stepHybrid(dt); }

}  // namespace rattle
