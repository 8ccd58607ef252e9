// A way of advancing the world: one Stepper per StepMode. World::step saves the step's start
// (step_undo.cpp) and forgets the squeezes that parted, then hands the step to the world's stepper,
// chosen once from WorldDef::mode. A stepper moves every body to the step's end and fills the world's
// contactEvents, sensorEvents and stats; what it keeps from one step to the next is its own.
//
// What the modes share stays in WorldState: the bodies and fixtures, the broad phase, the persistent
// contact (islands, jams, squeezes: contact/) and the hybrid step's predictions, which the islands
// call back into (repredict); the predictive mode hands a pile over to the hybrid step
// (detail::stepHybrid, hybrid_step.h) for the rest of a step.
#pragma once

#include <memory>

namespace rattle::detail {

struct WorldState;

class Stepper {
 public:
  virtual ~Stepper() = default;
  /// Advances the world by dt (finite, >= 0).
  virtual void step(double dt) = 0;
  /// A step failed (out of memory) and the world was taken back to its start: drop whatever was kept
  /// that the failed step may have left part built.
  virtual void forget() {}
};

/// StepMode::Hybrid (hybrid/hybrid_step.cpp): it keeps nothing of its own between steps beyond
/// WorldState's hybrid state.
std::unique_ptr<Stepper> makeHybridStepper(WorldState& world);
/// StepMode::Discrete (discrete/discrete_step.cpp): it keeps only its scratch lists.
std::unique_ptr<Stepper> makeDiscreteStepper(WorldState& world);
/// StepMode::Predictive (predictive/predictive_step.cpp): it keeps its cell grid and its event queue
/// across steps (PredictiveState).
std::unique_ptr<Stepper> makePredictiveStepper(WorldState& world);

}  // namespace rattle::detail
