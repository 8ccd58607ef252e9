// Private: the hybrid step, which the hybrid mode's stepper runs every step and the predictive mode
// hands a step's rest to when a pile forms (predictive_step.cpp).
#pragma once

namespace rattle::detail {

struct WorldState;
struct HybridState;

/// One hybrid step of dt (hybrid_step.cpp says how), with the state the hybrid step keeps between steps
/// (hybrid_state.h), which its caller owns. `eventsBefore`: events a predictive step processed before
/// it handed the rest of its step over; they count toward this step's budget and its stats.
void stepHybrid(WorldState& world, HybridState& state, double dt, int eventsBefore = 0);

}  // namespace rattle::detail
