// The predictive mode (being written).
#include "predictive_step.h"

#include "world_impl.h"

namespace rattle {

void World::Impl::stepPredictive(double dt) { stepHybrid(dt); }

}  // namespace rattle
