// A way of advancing the world: one Stepper per StepMode. World::step saves the step's start
// (step_undo.cpp) and forgets the squeezes that parted, then hands the step to the world's stepper,
// chosen once from WorldDef::mode. A stepper moves every body to the step's end and fills the world's
// contactEvents, sensorEvents and stats; what it keeps from one step to the next is its own.
//
// What the modes share stays in WorldState: the bodies and fixtures, the broad phase, the contact
// response and the squeezes (contact/). The islands and jams (contact/islands.h) are the hybrid step's,
// kept in its HybridState; they tell the step that runs them whose motion they changed through an
// EventPredictor. The predictive mode hands a pile over to the hybrid step (detail::stepHybrid,
// hybrid_step.h) for the rest of a step, with a HybridState of its own.
#pragma once

#include <cstdint>
#include <memory>

namespace rattle::detail {

struct WorldState;
struct Islands;  // contact/islands.h

/// What the persistent contact (islands and jams, contact/) tells the step that runs it and predicts
/// events: a body's motion changed at `now`, so its events for the rest of the step (of length dt) are
/// predicted again. The hybrid step is one; while it runs, Islands::predictor names it.
class EventPredictor {
 public:
  virtual void motionChanged(uint32_t body, double now, double dt) = 0;

 protected:
  ~EventPredictor() = default;
};

class Stepper {
 public:
  virtual ~Stepper() = default;
  /// Advances the world by dt (finite, >= 0).
  virtual void step(double dt) = 0;
  /// A step failed (out of memory) and the world was taken back to its start: drop whatever was kept
  /// that the failed step may have left part built.
  virtual void forget() {}
  /// The islands whose warm start and jam count carry from step to step (World::save keeps them), or
  /// null for a mode without them.
  virtual Islands* islands() { return nullptr; }
};

/// StepMode::Hybrid (hybrid/hybrid_step.cpp): it keeps the hybrid step's state (HybridState: the event
/// queue, the disk shapes, scratch) across steps.
std::unique_ptr<Stepper> makeHybridStepper(WorldState& world);
/// StepMode::Discrete (discrete/discrete_step.cpp): it keeps only its scratch lists.
std::unique_ptr<Stepper> makeDiscreteStepper(WorldState& world);
/// StepMode::Predictive (predictive/predictive_step.cpp): it keeps its cell grid and its event queue
/// across steps (PredictiveState), and a HybridState for the steps it hands over to the hybrid step.
std::unique_ptr<Stepper> makePredictiveStepper(WorldState& world);

}  // namespace rattle::detail
