// The hybrid step (the default): swept boxes through sort-and-sweep, then exact events inside the step.
//
//  1. Every fixture of a moving body gets the box of its straight path over the step.
//  2. Sort-and-sweep turns overlapping boxes into candidate pairs (static-static, sensor and filtered
//     pairs never get this far).
//  3. Each candidate pair gets its exact time of impact within the step; the predictions go into one
//     queue ordered by time and then by ids.
//  4. Events are resolved in time order. A prediction carries the collision counters its bodies had when
//     it was made; when one has changed since, the prediction is stale and dropped (lazy invalidation:
//     Sedgewick & Wayne, Algorithms 6.1). After a collision the two bodies are predicted again from that
//     instant, and when a body's new path leaves the swept box the sweep saw, the broad phase is asked
//     again for it, so a path changed mid-step misses nothing.
//  5. Every body moves to the end of the step.
//
// Within a step each body keeps its position at its own local time (the time of its last collision), so
// bodies that do not collide are moved once per step and times stay in [0, dt] where they are precise.
#include <algorithm>
#include <cmath>

#include "rattle/time_of_impact.h"
#include "world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::PredictedContact;

void World::Impl::addPair(uint32_t fa, uint32_t fb) {
  const uint32_t ba = fixtures[fa].body, bb = fixtures[fb].body;
  if (bodies[ba].type == BodyType::Dynamic) pairsOfBody[ba].push_back({fa, fb});
  if (bodies[bb].type == BodyType::Dynamic) pairsOfBody[bb].push_back({fb, fa});
}

void World::Impl::predict(uint32_t own, uint32_t other, double now, double dt) {
  const BodySlot& a = bodyOf(own);
  const BodySlot& b = bodyOf(other);
  ++stats.timeOfImpactTests;

  // Round-off guard (see LastContact): if every dynamic body of the pair was last resolved against this
  // same pair at this same instant, the feature it touched cannot be approaching now.
  int excluded = kNoFeature;
  const uint32_t low = std::min(own, other), high = std::max(own, other);
  auto resolvedHereNow = [&](const BodySlot& s) {
    return s.type != BodyType::Dynamic ||
           (s.last.time == now && s.last.fixtureLow == low && s.last.fixtureHigh == high);
  };
  if (a.last.time == now && resolvedHereNow(a) && resolvedHereNow(b)) excluded = a.last.feature;

  const Vec2 pa = positionAt(a, now);
  const Vec2 pb = positionAt(b, now);
  auto impact = timeOfImpact(fixtures[own].geometry, pa, fixtures[other].geometry, pb, a.velocity - b.velocity,
                             dt - now, excluded);
  if (!impact) return;
  // The impact's point is in the frame where `other` rests; in the world it has moved with b.
  const double time = std::min(now + impact->time, dt);
  queue.push_back(PredictedContact{time, own, other, impact->feature, a.collisionCount, b.collisionCount,
                                   impact->point + b.velocity * impact->time, impact->normal});
  std::push_heap(queue.begin(), queue.end(), detail::later);
}

void World::Impl::repredict(uint32_t bodyIndex, double now, double dt) {
  BodySlot& body = bodies[bodyIndex];
  auto& pairs = pairsOfBody[bodyIndex];
  const Vec2 from = positionAt(body, now);
  const Vec2 to = from + body.velocity * (dt - now);
  const Box path{{std::min(from.x, to.x), std::min(from.y, to.y)}, {std::max(from.x, to.x), std::max(from.y, to.y)}};
  for (uint32_t f : body.fixtures) {
    const Box box{path.min + fixtures[f].localBox.min, path.max + fixtures[f].localBox.max};
    if (broadPhase.box(f).contains(box)) continue;
    // The new path leaves the swept box: grow it and ask the broad phase again.
    ++stats.requeries;
    broadPhase.grow(f, unionOf(broadPhase.box(f), box));
    ++stampCounter;
    for (const auto& p : pairs) {
      if (p.own == f) stamp[p.other] = stampCounter;
    }
    broadPhase.query(broadPhase.box(f), [&](uint32_t g) {
      if (stamp[g] == stampCounter || !canCollide(f, g)) return;
      stamp[g] = stampCounter;
      ++stats.candidatePairs;
      addPair(f, g);
    });
  }
  // `pairs` may have grown above (addPair); index, do not iterate by reference.
  for (size_t i = 0; i < pairs.size(); ++i) predict(pairs[i].own, pairs[i].other, now, dt);
}

void World::Impl::advance(BodySlot& b, double t) {
  if (b.type != BodyType::Dynamic) return;  // kinematic paths are evaluated from the step start
  b.position = positionAt(b, t);
  b.localTime = t;
}

void World::Impl::resolve(const PredictedContact& c) {
  const uint32_t ia = fixtures[c.a].body, ib = fixtures[c.b].body;
  BodySlot& a = bodies[ia];
  BodySlot& b = bodies[ib];
  advance(a, c.time);
  advance(b, c.time);

  // Impulse along the normal (Newton's restitution law): the normal speed after is -e times before.
  // j = -(1 + e) vn / (1/ma + 1/mb); static and kinematic bodies have 1/m = 0.
  const double vn = dot(a.velocity - b.velocity, c.normal);
  const double e = std::max(fixtures[c.a].restitution, fixtures[c.b].restitution);
  const double j = -(1 + e) * vn / (a.inverseMass + b.inverseMass);
  a.velocity += c.normal * (j * a.inverseMass);
  b.velocity -= c.normal * (j * b.inverseMass);

  const detail::LastContact last{std::min(c.a, c.b), std::max(c.a, c.b), c.feature, c.time};
  if (a.type == BodyType::Dynamic) {
    ++a.collisionCount;
    a.last = last;
  }
  if (b.type == BodyType::Dynamic) {
    ++b.collisionCount;
    b.last = last;
  }

  ContactEvent event;
  event.time = c.time;
  event.point = c.point;
  event.impulse = j;
  const bool aIsLower = c.a < c.b;
  const uint32_t fa = aIsLower ? c.a : c.b, fb = aIsLower ? c.b : c.a;
  event.fixtureA = {fa, fixtures[fa].generation};
  event.fixtureB = {fb, fixtures[fb].generation};
  event.bodyA = {fixtures[fa].body, bodies[fixtures[fa].body].generation};
  event.bodyB = {fixtures[fb].body, bodies[fixtures[fb].body].generation};
  event.normal = aIsLower ? -c.normal : c.normal;  // c.normal points from c.b toward c.a
  contactEvents.push_back(event);
}

void World::Impl::stepHybrid(double dt) {
  contactEvents.clear();
  stats = StepStats{};
  queue.clear();
  if (pairsOfBody.size() < bodies.size()) pairsOfBody.resize(bodies.size());
  if (stamp.size() < fixtures.size()) stamp.resize(fixtures.size(), 0);

  // 1. Swept boxes.
  for (uint32_t i = 0; i < bodies.size(); ++i) {
    BodySlot& b = bodies[i];
    if (!b.alive) continue;
    pairsOfBody[i].clear();
    b.localTime = 0;
    b.last = detail::LastContact{};
    if (!moves(b)) continue;
    const Vec2 to = b.position + b.velocity * dt;
    const Box path{{std::min(b.position.x, to.x), std::min(b.position.y, to.y)},
                   {std::max(b.position.x, to.x), std::max(b.position.y, to.y)}};
    for (uint32_t f : b.fixtures) {
      broadPhase.setBox(f, Box{path.min + fixtures[f].localBox.min, path.max + fixtures[f].localBox.max});
    }
  }

  // 2 and 3. Candidate pairs and their first predictions.
  broadPhase.findPairs([&](uint32_t fa, uint32_t fb) {
    if (!canCollide(fa, fb)) return;
    ++stats.candidatePairs;
    addPair(fa, fb);
    // Predict with the dynamic body's circle first (the time-of-impact functions' moving side).
    if (bodyOf(fa).type == BodyType::Dynamic) {
      predict(fa, fb, 0, dt);
    } else {
      predict(fb, fa, 0, dt);
    }
  });

  // 4. Events in time order.
  while (!queue.empty()) {
    std::pop_heap(queue.begin(), queue.end(), detail::later);
    const PredictedContact c = queue.back();
    queue.pop_back();
    const BodySlot& a = bodyOf(c.a);
    const BodySlot& b = bodyOf(c.b);
    if (a.collisionCount != c.countA || b.collisionCount != c.countB) {
      ++stats.staleEvents;
      continue;
    }
    // The prediction said "approaching"; if round-off in moving the bodies to this instant says
    // otherwise, there is nothing to resolve.
    if (!(dot(a.velocity - b.velocity, c.normal) < 0)) {
      ++stats.staleEvents;
      continue;
    }
    if (stats.eventsProcessed >= def.maxEventsPerStep) {
      stats.eventBudgetReached = true;
      break;
    }
    resolve(c);
    ++stats.eventsProcessed;
    const uint32_t ia = fixtures[c.a].body, ib = fixtures[c.b].body;
    if (bodies[ia].type == BodyType::Dynamic) repredict(ia, c.time, dt);
    if (bodies[ib].type == BodyType::Dynamic) repredict(ib, c.time, dt);
  }
  queue.clear();

  // 5. Everyone to the end of the step.
  for (BodySlot& b : bodies) {
    if (!b.alive || !moves(b)) continue;
    b.position = b.position + b.velocity * (dt - (b.type == BodyType::Dynamic ? b.localTime : 0.0));
    b.localTime = 0;
  }
  time += dt;
}

}  // namespace rattle
