// Private: what a step changes of the world's lasting state, kept from its start so that a step that
// runs out of memory can be taken back (step_undo.cpp), and World::step throws with the world unchanged.
#pragma once

#include <cstdint>

#include "world/world_impl.h"

namespace rattle::detail {

/// The state of a body that the step's start keeps (keepBody is declared in world_impl.h, for keep).
WorldState::BodyAtStepStart stateOf(uint32_t body, const BodySlot& b);
/// At World::step's start: keeps what a failed step must put back (sensor events pending, squeezes,
/// stats, the clock), and starts logging the changes of the step.
void saveStepStart(WorldState& w);
/// The step ran out of memory: puts back what it changed of the world's lasting state, voids the caches
/// of positions it moved away from, and tells the stepper to forget what it kept.
void undoStep(WorldState& w);
/// After a step that completed: stops logging.
void endStep(WorldState& w);

}  // namespace rattle::detail
