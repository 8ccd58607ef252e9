// A step that runs out of memory part way is taken back (World::step), so that the caller gets
// rattle::Error and the world as it was before the call, as every other call of the API promises.
//
// Taking a step back is cheaper than making each of its allocations safe. What a step changes of the
// world's lasting state is kept as it goes: the bodies (below), the sensors' overlaps and the lists of
// sleeping bodies (logged where they change), and what the step keeps only to go faster (the broad
// phase's kept pairs, the predictive mode's queue) is marked void, to be rebuilt by the next step.
//
// The bodies: a step's passes over every body are most of a large gas's time, so the hybrid and
// predictive steps keep a body only when they first change it (detail::WorldState::keep: from advance, from
// the predictive step's copy back into the body, and from the few places that change a body without
// advancing it), and their last pass, which moves every body to the end, comes after everything that
// allocates. Their first passes change only what they set again every step. A gas's step keeps the
// bodies that collide. The discrete step, which moves every body before it looks for pairs, keeps each
// body's position and velocity as it moves it (the only lasting state it changes).
//
// Nothing in undoStep allocates: the log holds the map's own nodes, and putting a node back cannot
// rehash the map, as it never holds more than it held when the node was taken out.
#include "world/step_undo.h"

#include <algorithm>

#include "common/out_of_memory.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

detail::WorldState::BodyAtStepStart detail::stateOf(uint32_t body, const detail::BodySlot& b) {
  return {body, b.position, b.velocity, b.acceleration, b.localTime, b.support, b.lastContactTime,
          b.asleep, b.stepped, b.sliding};
}

void detail::keepBody(WorldState& w, uint32_t body) {
  detail::roomForOneMore(w.stepStart.bodies);  // before the change it precedes: a failure here is clean
  detail::BodySlot& b = w.bodies[body];
  w.stepStart.bodies.push_back(stateOf(body, b));
  b.kept = true;
}

void detail::saveStepStart(WorldState& w) {
  // Room first: a failure here leaves everything as it was.
  w.stepStart.keepEach = w.def.mode != StepMode::Discrete;
  w.stepStart.keeping = false;
  w.stepStart.bodies.clear();
  if (!w.stepStart.keepEach && w.stepStart.motion.size() < w.bodies.size()) w.stepStart.motion.resize(w.bodies.size());
  w.stepStart.pendingSensorEvents = w.pendingSensorEvents;
  w.stepStart.squeezes = w.squeezes;
  w.stepStart.sleepersOnAwakeBodies = w.sleepersOnAwakeBodies;
  w.stepStart.sensorOverlaps.clear();
  w.stepStart.dependents.clear();
  w.stepStart.time = w.time;
  w.stepStart.stats = w.stats;
  w.stepStart.active = true;
  w.stepStart.keeping = w.stepStart.keepEach;
}

void detail::endStep(WorldState& w) {
  w.stepStart.active = false;
  w.stepStart.keeping = false;
  if (w.stepStart.keepEach) {
    for (const WorldState::BodyAtStepStart& s : w.stepStart.bodies) w.bodies[s.body].kept = false;
  }
  w.stepStart.sensorOverlaps.clear();  // frees the ended overlaps' nodes
  w.stepStart.dependents.clear();
}

void detail::undoStep(WorldState& w) {
  w.contactEvents.clear();  // a failed step reports no events
  w.sensorEvents.clear();
  if (!w.stepStart.active) return;  // saveStepStart failed: nothing else changed
  w.stepStart.active = false;
  w.stepStart.keeping = false;
  // Latest first: a body kept twice (a jam undone puts back a copy of its slot from before it was kept)
  // ends with its first record, from the step's start.
  for (auto it = w.stepStart.bodies.rbegin(); it != w.stepStart.bodies.rend(); ++it) {
    detail::BodySlot& b = w.bodies[it->body];
    b.position = it->position;
    b.velocity = it->velocity;
    b.acceleration = it->acceleration;
    b.localTime = it->localTime;
    b.support = it->support;
    b.lastContactTime = it->lastContactTime;
    b.asleep = it->asleep;
    b.stepped = it->stepped;
    b.sliding = it->sliding;
    b.kept = false;
    b.stepLocalsSet = true;  // the next step resets them (stepHybrid's first pass)
  }
  if (!w.stepStart.keepEach) {
    // The discrete step moved these (discrete_step.cpp) and changed nothing else of a body that lasts.
    for (uint32_t i = 0; i < w.bodies.size(); ++i) {
      detail::BodySlot& b = w.bodies[i];
      if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
      b.position = w.stepStart.motion[i].first;
      b.velocity = w.stepStart.motion[i].second;
    }
  }
  w.time = w.stepStart.time;
  w.stats = w.stepStart.stats;
  w.pendingSensorEvents.swap(w.stepStart.pendingSensorEvents);
  w.squeezes.swap(w.stepStart.squeezes);
  w.squeezeIndex.valid = false;  // read one by one until the next step sorts it again
  w.sleepersOnAwakeBodies.swap(w.stepStart.sleepersOnAwakeBodies);
  // Newest first, so that each entry finds the map (and each list) as it was right after its change.
  for (auto it = w.stepStart.sensorOverlaps.rbegin(); it != w.stepStart.sensorOverlaps.rend(); ++it) {
    if (it->ended.empty()) {
      w.sensorOverlaps.erase(it->key);
    } else {
      w.sensorOverlaps.insert(std::move(it->ended));
    }
  }
  w.stepStart.sensorOverlaps.clear();
  // A list wakeUp emptied goes back whole; what a failed step added to it named bodies that are awake
  // again, and a list may name an awake body (wakeUp passes it over).
  for (auto it = w.stepStart.dependents.rbegin(); it != w.stepStart.dependents.rend(); ++it) {
    w.dependents[it->first] = std::move(it->second);
  }
  w.stepStart.dependents.clear();
  // Scratch whose invariants hold between calls.
  w.pathLog.active = false;
  // Caches of positions the step moved away from: void, rebuilt by the next step.
  w.broadPhase.forgetStep();
  if (w.stepper) w.stepper->forget();  // the event queues may be part built: the next step makes them afresh
  w.changes.structureChanged = true;
  ++w.changes.staticVersion;
}

}  // namespace rattle
