// The predictive mode: event-driven throughout. step(dt) processes every event up to the new time; a
// frame is only a time at which to look.
//
// The physics is the hybrid step's (hybrid_step.cpp): the same times of impact, the same round-off guard
// (LastContact), the same approach tolerance and absorption at pop, the same resolve() with its resting
// rules, the same slide ends and the same event budget. What differs is how the next event is found
// (event-driven molecular dynamics: Isobe 1999; Smallenburg, Eur. Phys. J. E 45, 22, 2022):
//  - Cell grid. Cells are at least as wide as the largest dynamic body, so two bodies that touch have
//    their centres in neighbouring cells; a body leaving its cell is an event (the first exit of a line
//    or a parabola from the cell, a little past its side), after which it is predicted against its new
//    neighbours. The grid is unbounded and folded onto a table that covers the bodies' region and the
//    static fixtures' (up to a limit); cells grow where bodies are sparse. Static fixtures are listed in
//    every cell they come within half a cell of (a long wall in many); kinematic bodies are few, and
//    every prediction looks at all of them.
//  - One scheduled event per body: the earliest of its contacts with its neighbours, its slide end and
//    its cell crossing, predicted no further than that crossing. A body whose motion changes is predicted
//    again at once against all its neighbours, so every pair's next contact is held by one of its two
//    bodies; a prediction whose partner has changed since (its collision counter moved on) is found stale
//    when it comes up, and its body is predicted again from then. A body at rest predicts only up to its
//    moving neighbours' own next events (they see it when they are predicted again).
//  - The queue is a calendar of buckets with a small heap for the current one; events are ordered by
//    (time, kind, ids), so ties resolve the same way on every run.
//  - Lazy clocks: a body keeps its position and velocity at the time of its last change (its local time)
//    and is moved only when it collides. At the end of a step every body is brought up to the new time (so
//    World::position reads it) and the clocks and queued times are re-based to the step's end, so times
//    stay small where they are precise.
//  - What predictions read is copied into compact records in cell order (PredictiveState::HotBody),
//    refreshed whenever a body changes; the BodySlot stays the truth, and resolve() works on it.
//  - Except in a plain world (every tracked body one circle on its centre with the default filter; no
//    gravity, no sensor, nobody asleep): there a collision of two disks is resolve() done on the compact
//    records (plain_collision.h, the same arithmetic, so the same bits), and the BodySlot catches up
//    (attach()) before anything else reads it and at the step's end. A gas then never touches its
//    192-byte BodySlots between the step's start and end.
//    There, too, a moving body is predicted by predictPlain(): pairPlain()'s tests with what they carry
//    from pair to pair in registers, in two passes (a branch-free one that keeps the neighbours that
//    approach and can meet in time, and one that seeks their times of impact, plain_disk_impact.h), the
//    contact point and normal worked out for the winner only. The same tests in the same order with
//    the same arithmetic, so the same event (tests/test_predictive_plain.cpp compares the two paths).
//  - Memory, not arithmetic, sets the pace at 10^5 bodies and more: the cell lists are linked through a
//    small array of their own, a body's neighbours are gathered (and their records asked for) before
//    they are tested (a collision's two bodies' both before it is resolved), the calendar reads its
//    buckets ahead in stages (entries, then the events' first records, then the cells around their
//    bodies) so that an event's records are in cache when it comes up, and the calendar's buckets reach
//    no further than the step's end. Branches that a predictor cannot guess (is a cell empty, does a
//    neighbour approach, which heap child is earliest) are taken without branching.
//  - Between steps the world may change (bodies created, destroyed, moved, given a velocity, woken; a
//    filter changed). The World API reports every change (detail::WorldState::touched), so a step costs nothing
//    for bodies nobody touched: a dynamic body that was changed is relocated and predicted again (its
//    counter is bumped so that predictions against its old path go stale); anything structural rebuilds
//    the grid and the queue, but keeps the grid's cells and its listing of static fixtures while no
//    static or kinematic fixture came or went and no static body moved (detail::ChangeLog::staticVersion): a
//    game firing shots on a large map does not list its walls again.
//
// Sensors: when the world has any, every change of a body's motion is recorded (PathLog), and the sensor
// events are found from those paths when the step's events are done (sensor_paths.cpp).
#include "predictive/predictive_step.h"

#include "hybrid/hybrid_state.h"
#include "hybrid/hybrid_step.h"
#include "predictive/predictive_engine.h"
#include "predictive/predictive_engine_inl.h"
#include "world/stepper.h"

namespace rattle::predictive {

double Engine::endPlain(double end, double& speed) {
  // The step's end in a plain world, for the tracked bodies: attach(), detail::WorldState::advance() to `end`,
  // the clocks re-based to it and sync(), in one pass over the copies instead of three passes (one over
  // all the BodySlots). Nobody accelerates but by the world's gravity (zero here), sleeps or slides, so
  // sync() would copy back exactly what is written here. Returns the largest coordinate; `speed` grows to
  // the largest speed.
  const Vec2 g = w_.def.gravity;  // every tracked body's BodySlot::acceleration (normalize())
  double extent = 0, speedSquared = 0;
  // Slots are in spatial order, BodySlots in creation order: the writes below go all over the bodies,
  // three lines of each (the motion, `last`, `lastContactTime`). Asked for this many slots ahead, they
  // are on their way together instead of each waiting for memory in turn.
  constexpr uint32_t kAhead = 16;
  const uint32_t n = static_cast<uint32_t>(s_.hot.size());
  for (uint32_t slot = 0; slot < n; ++slot) {
    if (slot + kAhead < n) {
      const char* ahead = reinterpret_cast<const char*>(&w_.bodies[s_.bodyOfSlot[slot + kAhead]]);
      __builtin_prefetch(ahead, 1);
      __builtin_prefetch(ahead + offsetof(BodySlot, last), 1);
      __builtin_prefetch(ahead + offsetof(BodySlot, lastContactTime), 1);
    }
    HotBody& h = s_.hot[slot];
    ColdBody& c = s_.cold[slot];
    BodySlot& b = w_.bodies[s_.bodyOfSlot[slot]];
    const Vec2 p = positionAt(h, g, end), v = velocityAt(h, g, end);
    double lastTime = c.lastTime;
    if (lastTime >= 0) lastTime -= end;
    b.position = h.position = p;
    b.velocity = h.velocity = v;
    b.localTime = h.localTime = 0;
    b.collisionCount = h.collisionCount;
    c.lastTime = lastTime;
    b.setLast(detail::LastContact{c.lastLow, c.lastHigh, c.lastFeature, lastTime});
    b.lastContactTime = c.lastContactTime;
    // The step's collision count starts again with the next step (normalize() does not run between plain
    // steps).
    b.stepCollisions = 0;
    c.stepCollisions = 0;
    h.flags = static_cast<uint8_t>(h.flags & ~HotBody::kDetached);
    extent = std::max({extent, std::fabs(p.x), std::fabs(p.y)});
    speedSquared = std::max(speedSquared, dot(v, v));
  }
  // The largest length(v): sqrt is correctly rounded and monotone, so the root of the largest v.v is the
  // largest of the roots, one root instead of one a body (as the hybrid step's speed scale).
  speed = std::max(speed, std::sqrt(speedSquared));
  return extent;
}

[[gnu::always_inline]] inline
void Engine::collidePlain(uint32_t i, uint32_t j, const PredictiveEvent& c, double tolerance) {
  // detail::resolve() for two plain disks, on their copies (plain_collision.h); the BodySlots
  // catch up in attach(). The contact event as resolve() writes it.
  const detail::PlainOutcome out =
      detail::resolvePlainDisks({s_.hot[i], s_.cold[i]}, {s_.hot[j], s_.cold[j]}, c, w_.time,
                                w_.def.collapseTime, tolerance, detail::collapseCollisions(w_.def.maxEventsPerStep));
  if (out.approachingAfter) {
    // As after resolve(): the guard does not hold for a pair left approaching.
    for (uint32_t k : {i, j}) {
      ColdBody& cold = s_.cold[k];
      const detail::LastContact none;
      cold.lastTime = none.time;
      cold.lastLow = none.fixtureLow;
      cold.lastHigh = none.fixtureHigh;
      cold.lastFeature = none.feature;
    }
  }
  if (!out.resolved) return;
  auto side = [&](uint32_t k) {
    return detail::ContactSide{s_.hot[k].fixture, s_.cold[k].fixtureGeneration, s_.bodyOfSlot[k],
                               s_.cold[k].bodyGeneration};
  };
  const ContactEvent event = detail::makeContactEvent(c.time, c.point, c.normal, out.impulse, side(i), side(j));
  std::vector<ContactEvent>& events = w_.contactEvents;
  if (events.size() == events.capacity()) {
    // Room for as many as this step is on course for (a quarter more), rather than doubling: a long step
    // of a gas reports millions, each doubling copies what came before into fresh memory, and the
    // system's first touch of fresh memory costs more than the copy. The rate is read once a
    // thousand are in; the room only changes speed.
    const double done = c.time / stepLength_;
    size_t room = std::max<size_t>(1024, 2 * events.capacity());
    if (events.size() >= 1024 && done > 1.0 / 256) {
      room = std::max(room, static_cast<size_t>(1.25 * static_cast<double>(events.size()) / done));
    }
    events.reserve(room);
  }
  events.push_back(event);
}

bool Engine::crowdedCell() const {
  // Cells are as wide as the largest body, so a cell holds a handful of bodies that do not overlap; only
  // bodies piled on each other put thousands in one (each of them then tests all the others).
  std::vector<uint32_t> count(s_.heads.size(), 0);
  for (uint32_t slot = 0; slot < s_.hot.size(); ++slot) {
    if (++count[s_.hot[slot].cell] > kCrowdedCell) return true;
  }
  return false;
}

double Engine::step(double dt) {
  if (!startStep(dt)) return 0;
  runEvents(dt);
  return finishStep(dt);
}

// 1. Notice what changed since the last step, re-base the clocks, predict what must be. False: a body is
// too fast for the grid, or a fresh grid too crowded; the step is the hybrid step's (nothing changed).
bool Engine::startStep(double dt) {
  stepLength_ = dt;
  w_.contactEvents.clear();
  w_.sensorEvents.clear();
  w_.sensorEvents.swap(w_.pendingSensorEvents);
  w_.stats = StepStats{};
  // The bodies' candidate pairs are read only by the resting rules and the Zeno guard, which need gravity
  // (fillPairs, detail::supportsAt): a world without it does not make them (a vector a body, fresh
  // memory written at the first step).
  if (!(w_.def.gravity == Vec2{}) && w_.pairsOfBody.size() < w_.bodies.size()) w_.pairsOfBody.resize(w_.bodies.size());

  // Re-base the clocks to this step's start. After a plain
  // world's step, with nothing touched since, normalize() would change nothing (no gravity, sleep or
  // slide; the Zeno count moves only under gravity) and its gathering was done by endPlain().
  if (s_.normalized && s_.valid && !w_.changes.structureChanged && w_.changes.touchedBodies.empty()) {
    speedScale_ = s_.nextSpeedScale;
    movingKinematic_ = s_.nextMovingKinematic;
    anyAsleep_ = anySliding_ = false;
  } else {
    normalize(dt);
  }
  s_.normalized = false;
  // What the World API changed since the last step (detail::WorldState::touched): the dynamic bodies touched are
  // predicted again; a change of structure starts afresh.
  bool rebuild = !s_.valid || w_.changes.structureChanged;
  s_.dirty.clear();
  if (!rebuild) {
    rebase(s_.lastStep);
    double extent = s_.endExtent;
    std::vector<uint32_t>& touched = w_.changes.touchedBodies;
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (uint32_t body : touched) {
      const BodySlot& b = w_.bodies[body];
      if (!b.alive || body >= s_.slotOfBody.size() || s_.slotOfBody[body] == PredictiveState::kNone) continue;
      extent = std::max({extent, std::fabs(b.position.x), std::fabs(b.position.y)});
      s_.dirty.push_back(s_.slotOfBody[body]);
    }
    // Bodies far beyond where the grid was made: its margins, sized for the round-off of coordinates
    // there, may be too thin here. Make it again.
    if (extent > 64 * s_.extent + s_.cellSize) rebuild = true;
  }
  if (rebuild) buildGrid();
  computeConstants(dt);
  if (speedScale_ * dt > kFollowCells * s_.cellSize || (rebuild && crowdedCell())) {
    // Undo what this step showed the caller (the pending sensor events go back), and start afresh after.
    w_.sensorEvents.swap(w_.pendingSensorEvents);
    s_.valid = false;
    s_.normalized = false;
    return false;
  }
  if (!rebuild && w_.changes.restitutionChanged) {
    for (uint32_t slot = 0; slot < s_.hot.size(); ++slot) {
      s_.cold[slot].restitution = w_.fixtures[s_.hot[slot].fixture].restitution;
    }
  }
  plainWorld_ = s_.plainShapes && w_.def.gravity == Vec2{} && w_.liveSensors == 0 && !anyAsleep_ && !anySliding_;
  if (rebuild) {
    queueing_ = false;  // retune() below queues them
    for (uint32_t slot = 0; slot < s_.hot.size(); ++slot) predictBody(slot, 0);
    queueing_ = true;
  } else {
    for (uint32_t slot : s_.dirty) {
      // Moved, given a velocity, woken or put to sleep from outside: predictions against its old path
      // go stale, and it is predicted afresh from where it is.
      BodySlot& b = w_.bodies[s_.bodyOfSlot[slot]];
      ++b.collisionCount;
      b.last = detail::LastContact{};
    }
    // The copies of the others are as the end of the last step left them.
    for (uint32_t slot : s_.dirty) sync(slot);
    for (uint32_t slot : s_.dirty) {
      unlink(slot);
      placeInCell(slot, centreOf(slot, s_.hot[slot].localTime));
      link(slot);
      clearDismissals(slot);
      predictBody(slot, 0);
    }
    // Contacts dropped as not approaching were dropped for that step only (as in the hybrid step).
    for (uint32_t slot : s_.dismissedSlots) {
      if (!dismissals(slot)) continue;
      clearDismissals(slot);
      predictBody(slot, 0);
    }
  }
  s_.dismissedSlots.clear();
  s_.stepEnd = dt;
  // The calendar is laid again from the step's start; its width is measured again once a quarter of the
  // bodies' worth of events went by since (short steps see few events each).
  retune(0, /*keepWidth=*/!rebuild && s_.popsSinceRetune < s_.hot.size() / 4);
  startPaths(w_);
  return true;
}

// 2. Events in time order, up to the step's end (or budgetTime_, at the event budget or when a pile or a
// jam is handed over: pile_).
void Engine::runEvents(double dt) {
  // Slots back in cell order (reorder()) once every body has had a few dozen events: by then a body of
  // a dense gas has moved about a cell, and the order has begun to fray (more often cost more than the
  // locality won: 4n pops was 4% slower on the 1e5-disk gas).
  const uint64_t reorderEvery = 16 * static_cast<uint64_t>(s_.hot.size()) + 1024;
  budgetTime_ = dt;
  pile_ = false;
  s_.absorbs.clear();
  s_.bursts.clear();
  // Without gravity, a cluster the game drives into itself is a jam that the hybrid step holds (jam.cpp):
  // handed over the same way when one of a contact's bodies is driven (handsOver).
  pilesForm_ = w_.def.restingSpeed > 0 && !(w_.def.gravity == Vec2{});
  jamsForm_ = w_.def.restingSpeed > 0 && w_.def.gravity == Vec2{};
  collapseLimit_ = static_cast<uint32_t>(detail::collapseCollisions(w_.def.maxEventsPerStep));
  const int64_t queueBudget = kQueueEventsPerEvent * int64_t{w_.def.maxEventsPerStep};
  int64_t queueEvents = 0;
  for (;;) {
    if (++s_.popsSinceReorder > reorderEvery) reorder();
    const uint32_t i = top();
    if (i == PredictiveState::kNone) break;
    const PredictiveEvent c = s_.event[i];
    if (!(c.time <= dt)) break;
    if (++queueEvents > queueBudget) {
      w_.stats.eventBudgetReached = true;
      budgetTime_ = lastChangeBefore(c.time);
      break;
    }
    // A heap grown large (events denser than the calendar was cut for): cut it again from here.
    if (++s_.popsSinceRetune > s_.hot.size() && s_.heap.size() > 4096) retune(c.time);
    const uint32_t j = c.kind == PredictiveKind::Contact ? c.partner : PredictiveState::kNone;
    // Every way on from here predicts `i` again (or ends the step, which then starts afresh).
    popped_ = i;
    // What comes next reads these; ask for them together (asked for already when the event's bucket was
    // read, top(), unless it went straight into the heap).
    prefetchNeighbourhood(i);
    __builtin_prefetch(&s_.cold[i]);
    if (j != PredictiveState::kNone) {
      __builtin_prefetch(&s_.hot[j]);
      prefetchNeighbourhood(j);
    }

    if (c.kind == PredictiveKind::Cross) {
      crossCell(i, c);
      continue;
    }
    if (c.kind == PredictiveKind::SlideEnd) {
      endSlide(i, c);
      continue;
    }
    if (!collideAt(i, j, c)) break;
  }
}

// A cell crossing: the body moves to its neighbour cell, and is predicted there.
[[gnu::always_inline]] inline void Engine::crossCell(uint32_t i, const PredictiveEvent& c) {
  if (c.feature >= 0) {
    unlink(i);
    ColdBody& cell = s_.cold[i];
    if (c.feature == 0) {
      --cell.cx;
    } else if (c.feature == 1) {
      ++cell.cx;
    } else if (c.feature == 2) {
      --cell.cy;
    } else {
      ++cell.cy;
    }
    setCell(i);
    link(i);
  }
  predictBody(i, c.time);
}

// The end of a slide: the body leaves the face and falls freely from here.
[[gnu::always_inline]] inline void Engine::endSlide(uint32_t i, const PredictiveEvent& c) {
  const uint32_t ia = s_.bodyOfSlot[i];
  attach(i);
  BodySlot& a = w_.bodies[ia];
  if (!a.sliding) {
    ++w_.stats.staleEvents;
    predictBody(i, c.time);
    return;
  }
  w_.advance(a, c.time);
  stopSliding(w_, a);
  ++a.collisionCount;
  sync(i);
  predictBody(i, c.time);
}

// Whether a contact whose bodies collided at most `most` times this step (either of them driven or not)
// ends the predictive part of the step: a pile, a driven jam, or an inelastic collapse, where the collapse
// guard would make its collisions elastic (jam.cpp).
bool Engine::handsOver(uint32_t most, bool driven) const {
  return most > kPileCollisions && (pilesForm_ || (jamsForm_ && (driven || most > collapseLimit_)));
}

// Counts a collision of `body` at `time` (its stepCollisions-th in the step) for the rule of
// kBurstFollow: the hybrid step's Islands::collapsing. A crowd of 150 nobody drives, crushed against a
// wall by a gate, collapsed in a cluster of seven disks with thousands of collisions each within 2% of
// the step, some 3e-7 s apart, until the collapse guard's count. A gas body's collisions are a mean free
// time apart, and it rarely passes kBurstFollow in a step.
bool Engine::collapsing(uint32_t body, uint32_t stepCollisions, double time) {
  if (stepCollisions <= static_cast<uint32_t>(kBurstFollow)) return false;
  PredictiveState::Burst burst = s_.bursts.get(body);
  const bool close = burst.count > 0 && time - burst.time <= detail::Islands::kBurstWindow * stepLength_;
  burst.count = close ? burst.count + 1 : 1;
  burst.time = time;
  s_.bursts.set(body, burst);
  return burst.count > static_cast<uint32_t>(kBurstCollisions);
}

// A contact that does not approach (beyond round-off) and that nothing presses: not a collision. Its
// tiny approach is absorbed while the pair moves (the hybrid step's dismissContact), or the pair is
// dismissed for the step (dismissals) and predicted again without it. False: a jam is handed over
// (kJamAbsorbs; pile_).
bool Engine::absorbOrDismiss(uint32_t i, uint32_t j, const PredictiveEvent& c, const detail::PredictedContact& contact,
                             double vn, double speed, double velocityScale, double restTol) {
  const uint32_t countA = contact.countA;
  ++w_.stats.staleEvents;
  if (vn < -detail::kAbsorbRoundOff * velocityScale && speed > restTol && w_.stats.eventsProcessed < w_.def.maxEventsPerStep &&
      stepAbsorbs_ < detail::collapseCollisions(w_.def.maxEventsPerStep)) {
    // A crowd of 150 that a piston crushed against a wall, left alone, spent 62,500 absorbs of a step
    // (the step's cap, below) among seven disks at one instant, 1e-12 s apart, each at an approach of
    // 1e-16 to 1e-13 that the last left its neighbours (tests: Squeeze.APistonClosingOnACrowdThatFills-
    // TheGapPassesOverIt). The hybrid step's islands hold such a cluster by a solve.
    if (pilesForm_ || jamsForm_) {
      int most = 0;
      for (const uint32_t slot : {i, j}) {
        if (slot == PredictiveState::kNone) continue;
        const uint32_t body = s_.bodyOfSlot[slot];
        const uint16_t count = s_.absorbs.get(body);
        if (count < UINT16_MAX) s_.absorbs.set(body, static_cast<uint16_t>(count + 1));
        most = std::max<int>(most, count + 1);
      }
      if (most > kJamAbsorbs) {
        pile_ = true;
        budgetTime_ = c.time;
        return false;
      }
    }
    ++stepAbsorbs_;
    attach(i);
    if (j != PredictiveState::kNone) attach(j);
    absorb(w_, contact, vn);
    ++w_.stats.eventsProcessed;
    sync(i);
    if (j != PredictiveState::kNone) sync(j);
    predictBody(i, c.time);
    if (j != PredictiveState::kNone) predictBody(j, c.time);
  } else {
    // At rest by the tolerance: a point moving into a static face stops (resting.cpp).
    if (!(speed > restTol) && vn < 0 && w_.stats.eventsProcessed < w_.def.maxEventsPerStep) {
      attach(i);
      if (stopPointAtRest(w_, contact, vn)) {
        ++w_.stats.eventsProcessed;
        sync(i);
        predictBody(i, c.time);
        return true;
      }
    }
    if (!dismissals(i)) s_.dismissedSlots.push_back(i);
    s_.hot[i].flags |= HotBody::kDismissals;
    // Only entries that still hold are kept (a body at rest in a pile is dismissed again and again).
    if (s_.dismissed.size() < s_.hot.size()) s_.dismissed.resize(s_.hot.size());
    auto& list = s_.dismissed[i];
    list.erase(std::remove_if(list.begin(), list.end(),
                              [&](const detail::Dismissal& d) {
                                return d.countOwn != countA || d.countOther != countOf(d.other);
                              }),
               list.end());
    list.push_back({c.a, c.b, countA, c.countB, c.feature});
    predictBody(i, c.time);
  }
  return true;
}

// A collision of two plain disks in a plain world (no gravity, sensors, sleep or slides), on the copies
// (collidePlain). False: a jam is handed over (pile_).
bool Engine::collidePlainPair(uint32_t i, uint32_t j, const PredictiveEvent& c, double tolerance) {
  // (No gravity here, so no pile: only a jam hands over.)
  const uint32_t collisionsI = s_.cold[i].stepCollisions, collisionsJ = s_.cold[j].stepCollisions;
  const uint32_t bodyI = s_.bodyOfSlot[i], bodyJ = s_.bodyOfSlot[j];
  if (jamsForm_) {
    // Each body's burst is followed, so both are asked, whatever the first says.
    const bool collapseI = collapsing(bodyI, collisionsI, c.time);
    const bool collapseJ = collapsing(bodyJ, collisionsJ, c.time);
    const bool driven = collapseI || collapseJ || w_.bodies[bodyI].driven || w_.bodies[bodyJ].driven;
    if (handsOver(std::max(collisionsI, collisionsJ), driven)) {
      pile_ = true;
      budgetTime_ = c.time;
      return false;
    }
  }
  // Both bodies' neighbours are gathered first, which asks for their records, so that they arrive
  // while the collision is resolved (it moves no body between cells).
  uint32_t aroundI[kNeighbourBuffer], aroundJ[kNeighbourBuffer];
  const size_t countI = gatherNeighbours(i, aroundI, kNeighbourBuffer);
  const size_t countJ = gatherNeighbours(j, aroundJ, kNeighbourBuffer);
  collidePlain(i, j, c, tolerance);
  ++w_.stats.eventsProcessed;
  if (predictsPlain(i)) {
    predictPlainAmong(i, c.time, aroundI, countI);
  } else {
    predictBody(i, c.time);
  }
  if (predictsPlain(j)) {
    predictPlainAmong(j, c.time, aroundJ, countJ);
  } else {
    predictBody(j, c.time);
  }
  return true;
}

// A contact: stale, dismissed or absorbed (not approaching), or a collision. False: the step stops here
// (the event budget, or a pile or a jam handed over: budgetTime_, pile_).
[[gnu::always_inline]] inline bool Engine::collideAt(uint32_t i, uint32_t j, const PredictiveEvent& c) {
  const double restTolerance = s_.restTolerance;
  const double approachTolerance = s_.approachTolerance;
  // A contact. Static and kinematic bodies never change their counters; the body's own event is never
  // stale (PredictiveEvent).
  const uint32_t countA = s_.hot[i].collisionCount;
  if (j != PredictiveState::kNone && s_.hot[j].collisionCount != c.countB) {
    ++w_.stats.staleEvents;
    predictBody(i, c.time);
    return true;
  }
  if (j != PredictiveState::kNone) __builtin_prefetch(&s_.cold[j]);
  // The hybrid step's check at pop: an approach no faster than round-off, with nothing pressing the two
  // together, is not a collision. It is absorbed when the bodies still move, or else dropped.
  Vec2 relativeVelocity, relativeAcceleration;
  double velocityScale = 0;  // |v_a| + |v_b|: the round-off of the relative velocity (as the hybrid step)
  {
    const HotBody& ha = s_.hot[i];
    const Vec2 accA = accelerationOf(ha, s_.rare[i]);
    if (j != PredictiveState::kNone) {
      const HotBody& hb = s_.hot[j];
      const Vec2 accB = accelerationOf(hb, s_.rare[j]);
      relativeVelocity = velocityAt(ha, accA, c.time) - velocityAt(hb, accB, c.time);
      relativeAcceleration = accA - accB;
      velocityScale = length(velocityAt(ha, accA, c.time)) + length(velocityAt(hb, accB, c.time));
    } else {
      const BodySlot& b = w_.bodyOf(c.b);
      relativeVelocity = velocityAt(ha, accA, c.time) - w_.velocityAt(b, c.time);
      relativeAcceleration = accA - b.acceleration;
      velocityScale = length(velocityAt(ha, accA, c.time)) + length(w_.velocityAt(b, c.time));
    }
  }
  const detail::PredictedContact contact{
      c.time, detail::EventKind::Contact, false, c.a, c.b, c.feature, countA, c.countB, c.point, c.normal};
  const double vn = dot(relativeVelocity, c.normal);
  const bool pressing = detail::pressedTogether(relativeAcceleration, c.normal);
  const double restTol = restTolerance * (std::fabs(c.point.x) + std::fabs(c.point.y));
  const double tolerance = approachTolerance + restTol;
  if (!(vn < -tolerance) && !pressing) {
    return absorbOrDismiss(i, j, c, contact, vn, length(relativeVelocity), velocityScale, restTol);
  }
  if (w_.stats.eventsProcessed >= w_.def.maxEventsPerStep) {
    w_.stats.eventBudgetReached = true;
    budgetTime_ = lastChangeBefore(c.time);
    return false;
  }
  if (plainWorld_ && j != PredictiveState::kNone) return collidePlainPair(i, j, c, tolerance);
  const uint32_t ia = s_.bodyOfSlot[i];
  attach(i);
  if (j != PredictiveState::kNone) attach(j);
  // The resting rules look at the bodies' candidate pairs.
  if (w_.def.restingSpeed > 0 && !(w_.def.gravity == Vec2{})) {
    fillPairs(i);
    if (j != PredictiveState::kNone) fillPairs(j);
  }
  const detail::BodySlot* partner = j != PredictiveState::kNone ? &w_.bodies[s_.bodyOfSlot[j]] : nullptr;
  const int most = std::max(w_.bodies[ia].stepCollisions, partner != nullptr ? partner->stepCollisions : 0);
  bool driven = jamsAsDriven(w_, ia) || (partner != nullptr && jamsAsDriven(w_, s_.bodyOfSlot[j]));
  if (jamsForm_) {
    // Both followed (collapsing), whatever the other says.
    auto stepCount = [](const detail::BodySlot& b) { return static_cast<uint32_t>(std::max(b.stepCollisions, 0)); };
    const bool collapseA = collapsing(ia, stepCount(w_.bodies[ia]), c.time);
    const bool collapseB = partner != nullptr && collapsing(s_.bodyOfSlot[j], stepCount(*partner), c.time);
    driven = driven || collapseA || collapseB;
  }
  if (handsOver(static_cast<uint32_t>(std::max(most, 0)), driven)) {
    pile_ = true;
    budgetTime_ = c.time;
    return false;
  }
  if (squeezeAt(w_, contact)) {
    ++w_.stats.eventsProcessed;
    sync(i);
    predictBody(i, c.time);
    // Two dynamic bodies that pass through each other (squeeze.cpp: passesThrough); either may have
    // stopped moving into a wall.
    if (j != PredictiveState::kNone && w_.bodies[s_.bodyOfSlot[j]].type == BodyType::Dynamic) {
      sync(j);
      predictBody(j, c.time);
    }
    return true;
  }
  s_.woken.clear();
  resolve(w_, contact, s_.woken, /*zenoGuard=*/true);
  ++w_.stats.eventsProcessed;
  {
    // The round-off guard (LastContact) takes a pair just resolved to be separating. When the resolution
    // left it approaching after all (a body put back to sleep after sharing the impulse), that is not
    // so: drop the guard for it, and the pair's next prediction finds the contact again, now. (The
    // hybrid step does the same at its next step, which starts without guards.)
    BodySlot& ba = w_.bodies[ia];
    BodySlot& bb = w_.bodyOf(c.b);
    const double after = dot(w_.velocityAt(ba, c.time) - w_.velocityAt(bb, c.time), c.normal);
    if (after < -tolerance) {
      for (BodySlot* body : {&ba, &bb}) {
        if (body->type == BodyType::Dynamic) body->last = detail::LastContact{};
      }
    }
  }
  sync(i);
  if (j != PredictiveState::kNone) sync(j);
  if (!s_.woken.empty()) {
    const uint32_t ib = w_.fixtures[c.b].body;
    for (uint32_t k : s_.woken) {
      if (k == ia || k == ib) continue;
      // Asleep until now, so at rest where it lies: its clock starts here.
      w_.bodies[k].localTime = c.time;
      syncBody(k);
    }
    for (uint32_t k : s_.woken) {
      const uint32_t slot = s_.slotOfBody[k];
      if (k != ia && k != ib && slot != PredictiveState::kNone) predictBody(slot, c.time);
    }
  }
  predictBody(i, c.time);
  if (j != PredictiveState::kNone) predictBody(j, c.time);
  return true;
}

// Where a step out of budget stops, as the hybrid step's HybridStep::lastChangeBefore (why there): the latest
// instant at which an event changed a body's motion, not the time `next` of the event it could not take.
// The copies are the truth for tracked bodies (a plain collision leaves the BodySlot behind, attach()).
double Engine::lastChangeBefore(double next) const {
  double last = 0;
  for (const HotBody& h : s_.hot) last = std::max(last, h.localTime);
  for (uint32_t body : s_.untracked) {
    const BodySlot& b = w_.bodies[body];
    if (b.type == BodyType::Dynamic) last = std::max(last, b.localTime);
  }
  return std::min(last, next);
}

// 3. Sensor events, from the paths the bodies took. Then every body to the end of the step (out of
// budget: to the last change of motion before it ran out, as the hybrid step does); the clocks start
// again from there.
double Engine::finishStep(double dt) {
  const bool pile = pile_;
  const double end = w_.stats.eventBudgetReached || pile ? budgetTime_ : dt;
  if (w_.pathLog.active) {
    sensePaths(w_, w_.pathLog, end);
    w_.pathLog.active = false;
  }
  // The pass below changes every body. Nothing after it allocates, but for a pile handed over to the
  // hybrid step, whose rest of the step may still fail: then every body is kept first (step_undo.cpp).
  if (pile) {
    for (uint32_t body = 0; body < w_.bodies.size(); ++body) w_.keep(body);
  } else {
    w_.stepStart.keeping = false;
  }
  double extent = 0;
  auto toEnd = [&](BodySlot& b) {
    if (b.type == BodyType::Dynamic) {
      w_.advance(b, end);
      if (b.asleep) ++w_.stats.sleeping;
      b.stepCollisions = 0;  // as in endPlain(): the copies take it in sync()
    } else {
      b.position = b.position + b.velocity * end;
    }
    b.localTime = 0;
    if (b.last.time >= 0) b.last.time -= end;  // the next step starts at this one's end
    extent = std::max({extent, std::fabs(b.position.x), std::fabs(b.position.y)});
  };
  if (plainWorld_) {
    // normalize()'s gathering for the next step: the speed scale (every acceleration is zero: its term,
    // |a| dt, adds nothing) and whether a kinematic body with a fixture moves.
    double speed = 0;
    extent = endPlain(end, speed);
    bool movingKinematic = false, accelerating = false;
    for (uint32_t body : s_.untracked) {
      BodySlot& b = w_.bodies[body];
      toEnd(b);
      speed = std::max(speed, length(b.velocity));
      if (b.type == BodyType::Kinematic && !(b.velocity == Vec2{}) && !b.fixtures.empty()) movingKinematic = true;
      if (!(b.acceleration == Vec2{})) accelerating = true;
    }
    s_.normalized = !accelerating;
    s_.nextSpeedScale = speed;
    s_.nextMovingKinematic = movingKinematic;
  } else {
    for (uint32_t slot = 0; slot < s_.hot.size(); ++slot) attach(slot);
    for (BodySlot& b : w_.bodies) {
      if (b.alive && b.type != BodyType::Static) toEnd(b);
    }
    for (uint32_t slot = 0; slot < s_.hot.size(); ++slot) sync(slot);
  }
  s_.lastStep = end;
  s_.endExtent = extent;
  if (pile) {
    // The caller goes on from `end`; the grid is made again when the predictive mode takes over again.
    w_.time += end;
    s_.valid = false;
    return end;
  }
  w_.time += dt;
  // Cut short, the bodies lost the rest of the step: every prediction is off; start afresh.
  if (w_.stats.eventBudgetReached) s_.valid = false;
  return dt;
}

}  // namespace rattle::predictive

namespace rattle {
namespace {

using predictive::Engine;

// The predictive mode's stepper: its state (the cell grid and the event queue) lasts from one step to the
// next, and a pile it hands over goes to the hybrid step for the rest of the step.
class PredictiveStepper final : public detail::Stepper {
 public:
  explicit PredictiveStepper(detail::WorldState& world) : w_(world), hybrid_(world) {}
  void step(double dt) override;
  void forget() override {
    state_.reset();
    hybrid_.forget();
  }
  detail::Islands* islands() override { return &hybrid_.islands; }

 private:
  detail::WorldState& w_;
  std::unique_ptr<detail::PredictiveState> state_;
  detail::HybridState hybrid_;  // for the steps and rests of steps it hands over to the hybrid step
};

bool anyHeld(const detail::WorldState& w) {
  return std::any_of(w.bodies.begin(), w.bodies.end(), [](const detail::BodySlot& b) { return b.alive && b.stepped; });
}

void PredictiveStepper::step(double dt) {
  detail::WorldState& w = w_;
  hybrid_.islands.beginStep();
  if (!state_) {
    // The first step, or the first after one that failed (step_undo.cpp): the grid and the queue are
    // made afresh, and a pile still held by stepped islands stays with the hybrid step (below).
    state_ = std::make_unique<detail::PredictiveState>();
    state_->pileHeld = anyHeld(w);
  }
  detail::PredictiveState& s = *state_;
  // A pile handed over (kPileCollisions) stays with the hybrid step while its islands hold anybody.
  if (!s.pileHeld) {
    const double done = Engine(w, s).step(dt);
    if (done == dt) return;
    if (done > 0) {
      // The rest of the step from `done` on, as a hybrid step of its own whose events and stats join
      // this step's, and whose budget is what this step's events left of it; the world's clock ends at
      // exactly time + dt, as after any step.
      const double startTime = w.time - done;
      std::vector<ContactEvent> contacts = std::move(w.contactEvents);
      std::vector<SensorEvent> sensed = std::move(w.sensorEvents);
      const StepStats first = w.stats;
      detail::stepHybrid(w, hybrid_, dt - done, first.eventsProcessed);
      for (ContactEvent& e : w.contactEvents) e.time += done;
      for (SensorEvent& e : w.sensorEvents) e.time += done;
      contacts.insert(contacts.end(), w.contactEvents.begin(), w.contactEvents.end());
      sensed.insert(sensed.end(), w.sensorEvents.begin(), w.sensorEvents.end());
      w.contactEvents = std::move(contacts);
      w.sensorEvents = std::move(sensed);
      w.stats.candidatePairs += first.candidatePairs;
      w.stats.timeOfImpactTests += first.timeOfImpactTests;
      w.stats.staleEvents += first.staleEvents;
      w.stats.requeries += first.requeries;
      w.stats.squeezes += first.squeezes;
      w.time = startTime + dt;
      s.pileHeld = true;
    } else {
      // Too fast for the grid: the hybrid step has the same physics and sweeps each path whole.
      detail::stepHybrid(w, hybrid_, dt);
    }
  } else {
    detail::stepHybrid(w, hybrid_, dt);
  }
  // Back to events once nobody is held in an island (the grid is made afresh then: s.valid is false).
  s.pileHeld = anyHeld(w);
}

}  // namespace

std::unique_ptr<detail::Stepper> detail::makePredictiveStepper(detail::WorldState& world) {
  return std::make_unique<PredictiveStepper>(world);
}

}  // namespace rattle
