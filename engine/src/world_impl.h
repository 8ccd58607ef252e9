// Private: the world's storage, shared by world.cpp (creation, validation, accessors) and
// hybrid_step.cpp (the step).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "broad_phase.h"
#include "rattle/world.h"

namespace rattle {

namespace detail {

// The last collision a body took part in, within the current step. A pair that was resolved at an
// instant and whose bodies have done nothing since cannot be approaching at that instant; remembering it
// keeps round-off from reporting the same contact again at time zero.
struct LastContact {
  uint32_t fixtureLow = 0;
  uint32_t fixtureHigh = 0;
  int feature = -1;
  double time = -1;  // < 0: none this step
};

struct BodySlot {
  uint32_t generation = 1;
  bool alive = false;
  BodyType type = BodyType::Static;
  Vec2 position;  // at localTime within the current step (0 between steps)
  Vec2 velocity;
  double localTime = 0;
  double mass = std::numeric_limits<double>::infinity();
  double inverseMass = 0;
  uint64_t userData = 0;
  std::vector<uint32_t> fixtures;
  // Step-local state.
  uint32_t collisionCount = 0;  // bumps on every velocity change; predictions carry it to detect staleness
  LastContact last;
};

struct FixtureSlot {
  uint32_t generation = 1;
  bool alive = false;
  uint32_t body = 0;
  Geometry geometry;
  Box localBox;  // box of the geometry relative to the body's position
  double density = 1;
  double restitution = 0;
  bool sensor = false;
  Filter filter;
};

// A predicted collision. `a` is the fixture whose body was moving forward (a dynamic circle), `b` the
// other one; `normal` points from b toward a.
struct PredictedContact {
  double time;
  uint32_t a, b;
  int feature;
  uint32_t countA, countB;
  Vec2 point;
  Vec2 normal;
};

// Total order for the event queue: by time, then by fixture ids, then the rest, so no two distinct
// predictions compare equal and the processing order never depends on the heap's implementation.
inline bool later(const PredictedContact& x, const PredictedContact& y) {
  if (x.time != y.time) return x.time > y.time;
  const uint32_t xl = std::min(x.a, x.b), yl = std::min(y.a, y.b);
  if (xl != yl) return xl > yl;
  const uint32_t xh = std::max(x.a, x.b), yh = std::max(y.a, y.b);
  if (xh != yh) return xh > yh;
  if (x.feature != y.feature) return x.feature > y.feature;
  if (x.a != y.a) return x.a > y.a;
  if (x.countA != y.countA) return x.countA > y.countA;
  return x.countB > y.countB;
}

struct CandidatePair {
  uint32_t own;  // a fixture of the body whose list this is
  uint32_t other;
};

}  // namespace detail

struct World::Impl {
  WorldDef def;
  double time = 0;
  std::vector<detail::BodySlot> bodies;
  std::vector<uint32_t> freeBodies;  // reused last-freed first
  std::vector<detail::FixtureSlot> fixtures;
  std::vector<uint32_t> freeFixtures;
  int liveBodies = 0;
  detail::BroadPhase broadPhase;

  // Results of the last step.
  std::vector<ContactEvent> contactEvents;
  StepStats stats;

  // Step scratch, kept to reuse its memory.
  std::vector<std::vector<detail::CandidatePair>> pairsOfBody;  // by body index; dynamic bodies only
  std::vector<detail::PredictedContact> queue;                  // binary heap ordered by detail::later
  std::vector<uint32_t> stamp;                                  // by fixture index, for de-duplication
  uint32_t stampCounter = 0;

  detail::BodySlot& bodyOf(uint32_t fixture) { return bodies[fixtures[fixture].body]; }
  const detail::BodySlot& bodyOf(uint32_t fixture) const { return bodies[fixtures[fixture].body]; }
  bool moves(const detail::BodySlot& b) const { return b.type != BodyType::Static; }
  Box worldBox(uint32_t fixture) const { return fixtures[fixture].localBox.translated(bodyOf(fixture).position); }
  bool canCollide(uint32_t fa, uint32_t fb) const;
  void recomputeMass(detail::BodySlot& body);

  void stepHybrid(double dt);
  // hybrid_step.cpp
  Vec2 positionAt(const detail::BodySlot& b, double t) const { return b.position + b.velocity * (t - b.localTime); }
  void addPair(uint32_t fa, uint32_t fb);
  void predict(uint32_t own, uint32_t other, double now, double dt);
  void repredict(uint32_t body, double now, double dt);
  void advance(detail::BodySlot& b, double t);
  void resolve(const detail::PredictedContact& c);
};

}  // namespace rattle
