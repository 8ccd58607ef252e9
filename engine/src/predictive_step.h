// Private: the predictive mode's state, kept from one step to the next (predictive_step.cpp).
//
// Event-driven molecular dynamics in the manner of Isobe (1999) and Smallenburg (2022):
//  - a uniform cell grid over the dynamic bodies (cell size >= the largest dynamic diameter), whose
//    border cells reach to infinity, so touching bodies are always in neighbouring cells;
//  - static fixtures listed in every cell they come within half a cell of;
//  - lazy per-body clocks (BodySlot::localTime): a body is moved only when it collides;
//  - one scheduled event per dynamic body (its earliest contact, slide end or cell crossing), in one
//    indexed heap ordered by time and then by ids; a partner's collision counter detects a prediction
//    that a later change made stale, and the body is then predicted again.
// Flat arrays indexed by body, cell or heap slot; nothing is allocated per event.
#pragma once

#include <cstdint>
#include <vector>

#include "rattle/types.h"
#include "rattle/vec2.h"

namespace rattle::detail {

enum class PredictiveKind : uint8_t { Contact = 0, SlideEnd = 1, Cross = 2, None = 255 };

// A body's one scheduled event. Contact: `a` is a fixture of the body, `b` the other fixture, `normal`
// from b toward a (as detail::PredictedContact). SlideEnd: `a` the body's first fixture, `b` its support.
// Cross: `a` = `b` = the body's primary fixture; `feature` the cell side it leaves (0: -x, 1: +x, 2: -y,
// 3: +y), or -1 for a mere horizon (the body is predicted again, its cell unchanged).
struct PredictiveEvent {
  double time = 0;  // from the start of the current step
  uint32_t a = 0, b = 0;
  int32_t feature = 0;
  uint32_t countA = 0, countB = 0;
  PredictiveKind kind = PredictiveKind::None;
  Vec2 point;
  Vec2 normal;
};

// A contact found not to be approaching (round-off) and dropped: the pair is left out of the body's
// predictions until either body's motion changes (as the hybrid step drops the prediction).
struct Dismissal {
  uint32_t own, other;
  uint32_t countOwn, countOther;
};

// What a body looked like at the end of the last step, to notice changes made between steps.
struct BodySnapshot {
  Vec2 position, velocity, acceleration;
  uint32_t generation = 0, collisionCount = 0, supportGeneration = 0, fixtureCount = 0;
  bool alive = false, asleep = false;
  BodyType type = BodyType::Static;
};

struct FixtureSnapshot {
  uint32_t generation = 0, body = 0;
  Filter filter;
  bool alive = false, sensor = false;
};

// The shape of a tracked dynamic body: its primary (first physical) fixture, and when that is its only
// physical fixture and a Circle, the circle, for the circle-circle fast path.
struct TrackedShape {
  Vec2 centre;        // the body's circles' common centre, relative to the body
  double radius = 0;  // of the primary fixture when `single`
  uint32_t fixture = 0;
  uint32_t categoryBits = 0, maskBits = 0;
  int32_t group = 0;
  bool single = false;  // one physical fixture, a Circle
};

struct HeapNode {
  double time;
  uint32_t body;
};

struct PredictiveState {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  bool valid = false;   // false: rebuild everything at the start of the next step
  double lastStep = 0;  // how far the last step moved the bodies' clocks (event times are rebased by it)

  // Per-step constants.
  double approachTolerance = 0;
  double restTolerance = 0;  // without the coordinate factor: 8 eps / dt
  double capTime = 1;        // longest horizon of a prediction when no cell crossing bounds it
  bool movingKinematic = false;

  // The grid. Cell (cx, cy) covers [x0 + cx s, x0 + (cx + 1) s) (and likewise in y), except that the
  // first and last cells of each row and column reach to infinity.
  double x0 = 0, y0 = 0, cellSize = 1;
  int32_t nx = 1, ny = 1;
  std::vector<int32_t> cellHead;      // first body in the cell, or -1
  std::vector<uint32_t> staticStart;  // CSR: static fixtures near cell c are staticList[staticStart[c] ..]
  std::vector<uint32_t> staticList;
  std::vector<uint32_t> kinematicFixtures;  // physical fixtures of kinematic bodies

  // Per body (indexed like World::Impl::bodies).
  std::vector<uint8_t> tracked;  // a dynamic body with a physical fixture: in the grid, may have an event
  std::vector<TrackedShape> shape;
  std::vector<int32_t> cx, cy;
  std::vector<int32_t> next, prev;  // the cell's list
  std::vector<PredictiveEvent> event;
  std::vector<int32_t> heapPos;  // -1: no event scheduled
  std::vector<std::vector<Dismissal>> dismissed;
  std::vector<uint32_t> dismissedBodies;  // bodies whose `dismissed` is not empty
  std::vector<BodySnapshot> bodySnapshot;
  std::vector<FixtureSnapshot> fixtureSnapshot;

  // The event queue: a binary heap of bodies, earliest event first.
  std::vector<HeapNode> heap;

  // Scratch.
  std::vector<uint32_t> dirty;
  std::vector<uint32_t> woken;
};

}  // namespace rattle::detail
