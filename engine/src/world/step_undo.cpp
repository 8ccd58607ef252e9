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
#include <algorithm>

#include "common/out_of_memory.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

detail::WorldState::BodyAtStepStart detail::WorldState::stateOf(uint32_t body, const detail::BodySlot& b) {
  return {body, b.position, b.velocity, b.acceleration, b.localTime, b.support, b.lastContactTime,
          b.asleep, b.stepped, b.sliding};
}

void detail::WorldState::keepBody(uint32_t body) {
  detail::roomForOneMore(stepStart.bodies);  // before the change it precedes: a failure here is clean
  detail::BodySlot& b = bodies[body];
  stepStart.bodies.push_back(stateOf(body, b));
  b.kept = true;
}

void detail::WorldState::saveStepStart() {
  // Room first: a failure here leaves everything as it was.
  stepStart.keepEach = def.mode != StepMode::Discrete;
  stepStart.keeping = false;
  stepStart.bodies.clear();
  if (!stepStart.keepEach && stepStart.motion.size() < bodies.size()) stepStart.motion.resize(bodies.size());
  stepStart.pendingSensorEvents = pendingSensorEvents;
  stepStart.squeezes = squeezes;
  stepStart.sensorOverlaps.clear();
  stepStart.dependents.clear();
  stepStart.time = time;
  stepStart.stats = stats;
  stepStart.active = true;
  stepStart.keeping = stepStart.keepEach;
}

void detail::WorldState::endStep() {
  stepStart.active = false;
  stepStart.keeping = false;
  if (stepStart.keepEach) {
    for (const BodyAtStepStart& s : stepStart.bodies) bodies[s.body].kept = false;
  }
  stepStart.sensorOverlaps.clear();  // frees the ended overlaps' nodes
  stepStart.dependents.clear();
}

void detail::WorldState::undoStep() {
  contactEvents.clear();  // a failed step reports no events
  sensorEvents.clear();
  if (!stepStart.active) return;  // saveStepStart failed: nothing else changed
  stepStart.active = false;
  stepStart.keeping = false;
  // Latest first: a body kept twice (a jam undone puts back a copy of its slot from before it was kept)
  // ends with its first record, from the step's start.
  for (auto it = stepStart.bodies.rbegin(); it != stepStart.bodies.rend(); ++it) {
    detail::BodySlot& b = bodies[it->body];
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
  if (!stepStart.keepEach) {
    // The discrete step moved these (discrete_step.cpp) and changed nothing else of a body that lasts.
    for (uint32_t i = 0; i < bodies.size(); ++i) {
      detail::BodySlot& b = bodies[i];
      if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
      b.position = stepStart.motion[i].first;
      b.velocity = stepStart.motion[i].second;
    }
  }
  time = stepStart.time;
  stats = stepStart.stats;
  pendingSensorEvents.swap(stepStart.pendingSensorEvents);
  squeezes.swap(stepStart.squeezes);
  // Newest first, so that each entry finds the map (and each list) as it was right after its change.
  for (auto it = stepStart.sensorOverlaps.rbegin(); it != stepStart.sensorOverlaps.rend(); ++it) {
    if (it->ended.empty()) {
      sensorOverlaps.erase(it->key);
    } else {
      sensorOverlaps.insert(std::move(it->ended));
    }
  }
  stepStart.sensorOverlaps.clear();
  // A list wakeUp emptied goes back whole; what a failed step added to it named bodies that are awake
  // again, and a list may name an awake body (wakeUp passes it over).
  for (auto it = stepStart.dependents.rbegin(); it != stepStart.dependents.rend(); ++it) {
    dependents[it->first] = std::move(it->second);
  }
  stepStart.dependents.clear();
  // Scratch whose invariants hold between calls.
  pathLog.active = false;
  // Caches of positions the step moved away from: void, rebuilt by the next step.
  broadPhase.forgetStep();
  if (stepper) stepper->forget();  // the event queues may be part built: the next step makes them afresh
  changes.structureChanged = true;
  ++changes.staticVersion;
}

}  // namespace rattle
