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
//    neighbours. The grid is unbounded and folded onto a table; cells grow where bodies are sparse.
//    Static fixtures are listed in every cell they come within half a cell of (a long wall in many);
//    kinematic bodies are few, and every prediction looks at all of them.
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
//    240-byte BodySlots between the step's start and end.
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
//    filter changed). The World API reports every change (World::Impl::touched), so a step costs nothing
//    for bodies nobody touched: a dynamic body that was changed is relocated and predicted again (its
//    counter is bumped so that predictions against its old path go stale); anything structural rebuilds
//    the grid and the queue.
//
// Sensors: when the world has any, every change of a body's motion is recorded (PathLog), and the sensor
// events are found from those paths when the step's events are done (sensor_paths.cpp).
#include "predictive_step.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "closest_point.h"
#include "plain_collision.h"
#include "plain_disk_impact.h"
#include "rattle/time_of_impact.h"
#include "world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::PathLog;
using detail::PredictiveEvent;
using detail::PredictiveKind;
using detail::PredictiveState;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();

// The total order of events: by time, then kind, then ids (as detail::later, of which this is the
// reverse for contacts), so no two distinct events compare equal.
bool earlier(const PredictiveEvent& x, const PredictiveEvent& y) {
  if (x.time != y.time) return x.time < y.time;
  if (x.kind != y.kind) return x.kind < y.kind;
  const uint32_t xl = std::min(x.a, x.b), yl = std::min(y.a, y.b);
  if (xl != yl) return xl < yl;
  const uint32_t xh = std::max(x.a, x.b), yh = std::max(y.a, y.b);
  if (xh != yh) return xh < yh;
  if (x.feature != y.feature) return x.feature < y.feature;
  if (x.a != y.a) return x.a < y.a;
  return x.countB < y.countB;
}

// The first h >= 0 at which s(h) = c + b h + A h^2, positive inside a cell, turns negative: when a
// coordinate moving along a line or a parabola leaves the cell through one side. Outside already
// (c <= 0) and moving out: now. Roots in cancellation-free forms. +infinity when it never leaves.
double exitTime(double c, double b, double A) {
  if (A == 0) {
    if (!(b < 0)) return kInf;
    return c <= 0 ? 0.0 : c / -b;
  }
  if (c <= 0) {
    if (b < 0) return 0.0;
    if (A > 0) return kInf;  // coming back in, and pulled further in
    // Moving in, pulled out: it leaves at the larger root, or at once if it never gets inside.
    const double disc = b * b - 4 * A * c;
    if (!(disc > 0)) return 0.0;
    return (b + std::sqrt(disc)) / (-2 * A);
  }
  if (A > 0) {
    if (!(b < 0)) return kInf;
    const double disc = b * b - 4 * A * c;
    if (!(disc > 0)) return kInf;
    return 2 * c / (-b + std::sqrt(disc));
  }
  // Inside, pulled out: exactly one positive root.
  const double disc = b * b - 4 * A * c;
  if (b >= 0) return (b + std::sqrt(disc)) / (-2 * A);
  return 2 * c / (-b + std::sqrt(disc));
}


// The furthest a plain pair's time of impact is sought from `now` while the best event so far is at
// `best`, within the body's `horizon`: an impact later than this is past `best` even after rounding
// now + h (the margin covers the round-off of best - now and of now + h), and the time of impact depends
// on its limit only through the final t <= maxTime. The last term keeps a time of impact that would
// underflow to 0 (best = now = 0) from being cut.
double searchBound(double horizon, double best, double now) {
  return std::min(horizon - now, (best - now) * (1 + 1e-9) + 8 * kEps * (std::fabs(best) + std::fabs(now)) + 1e-300);
}

// Neighbours of one body held on the stack; more (a crowd in a few cells) go to a vector. At least the
// nine cells' heads (Engine::gatherNeighbours).
constexpr size_t kNeighbourBuffer = 128;
static_assert(kNeighbourBuffer >= 9);

// PredictiveState::heads: an entry's first slot, and the entry for a first slot (-1: none) and whether
// more follow.
int32_t headSlot(int32_t entry) { return entry < 0 ? -1 : entry >> 1; }
int32_t headEntry(int32_t slot, bool more) { return slot < 0 ? -1 : 2 * slot + (more ? 1 : 0); }

// Cell coordinates are clamped to +-kMaxCoord; the cells there reach to infinity.
constexpr int32_t kMaxCoord = int32_t{1} << 30;

int32_t cellCoord(double x, double origin, double size) {
  const double k = std::floor((x - origin) / size);
  if (k != k) return 0;  // NaN
  if (k <= -kMaxCoord) return -kMaxCoord;
  if (k >= kMaxCoord) return kMaxCoord;
  return static_cast<int32_t>(k);
}

using detail::ColdBody;
using detail::HotBody;

// Motion of a hot copy: the same expressions as World::Impl::positionAt and velocityAt, so the same
// values (the acceleration is read only when it is not zero).
Vec2 accelerationOf(const HotBody& h, const detail::RareBody& r) {
  return (h.flags & HotBody::kAccelerating) ? r.acceleration : Vec2{};
}
using detail::positionAt;
using detail::velocityAt;
bool isMoving(const HotBody& b) { return !(b.velocity == Vec2{}) || (b.flags & HotBody::kAccelerating) != 0; }
// The common body of a gas: one circle centred on the body, no acceleration, the default filter. Two such
// bodies need nothing from their ColdBody until a contact is found (Engine::pairPlain).
bool isPlain(const HotBody& b) {
  constexpr uint8_t mask = HotBody::kSingle | HotBody::kAccelerating | HotBody::kOffCentre | HotBody::kCustomFilter;
  return (b.flags & mask) == HotBody::kSingle;
}

// A body being predicted, as every pair test reads it.
struct Predicting {
  uint32_t slot;
  double now;
  Vec2 position, velocity, acceleration, centre;  // at `now`
  const HotBody* hot;
  const ColdBody* cold;
};

// The predictive step over a World::Impl (a template only so that this file can name the world's
// private implementation type through a parameter). Indices named `i`, `j`, `slot` are slots of tracked
// bodies (PredictiveState); `body` is an index into World::Impl::bodies.
template <class W>
class Engine {
 public:
  Engine(W& w, PredictiveState& s) : w_(w), s_(s) {}
  void step(double dt);

 private:
  W& w_;
  PredictiveState& s_;
  // The slot whose event was just taken from the queue and is being handled. Its entry stays in the heap
  // until the body's next prediction replaces it in place (one sift instead of a removal and an
  // insertion); until then it counts as having no event.
  uint32_t popped_ = PredictiveState::kNone;
  // Gathered by normalize() for computeConstants(): the fastest body's speed scale, and whether a
  // kinematic body with a fixture moves.
  double speedScale_ = 0;
  bool movingKinematic_ = false;
  bool anyAsleep_ = false, anySliding_ = false;  // among dynamic bodies, gathered by normalize() too
  // This step resolves collisions of two plain disks on the copies (plain_collision.h): every tracked
  // body is plain, and there is no gravity, no sensor and nobody asleep or sliding.
  bool plainWorld_ = false;
  // False while a fresh grid's bodies are first predicted: their events are only written, and retune()
  // then queues them all at once (a calendar cut for them), instead of each being queued twice.
  bool queueing_ = true;
  double stepLength_ = 1;  // this step's dt

  // Setup.
  void normalize(double dt);
  void rebase(double by);
  void computeConstants(double dt);
  void buildGrid();
  double sceneExtent() const;
  double meanNeighbours(double size) const;
  double sparseCellSize(double size, double limit) const;
  void reorder(bool fresh = false);
  void sync(uint32_t slot);
  void attach(uint32_t slot);
  void attachFixture(uint32_t fixture) {
    const uint32_t slot = s_.slotOfBody[w_.fixtures[fixture].body];
    if (slot != PredictiveState::kNone) attach(slot);
  }
  // A fixture's body's collision counter: the copy's for a tracked body (its BodySlot may lag).
  uint32_t countOf(uint32_t fixture) const {
    const uint32_t body = w_.fixtures[fixture].body;
    const uint32_t slot = s_.slotOfBody[body];
    return slot != PredictiveState::kNone ? s_.hot[slot].collisionCount : w_.bodies[body].collisionCount;
  }
  void collidePlain(uint32_t i, uint32_t j, const PredictiveEvent& c, double tolerance);
  double endPlain(double end, double& speed);
  void syncBody(uint32_t body) {
    const uint32_t slot = s_.slotOfBody[body];
    if (slot != PredictiveState::kNone) sync(slot);
  }

  // The grid.
  Vec2 centreOf(uint32_t slot, double now) const {
    const HotBody& h = s_.hot[slot];
    return positionAt(h, accelerationOf(h, s_.rare[slot]), now) + s_.rare[slot].centre;
  }
  // The table entry of cell (x, y) (PredictiveState::heads): the parts of a column and of a row, which add
  // up to it, and back from an entry to its folded column and row.
  uint32_t columnPart(uint32_t x) const {
    x &= s_.foldX - 1;
    return ((x >> 2) << 4) | (x & 3);
  }
  uint32_t rowPart(uint32_t y) const {
    y &= s_.foldY - 1;
    return ((y >> 2) << (__builtin_ctz(s_.foldX) + 2)) | ((y & 3) << 2);
  }
  uint32_t folded(int32_t x, int32_t y) const {
    return rowPart(static_cast<uint32_t>(y)) + columnPart(static_cast<uint32_t>(x));
  }
  void unfold(uint32_t entry, uint32_t& x, uint32_t& y) const {
    const int tileRow = __builtin_ctz(s_.foldX) + 2;
    const uint32_t within = entry & ((1u << tileRow) - 1);
    x = ((within >> 4) << 2) | (within & 3);
    y = ((entry >> tileRow) << 2) | ((within >> 2) & 3);
  }
  void placeInCell(uint32_t slot, Vec2 centre) {
    ColdBody& c = s_.cold[slot];
    c.cx = cellCoord(centre.x, s_.x0, s_.cellSize);
    c.cy = cellCoord(centre.y, s_.y0, s_.cellSize);
    setCell(slot);
  }
  // After its cell coordinates changed: the table entry, and whether static fixtures are listed there
  // (a flag in the HotBody, so that a prediction in open space does not look up the static list).
  void setCell(uint32_t slot) {
    const ColdBody& c = s_.cold[slot];
    HotBody& h = s_.hot[slot];
    h.cell = folded(c.cx, c.cy);
    const bool near = (s_.staticNear[h.cell >> 6] >> (h.cell & 63)) & 1;
    h.flags = static_cast<uint8_t>((h.flags & ~HotBody::kStaticNear) | (near ? HotBody::kStaticNear : 0));
  }
  size_t cellOf(uint32_t slot) const { return s_.hot[slot].cell; }
  // Asks for the lines of the table that gatherNeighbours() will read for the body (its record is in
  // cache): the three rows of three entries around its cell.
  void prefetchNeighbourhood(uint32_t slot) const {
    uint32_t x, y;
    unfold(s_.hot[slot].cell, x, y);
    const uint32_t left = columnPart(x - 1), right = columnPart(x + 1);
    for (uint32_t dy = 0; dy < 3; ++dy) {
      const int32_t* row = s_.heads.data() + rowPart(y + dy - 1);
      __builtin_prefetch(row + left);
      __builtin_prefetch(row + right);
    }
  }
  void link(uint32_t slot);
  void unlink(uint32_t slot);
  template <class Visit>
  void forEachNeighbour(uint32_t slot, Visit&& visit) const;
  void gatherNeighbours(uint32_t slot, std::vector<uint32_t>& out) const;
  size_t gatherNeighbours(uint32_t slot, uint32_t* out, size_t capacity) const;
  template <class Visit>
  void forEachPhysical(uint32_t slot, Visit&& visit) const;

  // Dismissed contacts.
  bool dismissals(uint32_t slot) const { return (s_.hot[slot].flags & HotBody::kDismissals) != 0; }
  void clearDismissals(uint32_t slot) {
    if (slot < s_.dismissed.size()) s_.dismissed[slot].clear();
    s_.hot[slot].flags = static_cast<uint8_t>(s_.hot[slot].flags & ~HotBody::kDismissals);
  }
  bool isDismissed(uint32_t slot, uint32_t own, uint32_t other) const;

  // Predictions.
  struct Prediction {
    Predicting p;
    PredictiveEvent best;
    double horizon = 0;
    bool moving = false, hasDismissals = false, single = false;
    bool plain = false;  // isPlain(), and nothing dismissed: pairPlain() applies to its plain neighbours
  };
  void startPrediction(uint32_t slot, double now, Prediction& q) const;
  void pairWith(Prediction& q, uint32_t other, double until);
  void pairPlain(Prediction& q, uint32_t other);
  void finishPrediction(Prediction& q);
  void predictBody(uint32_t slot, double now);
  void predictPlain(uint32_t slot, double now);
  void predictPlainAmong(uint32_t slot, double now, const uint32_t* neighbours, size_t count);
  bool predictsPlain(uint32_t slot) const {
    return plainWorld_ && isPlain(s_.hot[slot]) && !dismissals(slot) && isMoving(s_.hot[slot]);
  }
  void crossingStraight(Vec2 centre, Vec2 velocity, const ColdBody& cell, double& h, int& side) const;
  void crossing(const Predicting& p, double& h, int& side) const;
  void predictPair(uint32_t own, uint32_t other, double now, double horizon, PredictiveEvent& best);
  void predictCircles(const Predicting& p, uint32_t j, double horizon, PredictiveEvent& best);
  int resolvedFeature(const BodySlot& a, const BodySlot& b, uint32_t own, uint32_t other, double now) const;
  void fillPairs(uint32_t slot);

  // The queue (see PredictiveState): the calendar's buckets, and the heap of the current one, a 4-ary
  // heap (shallower than a binary one, and a node's children share a cache line).
  int64_t bucketOf(double t) const {
    // floor() of the scaled time, by truncation and a step down for negatives that were not whole: the
    // same value (for an integer N, floor(x) < N exactly when x < N), without a call into libm on
    // every queue operation.
    const double x = (t - s_.base) * s_.inverseWidth;
    if (!(x < 4e18)) return int64_t{1} << 62;  // also infinity and NaN: the overflow list
    if (x < -4e18) return -(int64_t{1} << 62);
    const int64_t k = static_cast<int64_t>(x);
    return static_cast<double>(k) > x ? k - 1 : k;
  }
  void enqueue(uint32_t slot) { enqueue(slot, s_.event[slot].time, s_.event[slot].partner); }
  void enqueue(uint32_t slot, double time, uint32_t partner);
  void dequeue(uint32_t slot);
  void retune(double now, bool keepWidth = false);
  uint32_t top();
  // The end of a round of the buckets from the current one: as many as there are, up to the step's end.
  int64_t roundLimit() const {
    return std::min(s_.current + static_cast<int64_t>(s_.buckets.size()), std::max(s_.stepBucket, s_.current) + 1);
  }
  size_t scheduledCount() const { return s_.heap.size() + s_.inBuckets + s_.inOverflow; }
  bool before(const detail::HeapNode& x, const detail::HeapNode& y) const {
    if (x.time != y.time) return x.time < y.time;
    return earlier(s_.event[x.slot], s_.event[y.slot]);
  }
  void place(size_t k, detail::HeapNode node) {
    s_.heap[k] = node;
    s_.queue[node.slot].heapPos = static_cast<int32_t>(k);
  }
  void siftUp(size_t k);
  void siftDown(size_t k);
  void schedule(uint32_t slot, const PredictiveEvent& e);
  void unschedule(uint32_t slot);
  void resetQueue();
};

// ---- Setup -----------------------------------------------------------------------------------------

template <class W>
void Engine<W>::normalize(double dt) {
  // As at the start of a hybrid step: the Zeno guard's count starts again, a slide on a fixture that is
  // gone ends, and an awake free dynamic body falls with gravity. The same pass gathers what
  // computeConstants() needs from every body (one pass over the bodies instead of two; nothing in
  // between changes a body's motion, type or sleep).
  double speedScale = 0;
  bool movingKinematic = false;
  bool anyAsleep = false, anySliding = false;
  for (BodySlot& b : w_.bodies) {
    if (!b.alive) continue;
    b.stepCollisions = 0;
    if (b.support.generation != 0 &&
        (!w_.fixtures[b.support.fixture].alive || w_.fixtures[b.support.fixture].generation != b.support.generation)) {
      w_.stopSliding(b);
    }
    if (b.type == BodyType::Dynamic && !b.asleep && b.support.generation == 0) b.acceleration = w_.def.gravity;
    if (b.type == BodyType::Dynamic) {
      anyAsleep = anyAsleep || b.asleep;
      anySliding = anySliding || b.support.generation != 0;
    }
    // As the hybrid step: approach speeds below 1e-13 of the fastest body's are round-off.
    if (b.type == BodyType::Static || b.asleep) continue;
    speedScale = std::max(speedScale, length(b.velocity) + length(b.acceleration) * dt);
    if (b.type == BodyType::Kinematic && !(b.velocity == Vec2{}) && !b.fixtures.empty()) movingKinematic = true;
  }
  speedScale_ = speedScale;
  movingKinematic_ = movingKinematic;
  anyAsleep_ = anyAsleep;
  anySliding_ = anySliding;
}

template <class W>
void Engine<W>::rebase(double by) {
  if (by == 0) return;
  // The queue is out of order until the next retune().
  for (PredictiveEvent& e : s_.event) {
    if (e.kind != PredictiveKind::None) e.time -= by;
  }
  for (detail::HeapNode& n : s_.heap) n.time = s_.event[n.slot].time;
  // The bodies' own times (localTime, last.time) were re-based at the end of the last step.
}

template <class W>
void Engine<W>::computeConstants(double dt) {
  const double speedScale = speedScale_;
  const bool movingKinematic = movingKinematic_;
  s_.approachTolerance = 1e-13 * speedScale;
  s_.restTolerance = 8 * kEps / dt;
  s_.movingKinematic = movingKinematic;
  // Horizon of a prediction that no cell crossing bounds (a body at the far edge of the coordinates, or
  // at rest next to a moving kinematic body): a few dozen cells at the fastest speed.
  s_.capTime = speedScale > 0 ? 32 * s_.cellSize / speedScale : 1.0;
  if (!(s_.capTime > 0) || !std::isfinite(s_.capTime)) s_.capTime = 1.0;
}

template <class W>
void Engine<W>::sync(uint32_t slot) {
  // The copy from the body, after anything changed it.
  const BodySlot& b = w_.bodies[s_.bodyOfSlot[slot]];
  HotBody& h = s_.hot[slot];
  ColdBody& c = s_.cold[slot];
  h.position = b.position;
  h.velocity = b.velocity;
  h.localTime = b.localTime;
  h.collisionCount = b.collisionCount;
  constexpr uint8_t keep =
      HotBody::kSingle | HotBody::kOffCentre | HotBody::kCustomFilter | HotBody::kDismissals | HotBody::kStaticNear;
  h.flags = static_cast<uint8_t>((h.flags & keep) | (b.acceleration == Vec2{} ? 0 : HotBody::kAccelerating) |
                                 (b.support.generation != 0 ? HotBody::kSliding : 0));
  s_.rare[slot].acceleration = b.acceleration;
  c.lastTime = b.last.time;
  c.lastLow = b.last.fixtureLow;
  c.lastHigh = b.last.fixtureHigh;
  c.lastFeature = b.last.feature;
  c.inverseMass = b.inverseMass;
  c.lastContactTime = b.lastContactTime;
  if (w_.pathLog.active) w_.pathLog.record(s_.bodyOfSlot[slot], {b.localTime, b.position, b.velocity, b.acceleration});
}

template <class W>
void Engine<W>::attach(uint32_t slot) {
  // The copy back into the BodySlot, after collisions resolved on the copy (collidePlain): before
  // anything reads the BodySlot, and at the step's end.
  HotBody& h = s_.hot[slot];
  if (!(h.flags & HotBody::kDetached)) return;
  const ColdBody& c = s_.cold[slot];
  BodySlot& b = w_.bodies[s_.bodyOfSlot[slot]];
  b.position = h.position;
  b.velocity = h.velocity;
  b.localTime = h.localTime;
  b.collisionCount = h.collisionCount;
  b.last = detail::LastContact{c.lastLow, c.lastHigh, c.lastFeature, c.lastTime};
  b.lastContactTime = c.lastContactTime;
  h.flags = static_cast<uint8_t>(h.flags & ~HotBody::kDetached);
}

template <class W>
void Engine<W>::buildGrid() {
  const size_t nb = w_.bodies.size();
  s_.slotOfBody.assign(nb, PredictiveState::kNone);
  s_.bodyOfSlot.clear();
  s_.hot.clear();
  s_.cold.clear();
  s_.rare.clear();
  s_.centres.clear();
  s_.untracked.clear();
  s_.plainShapes = true;
  s_.bodyOfSlot.reserve(nb);
  s_.hot.reserve(nb);
  s_.cold.reserve(nb);
  s_.rare.reserve(nb);

  // Tracked bodies: dynamic ones with a physical fixture.
  double diameter = 0;
  double minX = kInf, minY = kInf, maxX = -kInf, maxY = -kInf;
  for (uint32_t body = 0; body < nb; ++body) {
    BodySlot& b = w_.bodies[body];
    if (!b.alive) continue;
    b.last = detail::LastContact{};
    if (b.type == BodyType::Kinematic) s_.untracked.push_back(body);
    if (b.type != BodyType::Dynamic) continue;
    int physical = 0;
    HotBody h;
    ColdBody c;
    detail::RareBody r;
    for (uint32_t f : b.fixtures) {
      const detail::FixtureSlot& fs = w_.fixtures[f];
      if (fs.sensor) continue;
      if (physical == 0) {
        h.fixture = f;
        r.centre = detail::circleCentre(fs.geometry);
        r.categoryBits = fs.filter.categoryBits;
        r.maskBits = fs.filter.maskBits;
        r.group = fs.filter.group;
        h.radius = detail::circleRadius(fs.geometry);
        c.restitution = fs.restitution;
        c.bodyGeneration = b.generation;
        c.fixtureGeneration = fs.generation;
        if (std::holds_alternative<Circle>(fs.geometry)) h.flags |= HotBody::kSingle;
        if (!(r.centre == Vec2{})) h.flags |= HotBody::kOffCentre;
        if (r.categoryBits != Filter{}.categoryBits || r.maskBits != Filter{}.maskBits || r.group != 0) {
          h.flags |= HotBody::kCustomFilter;
        }
      }
      ++physical;
      diameter = std::max(diameter, 2 * detail::circleRadius(fs.geometry));
    }
    if (physical == 0) {
      s_.untracked.push_back(body);
      continue;
    }
    if (physical > 1) h.flags = static_cast<uint8_t>(h.flags & ~HotBody::kSingle);
    s_.slotOfBody[body] = static_cast<uint32_t>(s_.hot.size());
    s_.bodyOfSlot.push_back(body);
    s_.hot.push_back(h);
    s_.cold.push_back(c);
    s_.rare.push_back(r);
    constexpr uint8_t shape = HotBody::kSingle | HotBody::kOffCentre | HotBody::kCustomFilter;
    if ((h.flags & shape) != HotBody::kSingle) s_.plainShapes = false;
    const Vec2 centre = b.position + r.centre;
    s_.centres.push_back(centre);
    minX = std::min(minX, centre.x);
    minY = std::min(minY, centre.y);
    maxX = std::max(maxX, centre.x);
    maxY = std::max(maxY, centre.y);
  }
  const size_t n = s_.hot.size();
  for (uint32_t slot = 0; slot < n; ++slot) sync(slot);

  // Cell size: the largest diameter, with a margin for round-off in cell crossings. The table: about
  // the bodies' region, at most a few entries per body.
  double size = 1;
  s_.x0 = s_.y0 = 0;
  uint32_t foldX = 4, foldY = 4;
  if (n > 0 && std::isfinite(maxX - minX) && std::isfinite(maxY - minY)) {
    const double width = maxX - minX, height = maxY - minY;
    const double extent = std::max({std::fabs(minX), std::fabs(maxX), std::fabs(minY), std::fabs(maxY)});
    size = diameter * (1 + 1e-6) + 256 * kEps * extent;
    if (!(size > 0)) size = std::max(width, height) / std::sqrt(static_cast<double>(n));
    if (!(size > 0) || !std::isfinite(size)) size = 1;
    s_.x0 = minX;
    s_.y0 = minY;
    size = sparseCellSize(size, std::max(sceneExtent(), diameter));
    const double cap = static_cast<double>(std::max<size_t>(8 * n, 1024));
    while (foldX < width / size + 3 && foldX < cap) foldX *= 2;
    while (foldY < height / size + 3 && foldY < cap) foldY *= 2;
    while (static_cast<double>(foldX) * foldY > cap) {
      if (foldX >= foldY) {
        foldX /= 2;
      } else {
        foldY /= 2;
      }
    }
    foldX = std::max(foldX, 4u);
    foldY = std::max(foldY, 4u);
  }
  s_.cellSize = size;
  // A body leaves its cell only once it is this far past the side: without it, a body resting exactly on a
  // side could cross back and forth at one instant forever. Touching bodies still sit in neighbouring
  // cells: two cells apart their centres are >= size - 2 hysteresis > diameter apart; and a static
  // fixture within a disk's reach of its centre is within hysteresis + diameter / 2 < size / 2 of its
  // cell, so it is listed there.
  s_.hysteresis = 0.25 * (size - diameter);
  s_.extent = 0;
  for (const Vec2 c : s_.centres) s_.extent = std::max({s_.extent, std::fabs(c.x), std::fabs(c.y)});
  s_.foldX = foldX;
  s_.foldY = foldY;
  const size_t cells = static_cast<size_t>(foldX) * foldY;
  s_.heads.assign(cells, -1);
  s_.staticBegin.assign(cells + 1, 0);
  s_.staticNear.assign((cells + 63) / 64, 0);
  s_.links.assign(n, PredictiveState::CellLink{});
  s_.event.assign(n, PredictiveEvent{});
  resetQueue();
  s_.dismissed.clear();  // made as long as the slots when first needed: most worlds never dismiss
  s_.dismissedSlots.clear();
  for (uint32_t slot = 0; slot < n; ++slot) {
    placeInCell(slot, centreOf(slot, s_.hot[slot].localTime));
    link(slot);
  }
  reorder(/*fresh=*/true);

  // Static fixtures: in every cell whose region, grown by half a cell (the reach of any dynamic body
  // whose centre is in it), the fixture overlaps.
  std::vector<std::pair<uint32_t, uint32_t>> entries;  // (cell, fixture)
  s_.kinematicFixtures.clear();
  const double reach = 0.5 * size;
  for (uint32_t body = 0; body < nb; ++body) {
    const BodySlot& b = w_.bodies[body];
    if (!b.alive || b.type == BodyType::Dynamic) continue;
    for (uint32_t f : b.fixtures) {
      const detail::FixtureSlot& fs = w_.fixtures[f];
      if (fs.sensor) continue;
      if (b.type == BodyType::Kinematic) {
        s_.kinematicFixtures.push_back(f);
        continue;
      }
      const Box box = w_.worldBox(f);
      const Box grown{{box.min.x - reach, box.min.y - reach}, {box.max.x + reach, box.max.y + reach}};
      const int32_t ax = cellCoord(grown.min.x, s_.x0, size), bx = cellCoord(grown.max.x, s_.x0, size);
      const int32_t ay = cellCoord(grown.min.y, s_.y0, size), by = cellCoord(grown.max.y, s_.y0, size);
      const int64_t countX = int64_t{bx} - ax + 1, countY = int64_t{by} - ay + 1;
      if (countX * countY <= 4 * static_cast<int64_t>(cells) + 64) {
        for (int32_t y = ay; y <= by; ++y) {
          for (int32_t x = ax; x <= bx; ++x) {
            // The cell's region grown by `reach`; cells reaching to infinity cut at the fixture's box.
            Box region;
            region.min.x = x == -kMaxCoord ? grown.min.x : s_.x0 + x * size - reach;
            region.max.x = x == kMaxCoord ? grown.max.x : s_.x0 + (x + 1.0) * size + reach;
            region.min.y = y == -kMaxCoord ? grown.min.y : s_.y0 + y * size - reach;
            region.max.y = y == kMaxCoord ? grown.max.y : s_.y0 + (y + 1.0) * size + reach;
            if (overlapsBox(fs.geometry, b.position, region)) entries.emplace_back(folded(x, y), f);
          }
        }
      } else {
        // Huge: every table entry its box folds onto, without looking closer.
        const int64_t fx = std::min<int64_t>(countX, s_.foldX), fy = std::min<int64_t>(countY, s_.foldY);
        for (int64_t y = 0; y < fy; ++y) {
          for (int64_t x = 0; x < fx; ++x) {
            entries.emplace_back(folded(static_cast<int32_t>(ax + x), static_cast<int32_t>(ay + y)), f);
          }
        }
      }
    }
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  for (const auto& e : entries) ++s_.staticBegin[e.first + 1];
  for (size_t c = 0; c < cells; ++c) s_.staticBegin[c + 1] += s_.staticBegin[c];
  s_.staticList.assign(entries.size(), 0);
  {
    std::vector<uint32_t> fill(cells);
    for (size_t c = 0; c < cells; ++c) fill[c] = s_.staticBegin[c];
    for (const auto& e : entries) s_.staticList[fill[e.first]++] = e.second;
  }
  s_.staticNear.assign((cells + 63) / 64, 0);
  for (size_t c = 0; c < cells; ++c) {
    if (s_.staticBegin[c] != s_.staticBegin[c + 1]) s_.staticNear[c >> 6] |= uint64_t{1} << (c & 63);
  }
  for (uint32_t slot = 0; slot < n; ++slot) setCell(slot);
  s_.valid = true;
}

// Sorts by radix, 16 bits at a time from the lowest (LSD), skipping digits all keys share: O(n), where
// std::sort of 10^5 keys took longer than the rest of the grid's set-up.
void sortKeys(std::vector<uint64_t>& keys) {
  const size_t n = keys.size();
  std::vector<uint64_t> other(n);
  std::vector<uint32_t> count(size_t{1} << 16);
  for (int shift = 0; shift < 64; shift += 16) {
    std::fill(count.begin(), count.end(), 0u);
    for (uint64_t k : keys) ++count[(k >> shift) & 0xFFFF];
    if (n == 0 || count[(keys[0] >> shift) & 0xFFFF] == n) continue;
    uint32_t sum = 0;
    for (uint32_t& c : count) {
      const uint32_t here = c;
      c = sum;
      sum += here;
    }
    for (uint64_t k : keys) other[count[(k >> shift) & 0xFFFF]++] = k;
    keys.swap(other);
  }
}

template <class W>
double Engine<W>::sceneExtent() const {
  // The size of the box around every tracked body's centre and every static and kinematic fixture.
  Box box{{kInf, kInf}, {-kInf, -kInf}};
  for (const Vec2 c : s_.centres) box = unionOf(box, Box{c, c});
  for (const BodySlot& b : w_.bodies) {
    if (!b.alive || b.type == BodyType::Dynamic) continue;
    for (uint32_t f : b.fixtures) {
      if (!w_.fixtures[f].sensor) box = unionOf(box, w_.fixtures[f].localBox.translated(b.position));
    }
  }
  const double extent = std::max(box.max.x - box.min.x, box.max.y - box.min.y);
  return std::isfinite(extent) ? extent : 0.0;
}

template <class W>
double Engine<W>::meanNeighbours(double size) const {
  // How many other bodies the 3 x 3 cells around a body hold, on average, with cells of this size.
  const size_t n = s_.hot.size();
  if (n == 0) return 0.0;
  {
    // Where the bodies' cells fit a table of a few entries per body (a gas, a pile): counted in it, in
    // O(n + cells). The sum is of whole numbers below 2^53, so the same value in any order as below.
    // Cells are >= 0 here (the origin is the bodies' lowest corner); one cell of border on each side.
    auto cellOfCentre = [&](uint32_t slot, int64_t& x, int64_t& y) {
      const Vec2 c = s_.centres[slot];
      x = cellCoord(c.x, s_.x0, size) + int64_t{1};
      y = cellCoord(c.y, s_.y0, size) + int64_t{1};
    };
    int64_t maxX = 0, maxY = 0;
    bool fits = true;
    for (uint32_t slot = 0; slot < n && fits; ++slot) {
      int64_t x, y;
      cellOfCentre(slot, x, y);
      fits = x >= 1 && y >= 1 && x <= int64_t{1} << 20 && y <= int64_t{1} << 20;
      maxX = std::max(maxX, x);
      maxY = std::max(maxY, y);
    }
    const int64_t width = maxX + 2, height = maxY + 2;
    if (fits && width * height <= 8 * static_cast<int64_t>(n) + 1024) {
      std::vector<uint32_t>& count = s_.cellCounts;
      count.assign(static_cast<size_t>(width * height), 0);
      auto entry = [&](uint32_t slot) {
        int64_t x, y;
        cellOfCentre(slot, x, y);
        return static_cast<size_t>(y * width + x);
      };
      for (uint32_t k = 0; k < n; ++k) ++count[entry(k)];
      double total = 0;
      for (uint32_t k = 0; k < n; ++k) {
        const size_t at = entry(k);
        const size_t w = static_cast<size_t>(width);
        const uint32_t around = count[at - w - 1] + count[at - w] + count[at - w + 1] + count[at - 1] + count[at] +
                                count[at + 1] + count[at + w - 1] + count[at + w] + count[at + w + 1];
        total += static_cast<double>(around - 1);
      }
      return total / static_cast<double>(n);
    }
  }
  std::vector<uint64_t> keys(n);
  auto key = [](int64_t x, int64_t y) { return (static_cast<uint64_t>(x) << 32) | static_cast<uint32_t>(y); };
  for (uint32_t slot = 0; slot < n; ++slot) {
    const Vec2 c = s_.centres[slot];
    keys[slot] = key(cellCoord(c.x, s_.x0, size) + int64_t{kMaxCoord} + 1, cellCoord(c.y, s_.y0, size) + 1);
  }
  sortKeys(keys);
  // Cells are visited in key order, so each of the nine neighbouring keys (x + dx, y + dy) only grows:
  // nine cursors that only move forward find every neighbouring cell's run of keys in O(n) in all. Cell
  // coordinates here are >= 0 (the origin is the bodies' lowest corner), so y + dy never wraps the key.
  struct Cursor {
    size_t begin = 0, end = 0;
  };
  Cursor cursors[9];
  double total = 0;
  for (size_t k = 0; k < n;) {
    size_t end = k;
    while (end < n && keys[end] == keys[k]) ++end;
    const int64_t x = static_cast<int64_t>(keys[k] >> 32), y = static_cast<int64_t>(keys[k] & 0xFFFFFFFFu);
    size_t around = 0;
    Cursor* cursor = cursors;
    for (int64_t dx = -1; dx <= 1; ++dx) {
      for (int64_t dy = -1; dy <= 1; ++dy, ++cursor) {
        const uint64_t q = key(x + dx, y + dy);
        while (cursor->begin < n && keys[cursor->begin] < q) ++cursor->begin;
        if (cursor->end < cursor->begin) cursor->end = cursor->begin;
        while (cursor->end < n && keys[cursor->end] <= q) ++cursor->end;
        around += cursor->end - cursor->begin;
      }
    }
    total += static_cast<double>(end - k) * static_cast<double>(around - 1);
    k = end;
  }
  return n > 0 ? total / static_cast<double>(n) : 0.0;
}

template <class W>
double Engine<W>::sparseCellSize(double size, double limit) const {
  // Cells of one diameter suit a dense gas. Where bodies are sparse, a body crossing cells of that size
  // would do little else (a fast body in an empty arena crosses millions): cells grow, doubling, while a
  // body still has few neighbours (each crossing costs about as much as a handful of pair tests), up to
  // the size of the whole scene.
  for (int k = 0; k < 64 && 2 * size <= 2 * limit; ++k) {
    if (meanNeighbours(2 * size) > 6) break;
    size *= 2;
  }
  return size;
}

template <class W>
void Engine<W>::reorder(bool fresh) {
  // Slots in cell order, so that neighbours sit close in memory. The cells are taken along a Z-order
  // (Morton) curve over the table rather than row by row: a 3 x 3 block of cells, which every prediction
  // reads, then lies in a few short runs of slots instead of three runs a whole row apart. Only where
  // things are stored changes: no prediction, time or order of events does.
  const size_t n = s_.hot.size();
  auto& order = s_.order;  // order[new slot] = old slot
  order.clear();
  auto gather = [](uint64_t v) {  // the even bits of v, packed (a Z-order index to one coordinate)
    v &= 0x5555555555555555ull;
    v = (v | (v >> 1)) & 0x3333333333333333ull;
    v = (v | (v >> 2)) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | (v >> 4)) & 0x00FF00FF00FF00FFull;
    v = (v | (v >> 8)) & 0x0000FFFF0000FFFFull;
    v = (v | (v >> 16)) & 0x00000000FFFFFFFFull;
    return v;
  };
  // The table (powers of two on each side) as square tiles, row by row, each along the curve.
  const uint64_t side = std::min(s_.foldX, s_.foldY);
  for (uint64_t ty = 0; ty < s_.foldY; ty += side) {
    for (uint64_t tx = 0; tx < s_.foldX; tx += side) {
      for (uint64_t z = 0; z < side * side; ++z) {
        const uint64_t x = tx + gather(z), y = ty + gather(z >> 1);
        for (int32_t k = headSlot(s_.heads[folded(static_cast<int32_t>(x), static_cast<int32_t>(y))]); k >= 0;
             k = s_.links[k].next) {
          order.push_back(static_cast<uint32_t>(k));
        }
      }
    }
  }
  std::vector<uint32_t> newSlot(n);
  for (uint32_t k = 0; k < n; ++k) newSlot[order[k]] = k;
  // In place, along the permutation's cycles: no second copy of the arrays (tens of megabytes at 10^6
  // bodies, to be faulted in before it is any use).
  auto& done = s_.permuted;
  // Several arrays at once, along one walk of the cycles (their records at one index are fetched side
  // by side, and the walk is made once).
  auto permute = [&](auto&... v) {
    done.assign(n, 0);
    for (size_t start = 0; start < n; ++start) {
      if (done[start]) continue;
      auto held = std::make_tuple(std::move(v[start])...);
      for (size_t k = start;;) {
        done[k] = 1;
        const size_t from = order[k];
        if (from == start) {
          std::apply([&](auto&... h) { ((v[k] = std::move(h)), ...); }, held);
          break;
        }
        ((v[k] = std::move(v[from])), ...);
        k = from;
      }
    }
  };
  if (fresh) {
    // (Fresh from buildGrid: no events and no dismissals yet, nothing to carry over.)
    permute(s_.hot, s_.cold, s_.rare, s_.bodyOfSlot);
  } else {
    permute(s_.hot, s_.cold, s_.rare, s_.bodyOfSlot, s_.event);
  }
  for (uint32_t k = 0; k < n; ++k) s_.slotOfBody[s_.bodyOfSlot[k]] = k;
  if (!fresh) {
    if (!s_.dismissed.empty()) permute(s_.dismissed);
    for (PredictiveEvent& e : s_.event) {
      if (e.partner != PredictiveState::kNone) e.partner = newSlot[e.partner];
    }
    for (uint32_t& slot : s_.dismissedSlots) slot = newSlot[slot];
    // The queue again, with the same calendar.
    resetQueue();
    for (uint32_t k = 0; k < n; ++k) {
      if (s_.event[k].kind != PredictiveKind::None) enqueue(k);
    }
  }
  std::fill(s_.heads.begin(), s_.heads.end(), -1);
  s_.links.resize(n);
  for (uint32_t k = static_cast<uint32_t>(n); k-- > 0;) link(k);
  s_.popsSinceReorder = 0;
}

template <class W>
void Engine<W>::link(uint32_t slot) {
  const size_t cell = cellOf(slot);
  const int32_t head = headSlot(s_.heads[cell]);
  s_.links[slot] = {head, -1};
  if (head >= 0) s_.links[head].prev = static_cast<int32_t>(slot);
  s_.heads[cell] = headEntry(static_cast<int32_t>(slot), head >= 0);
}

template <class W>
void Engine<W>::unlink(uint32_t slot) {
  const auto [n, p] = s_.links[slot];
  if (p >= 0) {
    s_.links[p].next = n;
    if (n < 0 && s_.links[p].prev < 0) s_.heads[cellOf(slot)] = headEntry(p, false);  // p is left alone
  } else {
    s_.heads[cellOf(slot)] = headEntry(n, n >= 0 && s_.links[n].next >= 0);
  }
  if (n >= 0) s_.links[n].prev = p;
  s_.links[slot] = {};
}

template <class W>
template <class Visit>
void Engine<W>::forEachNeighbour(uint32_t slot, Visit&& visit) const {
  // The other bodies in the 3 x 3 cells around it (gatherNeighbours()).
  std::vector<uint32_t>& found = s_.visiting;
  gatherNeighbours(slot, found);
  for (uint32_t j : found) visit(j);
}

template <class W>
template <class Visit>
void Engine<W>::forEachPhysical(uint32_t slot, Visit&& visit) const {
  if (s_.hot[slot].flags & HotBody::kSingle) {
    visit(s_.hot[slot].fixture);
    return;
  }
  for (uint32_t f : w_.bodies[s_.bodyOfSlot[slot]].fixtures) {
    if (!w_.fixtures[f].sensor) visit(f);
  }
}

template <class W>
size_t Engine<W>::gatherNeighbours(uint32_t slot, uint32_t* out, size_t capacity) const {
  // The other bodies in the 3 x 3 cells around it (distinct table entries, since the table is at least
  // 4 x 4), into out[0, capacity), in no particular order (a plain prediction's result does not depend
  // on it: events are totally ordered); returns how many there are, which may be more than were
  // written. The cell's coordinates come folded from the HotBody (the same entries: the fold is a
  // remainder by a power of two). Every neighbour's record is asked for as its slot is found (a
  // prefetch): they are most often cache misses, and are then fetched side by side before the pair
  // tests read them, instead of one after each test. First the nine heads (capacity >= 9, as every
  // caller's is), then the rest of the lists (in `links`) of the cells whose head says more follow.
  uint32_t x, y;
  unfold(s_.hot[slot].cell, x, y);
  const uint32_t columns[3] = {columnPart(x - 1), columnPart(x), columnPart(x + 1)};
  const uint32_t rows[3] = {rowPart(y - 1), rowPart(y), rowPart(y + 1)};
  const int32_t* heads = s_.heads.data();
  const HotBody* hot = s_.hot.data();
  // Whether a cell is empty is a coin toss in a gas (about half are), which a branch predictor loses
  // half the time: the heads are taken without a branch.
  size_t count = 0;
  uint32_t crowded = 0;  // bit k: cell k of the nine holds more than its head
  int32_t entries[9];
  auto take = [&](uint32_t k, int32_t entry) {
    entries[k] = entry;
    const bool found = entry >= 0;
    const uint32_t j = static_cast<uint32_t>(entry) >> 1;
    __builtin_prefetch(hot + (j & (0u - static_cast<uint32_t>(found))));  // (an empty cell: slot 0)
    out[count] = j;
    count += found & (j != slot);
    crowded |= static_cast<uint32_t>(found & (entry & 1)) << k;
  };
  // (Written out: a loop over the nine is not unrolled, and costs twice the instructions.)
  take(0, heads[rows[0] + columns[0]]);
  take(1, heads[rows[0] + columns[1]]);
  take(2, heads[rows[0] + columns[2]]);
  take(3, heads[rows[1] + columns[0]]);
  take(4, heads[rows[1] + columns[1]]);
  take(5, heads[rows[1] + columns[2]]);
  take(6, heads[rows[2] + columns[0]]);
  take(7, heads[rows[2] + columns[1]]);
  take(8, heads[rows[2] + columns[2]]);
  const PredictiveState::CellLink* links = s_.links.data();
  for (; crowded != 0; crowded &= crowded - 1) {
    const int32_t entry = entries[__builtin_ctz(crowded)];
    for (int32_t j = links[headSlot(entry)].next; j >= 0; j = links[j].next) {
      __builtin_prefetch(hot + j);
      if (static_cast<uint32_t>(j) == slot) continue;
      if (count < capacity) out[count] = static_cast<uint32_t>(j);
      ++count;
    }
  }
  return count;
}

template <class W>
void Engine<W>::gatherNeighbours(uint32_t slot, std::vector<uint32_t>& out) const {
  // The same bodies in the order of the cells, row by row, and of their lists: the general path's order
  // (the resting rules keep the first supports found, World::Impl::supportsAt).
  out.clear();
  uint32_t x, y;
  unfold(s_.hot[slot].cell, x, y);
  const uint32_t columns[3] = {columnPart(x - 1), columnPart(x), columnPart(x + 1)};
  const HotBody* hot = s_.hot.data();
  const PredictiveState::CellLink* links = s_.links.data();
  for (uint32_t dy = 0; dy < 3; ++dy) {
    const int32_t* row = s_.heads.data() + rowPart(y + dy - 1);
    for (uint32_t column : columns) {
      const int32_t entry = row[column];
      if (entry < 0) continue;
      int32_t j = headSlot(entry);
      __builtin_prefetch(hot + j);
      if (static_cast<uint32_t>(j) != slot) out.push_back(static_cast<uint32_t>(j));
      if (!(entry & 1)) continue;  // alone in its cell: no look at `links`
      for (j = links[j].next; j >= 0; j = links[j].next) {
        __builtin_prefetch(hot + j);
        if (static_cast<uint32_t>(j) != slot) out.push_back(static_cast<uint32_t>(j));
      }
    }
  }
}

template <class W>
bool Engine<W>::isDismissed(uint32_t slot, uint32_t own, uint32_t other) const {
  const uint32_t countOwn = s_.hot[slot].collisionCount;
  for (const detail::Dismissal& d : s_.dismissed[slot]) {
    if (d.own == own && d.other == other && d.countOwn == countOwn && d.countOther == countOf(other)) {
      return true;
    }
  }
  return false;
}

// ---- Predictions -----------------------------------------------------------------------------------

template <class W>
void Engine<W>::crossing(const Predicting& p, double& h, int& side) const {
  const Vec2 c = p.position + p.centre;
  const Vec2 v = p.velocity;
  const Vec2 a = p.acceleration;
  const double s = s_.cellSize, d = s_.hysteresis;
  const int32_t x = p.cold->cx, y = p.cold->cy;
  h = kInf;
  side = -1;
  auto keep = [&](double t, int k) {
    if (t < h) {
      h = t;
      side = k;
    }
  };
  if (x > -kMaxCoord) keep(exitTime(c.x - (s_.x0 + x * s - d), v.x, 0.5 * a.x), 0);
  if (x < kMaxCoord) keep(exitTime((s_.x0 + (x + 1.0) * s + d) - c.x, -v.x, -0.5 * a.x), 1);
  if (y > -kMaxCoord) keep(exitTime(c.y - (s_.y0 + y * s - d), v.y, 0.5 * a.y), 2);
  if (y < kMaxCoord) keep(exitTime((s_.y0 + (y + 1.0) * s + d) - c.y, -v.y, -0.5 * a.y), 3);
}

template <class W>
int Engine<W>::resolvedFeature(const BodySlot& a, const BodySlot& b, uint32_t own, uint32_t other, double now) const {
  // As World::Impl::predict: the face a body slides on, or the feature of a contact that both bodies of
  // the pair were last resolved on at this very instant.
  if (a.support.generation != 0 && a.support.fixture == other) return a.support.feature;
  if (a.last.time != now) return kNoFeature;
  const uint32_t low = std::min(own, other), high = std::max(own, other);
  auto resolvedHereNow = [&](const BodySlot& s) {
    return s.type != BodyType::Dynamic ||
           (s.last.time == now && s.last.fixtureLow == low && s.last.fixtureHigh == high);
  };
  if (resolvedHereNow(a) && resolvedHereNow(b)) return a.last.feature;
  return kNoFeature;
}

template <class W>
void Engine<W>::predictPair(uint32_t own, uint32_t other, double now, double horizon, PredictiveEvent& best) {
  // World::Impl::predict, up to the body's horizon instead of the step's end.
  attachFixture(own);
  attachFixture(other);
  const BodySlot& a = w_.bodyOf(own);
  const BodySlot& b = w_.bodyOf(other);
  ++w_.stats.timeOfImpactTests;
  const int resolved = resolvedFeature(a, b, own, other, now);
  const Vec2 pa = w_.positionAt(a, now);
  const Vec2 pb = w_.positionAt(b, now);
  const Vec2 vb = w_.velocityAt(b, now);
  const Motion relative{w_.velocityAt(a, now) - vb, a.acceleration - b.acceleration};
  const auto impact =
      timeOfImpact(w_.fixtures[own].geometry, pa, w_.fixtures[other].geometry, pb, relative, horizon - now, resolved);
  if (!impact) return;
  const double h = impact->time;
  const double time = std::min(now + h, horizon);
  if (time > best.time) return;
  const Vec2 travelOfB = vb * h + b.acceleration * (0.5 * h * h);
  const PredictiveEvent e{time,
                          own,
                          other,
                          impact->feature,
                          b.collisionCount,
                          PredictiveKind::Contact,
                          s_.slotOfBody[w_.fixtures[other].body],
                          impact->point + travelOfB,
                          impact->normal};
  if (earlier(e, best)) best = e;
}

template <class W>
void Engine<W>::predictCircles(const Predicting& p, uint32_t j, double horizon, PredictiveEvent& best) {
  // Two single-circle dynamic bodies, from their copies: the same arithmetic as predictPair through the
  // dispatcher (timeOfImpact's circle-circle entry), with a cheap rejection of receding pairs first.
  const HotBody& a = *p.hot;
  const HotBody& b = s_.hot[j];
  if ((a.flags | b.flags) & HotBody::kCustomFilter) {
    // canCollide() (the bodies differ, are dynamic and physical): the filters.
    const detail::RareBody& ca = s_.rare[p.slot];
    const detail::RareBody& cb = s_.rare[j];
    if (ca.group != 0 && ca.group == cb.group) return;
    if ((ca.categoryBits & cb.maskBits) == 0 || (cb.categoryBits & ca.maskBits) == 0) return;
  }
  if ((a.flags & HotBody::kDismissals) && isDismissed(p.slot, a.fixture, b.fixture)) return;
  const double now = p.now;
  ++w_.stats.timeOfImpactTests;
  const Vec2 accB = accelerationOf(b, s_.rare[j]);
  const Vec2 centreB = (b.flags & HotBody::kOffCentre) ? s_.rare[j].centre : Vec2{};
  const Vec2 pb = positionAt(b, accB, now);
  const Vec2 vb = velocityAt(b, accB, now);
  const Motion relative{p.velocity - vb, p.acceleration - accB};
  Circle circleA{p.centre + p.position, a.radius};
  circleA.center -= pb;
  const Circle circleB{centreB, b.radius};
  const double maxTime = horizon - now;
  if (relative.acceleration == Vec2{}) {
    // A straight relative path: no impact unless approaching (r.v < 0; time_of_impact.cpp's
    // timeToReach), and none before c / (-2 r.v) (|r + v t|^2 - reach^2 >= c + 2 (r.v) t).
    const Vec2 r = circleA.center - circleB.center;
    const double rv = dot(r, relative.velocity);
    if (!(rv < 0)) return;
    const double reach = circleA.radius + circleB.radius;
    const double c = dot(r, r) - reach * reach;
    if (c > 0 && c > -2 * rv * maxTime * (1 + 1e-9)) return;
  }
  const ColdBody& ca = *p.cold;
  const ColdBody& cb = s_.cold[j];
  // resolvedFeature() from the copies: both bodies' last contact is this pair, at this instant.
  int resolved = kNoFeature;
  if (ca.lastTime == now) {
    const uint32_t low = std::min(a.fixture, b.fixture), high = std::max(a.fixture, b.fixture);
    if (ca.lastLow == low && ca.lastHigh == high && cb.lastTime == now && cb.lastLow == low && cb.lastHigh == high) {
      resolved = ca.lastFeature;
    }
  }
  auto impact = timeOfImpactCircleCircle(circleA, relative, circleB, maxTime, resolved);
  if (!impact) return;
  const double h = impact->time;
  const double time = std::min(now + h, horizon);
  if (time > best.time) return;
  impact->point += pb;
  const Vec2 travelOfB = vb * h + accB * (0.5 * h * h);
  const PredictiveEvent e{time,
                          a.fixture,
                          b.fixture,
                          impact->feature,
                          b.collisionCount,
                          PredictiveKind::Contact,
                          j,
                          impact->point + travelOfB,
                          impact->normal};
  if (earlier(e, best)) best = e;
}

template <class W>
void Engine<W>::startPrediction(uint32_t i, double now, Prediction& q) const {
  // The body's earliest event from `now` on. A moving body looks at everything near it up to its cell
  // crossing (or a horizon), after which it is predicted again anyway. A body at rest has no crossing:
  // it looks at each moving neighbour up to that neighbour's own next event, when the neighbour is
  // predicted again and sees it; with nothing due it holds no event (and costs nothing).
  const HotBody& hb = s_.hot[i];
  const ColdBody& cb = s_.cold[i];
  Predicting& p = q.p;
  p.slot = i;
  p.now = now;
  p.hot = &hb;
  p.cold = &cb;
  p.acceleration = accelerationOf(hb, s_.rare[i]);
  p.position = positionAt(hb, p.acceleration, now);
  p.velocity = velocityAt(hb, p.acceleration, now);
  p.centre = (hb.flags & HotBody::kOffCentre) ? s_.rare[i].centre : Vec2{};
  q.moving = isMoving(hb);
  q.hasDismissals = dismissals(i);
  q.single = (hb.flags & HotBody::kSingle) != 0;
  q.plain = isPlain(hb) && !q.hasDismissals;
  PredictiveEvent& best = q.best;
  best = PredictiveEvent{};
  best.time = kInf;
  best.a = best.b = hb.fixture;
  best.feature = -1;
  if (q.moving || s_.movingKinematic) {
    double h = kInf;
    int side = -1;
    if (q.moving) crossing(p, h, side);
    best.kind = PredictiveKind::Cross;
    if (h < kInf) {
      best.feature = side;
      best.time = now + h;
    } else {
      best.time = now + s_.capTime;
    }
  }
  q.horizon = best.time;
}

template <class W>
void Engine<W>::pairWith(Prediction& q, uint32_t j, double until) {
  const uint32_t i = q.p.slot;
  ++w_.stats.candidatePairs;
  if (q.single && (s_.hot[j].flags & HotBody::kSingle)) {
    predictCircles(q.p, j, until, q.best);
    return;
  }
  forEachPhysical(i, [&](uint32_t f) {
    forEachPhysical(j, [&](uint32_t g) {
      if (!w_.canCollide(f, g) || (q.hasDismissals && isDismissed(i, f, g))) return;
      predictPair(f, g, q.p.now, until, q.best);
    });
  });
}

template <class W>
inline void Engine<W>::pairPlain(Prediction& q, uint32_t j) {
  // pairWith() and predictCircles() for two plain bodies (isPlain(), the predicted one without dismissals),
  // the moving one's neighbour up to its horizon: the same expressions with the zero acceleration and
  // centre written in, so the same values, without the branches on flags and the call per pair. A scene
  // of plain disks (a gas) pays only for this.
  const Predicting& p = q.p;
  const HotBody& b = s_.hot[j];
  ++w_.stats.candidatePairs;
  ++w_.stats.timeOfImpactTests;
  const double now = p.now;
  const Vec2 pb = positionAt(b, Vec2{}, now);
  const Vec2 vb = velocityAt(b, Vec2{}, now);
  const Motion relative{p.velocity - vb, p.acceleration - Vec2{}};
  Circle circleA{p.centre + p.position, p.hot->radius};
  circleA.center -= pb;
  double within;
  {
    // As predictCircles: a straight relative path, approaching, and close enough to meet in time (no
    // impact before c / (-2 r.v)).
    const Vec2 r = circleA.center - Vec2{};
    const double rv = dot(r, relative.velocity);
    if (!(rv < 0)) return;
    // An impact is kept only if no later than the best so far (q.best): the search stops at searchBound.
    within = searchBound(q.horizon, q.best.time, now);
    const double reach = circleA.radius + b.radius;
    const double c = dot(r, r) - reach * reach;
    if (c > 0 && c > -2 * rv * within * (1 + 1e-9)) return;
  }
  // As predictCircles, with the neighbour's ColdBody read only when the pair is the body's own last
  // contact (the neighbour's record is a cache miss more often than not).
  const ColdBody& ca = *p.cold;
  int resolved = kNoFeature;
  if (ca.lastTime == now) {
    const uint32_t low = std::min(p.hot->fixture, b.fixture), high = std::max(p.hot->fixture, b.fixture);
    if (ca.lastLow == low && ca.lastHigh == high) {
      const ColdBody& cb = s_.cold[j];
      if (cb.lastTime == now && cb.lastLow == low && cb.lastHigh == high) resolved = ca.lastFeature;
    }
  }
  auto impact = timeOfImpactCircleCircle(circleA, relative, Circle{Vec2{}, b.radius}, within, resolved);
  if (!impact) return;
  const double h = impact->time;
  const double time = std::min(now + h, q.horizon);
  PredictiveEvent& best = q.best;
  if (time > best.time) return;
  impact->point += pb;
  const Vec2 travelOfB = vb * h + Vec2{} * (0.5 * h * h);
  const PredictiveEvent e{time,
                          p.hot->fixture,
                          b.fixture,
                          impact->feature,
                          b.collisionCount,
                          PredictiveKind::Contact,
                          j,
                          impact->point + travelOfB,
                          impact->normal};
  if (earlier(e, best)) best = e;
}

template <class W>
void Engine<W>::finishPrediction(Prediction& q) {
  // Static fixtures, kinematic bodies and the slide's end; then the event goes into the queue.
  const uint32_t i = q.p.slot;
  const double now = q.p.now, horizon = q.horizon;
  if (q.moving && (q.p.hot->flags & HotBody::kStaticNear)) {
    const size_t cell = cellOf(i);
    for (uint32_t k = s_.staticBegin[cell]; k < s_.staticBegin[cell + 1]; ++k) {
      const uint32_t g = s_.staticList[k];
      forEachPhysical(i, [&](uint32_t f) {
        if (!w_.canCollide(f, g) || (q.hasDismissals && isDismissed(i, f, g))) return;
        predictPair(f, g, now, horizon, q.best);
      });
    }
  }
  for (uint32_t g : s_.kinematicFixtures) {
    if (!q.moving && w_.bodyOf(g).velocity == Vec2{}) continue;
    forEachPhysical(i, [&](uint32_t f) {
      if (!w_.canCollide(f, g) || (q.hasDismissals && isDismissed(i, f, g))) return;
      predictPair(f, g, now, horizon, q.best);
    });
  }
  if (q.p.hot->flags & HotBody::kSliding) {
    attach(i);
    const BodySlot& b = w_.bodies[s_.bodyOfSlot[i]];
    const double until = q.moving ? horizon : now + s_.capTime;
    if (const auto t = w_.slideEndTime(b, now, until)) {
      const PredictiveEvent e{std::min(*t, until), b.fixtures.front(), b.support.fixture, b.support.feature, 0,
                              PredictiveKind::SlideEnd};
      if (earlier(e, q.best)) q.best = e;
    }
  }
  if (q.best.kind == PredictiveKind::None) {
    unschedule(i);
  } else {
    schedule(i, q.best);
  }
  if (i == popped_) popped_ = PredictiveState::kNone;
}

template <class W>
void Engine<W>::predictBody(uint32_t i, double now) {
  if (predictsPlain(i)) {
    predictPlain(i, now);
    return;
  }
  // The neighbours are gathered first, which asks for their records (forEachNeighbour), so that they
  // arrive while the body's own motion and cell crossing are worked out.
  std::vector<uint32_t>& neighbours = s_.neighbours;
  gatherNeighbours(i, neighbours);
  Prediction q;
  startPrediction(i, now, q);
  if (q.plain && q.moving) {
    for (uint32_t j : neighbours) {
      if (isPlain(s_.hot[j])) {
        pairPlain(q, j);
      } else {
        pairWith(q, j, q.horizon);
      }
    }
  } else if (q.moving) {
    for (uint32_t j : neighbours) pairWith(q, j, q.horizon);
  } else {
    for (uint32_t j : neighbours) {
      // A neighbour without an event is at rest too, or is about to be predicted (and then sees this).
      if (j == popped_ || s_.event[j].kind == PredictiveKind::None || !isMoving(s_.hot[j])) continue;
      pairWith(q, j, std::max(s_.event[j].time, now));
    }
  }
  finishPrediction(q);
}

template <class W>
void Engine<W>::crossingStraight(Vec2 c, Vec2 v, const ColdBody& cell, double& h, int& side) const {
  // crossing() for a centre `c` moving in a straight line at `v`: exitTime() with no acceleration leaves
  // each side's time infinite unless the centre moves toward that side, so at most one side of each axis
  // has a finite time. The same arguments and the same tie rule (the first side in 0..3 wins), so the
  // same values.
  const double s = s_.cellSize, d = s_.hysteresis;
  const int32_t x = cell.cx, y = cell.cy;
  auto leave = [](double gap, double speed) { return gap <= 0 ? 0.0 : gap / speed; };  // exitTime, A = 0, b < 0
  // One axis: the centre's coordinate, its speed, the cell's index and origin on that axis, and the
  // axis's low side's number (the high side's is the next).
  auto axis = [&](double centre, double speed, int32_t cellIndex, double origin, int lowSide, double& time,
                  int& which) {
    time = kInf;
    which = -1;
    if (speed < 0) {
      if (cellIndex > -kMaxCoord) {
        time = leave(centre - (origin + cellIndex * s - d), -speed);
        which = lowSide;
      }
    } else if (-speed < 0) {
      if (cellIndex < kMaxCoord) {
        time = leave((origin + (cellIndex + 1.0) * s + d) - centre, -(-speed));
        which = lowSide + 1;
      }
    }
  };
  axis(c.x, v.x, x, s_.x0, 0, h, side);
  double t;
  int k;
  axis(c.y, v.y, y, s_.y0, 2, t, k);
  if (t < h) {
    h = t;
    side = k;
  }
}

template <class W>
void Engine<W>::predictPlain(uint32_t i, double now) {
  // predictBody() for a moving plain body without dismissals in a plain world, where every neighbour is
  // a plain disk too (plainWorld_; no acceleration anywhere): pairPlain() over the neighbours with
  // everything the general path carries from pair to pair (the Prediction, the best event, the bound
  // `within`) kept in registers, and the contact point and normal worked out once, for the earliest
  // impact (plain_disk_impact.h). The same arithmetic and the same total order of events as
  // predictBody(), so the same event, bit for bit (tests/test_predictive_plain.cpp).
  uint32_t found[kNeighbourBuffer];
  const size_t count = gatherNeighbours(i, found, kNeighbourBuffer);
  predictPlainAmong(i, now, found, count);
}

template <class W>
void Engine<W>::predictPlainAmong(uint32_t i, double now, const uint32_t* neighbours, size_t count) {
  // predictPlain() with the neighbours gathered already (into a buffer of kNeighbourBuffer: a longer
  // list is gathered again here).
  if (count > kNeighbourBuffer) {
    gatherNeighbours(i, s_.neighbours);
    neighbours = s_.neighbours.data();
  }
  const HotBody& hb = s_.hot[i];
  const ColdBody& cb = s_.cold[i];
  const Vec2 position = positionAt(hb, Vec2{}, now);
  const Vec2 velocity = velocityAt(hb, Vec2{}, now);
  const Vec2 centre = Vec2{} + position;  // the circle's centre (Predicting: centre + position)
  double h;
  int side;
  crossingStraight(centre, velocity, cb, h, side);
  const double horizon = h < kInf ? now + h : now + s_.capTime;

  // The best so far: the crossing, or a contact with neighbour `partner` at `bestTime`.
  double bestTime = horizon;
  uint32_t partner = PredictiveState::kNone;
  double impactTime = 0;
  Vec2 impactR, impactV, impactPb, impactVb;
  // No impact later than this can beat the best (searchBound).
  double within = searchBound(horizon, bestTime, now);
  const double radius = hb.radius;
  const uint32_t fixture = hb.fixture;
  const bool lastNow = cb.lastTime == now;
  w_.stats.candidatePairs += static_cast<int>(count);
  w_.stats.timeOfImpactTests += static_cast<int>(count);
  // The neighbour's motion at `now` and the pair's relative motion, both coordinates at once (two lanes
  // of one register, each lane the scalar expression of positionAt, velocityAt and dot, so the same
  // values).
  using Lanes = double __attribute__((vector_size(16)));
  auto lanes = [](Vec2 a) { return Lanes{a.x, a.y}; };
  const Lanes zero{0.0, 0.0};  // the zero acceleration's terms, kept: 0 * x is not always +0
  const Lanes ownCentre = lanes(centre), ownVelocity = lanes(velocity);
  struct Relative {
    Lanes pb, vb, v, r;
    double rv, c, reach;
  };
  auto relative = [&](const HotBody& b) {
    Relative m;
    const double dt = now - b.localTime;
    const Lanes step{dt, dt};
    const double half = 0.5 * dt * dt;
    m.pb = (lanes(b.position) + lanes(b.velocity) * step) + zero * Lanes{half, half};
    m.vb = lanes(b.velocity) + zero * step;
    m.v = ownVelocity - m.vb;
    m.r = ownCentre - m.pb;
    const Lanes rv = m.r * m.v, rr = m.r * m.r;
    m.rv = rv[0] + rv[1];
    m.reach = radius + b.radius;
    m.c = (rr[0] + rr[1]) - m.reach * m.reach;
    return m;
  };
  // Two passes. The first, without a branch per pair (whether a pair approaches is a coin toss that
  // the branch predictor loses half the time), keeps the pairs that approach and can meet within the
  // bound as it stands at the start; the second takes them in order with the bound as it tightens. The
  // bound only tightens, so a pair dropped by the first would have been dropped by the second: the
  // pairs whose time of impact is sought are pairPlain()'s.
  // (A crowd beyond the buffer goes to the second pass whole.)
  const bool filtered = count <= kNeighbourBuffer;
  uint32_t kept[kNeighbourBuffer];
  size_t keptCount = 0;
  if (filtered) {
    // The second pass's test, -2 rv within (1 + 1e-9) < c, with a bound a little looser (and worked
    // out once): what it drops, the second pass would have dropped too.
    const double reachLimit = -2 * within * (1 + 4e-9);
    for (size_t k = 0; k < count; ++k) {
      const Relative m = relative(s_.hot[neighbours[k]]);
      const bool far = (m.c > 0) & (m.c > m.rv * reachLimit);
      kept[keptCount] = static_cast<uint32_t>(k);
      keptCount += (m.rv < 0) & !far;
    }
  }
  const size_t tested = filtered ? keptCount : count;
  for (size_t q = 0; q < tested; ++q) {
    const size_t k = filtered ? kept[q] : q;
    const uint32_t j = neighbours[k];
    const HotBody& b = s_.hot[j];
    const Relative m = relative(b);
    const double rv = m.rv;
    if (!(rv < 0)) continue;
    const Vec2 r{m.r[0], m.r[1]}, v{m.v[0], m.v[1]};
    const Vec2 pb{m.pb[0], m.pb[1]}, vb{m.vb[0], m.vb[1]};
    const double reach = m.reach;
    const double c = m.c;
    if (c > 0 && c > -2 * rv * within * (1 + 1e-9)) continue;
    // The LastContact guard: the pair is both bodies' last contact, resolved at this instant.
    bool justResolved = false;
    if (lastNow) {
      const uint32_t low = std::min(fixture, b.fixture), high = std::max(fixture, b.fixture);
      if (cb.lastLow == low && cb.lastHigh == high) {
        const ColdBody& other = s_.cold[j];
        justResolved = other.lastTime == now && other.lastLow == low && other.lastHigh == high && cb.lastFeature == 0;
      }
    }
    double t;
    if (!detail::plainTimeToReach(c, rv, v, reach, within, justResolved, t)) continue;
    const double time = std::min(now + t, horizon);
    if (time > bestTime) continue;
    if (time == bestTime && partner != PredictiveState::kNone) {
      // A tie with the contact held: the total order decides (the contacts differ in the partner only).
      PredictiveEvent e, held;
      e.time = held.time = time;
      e.kind = held.kind = PredictiveKind::Contact;
      e.a = held.a = fixture;
      e.b = b.fixture;
      e.countB = b.collisionCount;
      held.b = s_.hot[partner].fixture;
      held.countB = s_.hot[partner].collisionCount;
      if (!earlier(e, held)) continue;
    }
    // (A contact at the crossing's time comes first: Contact < Cross in the order.)
    bestTime = time;
    partner = j;
    impactTime = t;
    impactR = r;
    impactV = v;
    impactPb = pb;
    impactVb = vb;
    within = searchBound(horizon, bestTime, now);
  }

  const PredictiveEvent best = [&] {
    if (partner == PredictiveState::kNone) {
      return PredictiveEvent{horizon, fixture, fixture, h < kInf ? side : -1, 0, PredictiveKind::Cross};
    }
    const HotBody& b = s_.hot[partner];
    Vec2 point, normal;
    detail::plainContact(impactR, impactV, b.radius, impactTime, point, normal);
    point += impactPb;
    const Vec2 travelOfB = impactVb * impactTime + Vec2{} * (0.5 * impactTime * impactTime);
    return PredictiveEvent{bestTime, fixture, b.fixture, 0, b.collisionCount, PredictiveKind::Contact, partner,
                           point + travelOfB, normal};
  }();
  if ((hb.flags & (HotBody::kStaticNear | HotBody::kSliding)) == 0 && s_.kinematicFixtures.empty()) {
    // Nothing else to look at (finishPrediction()): into the queue.
    schedule(i, best);
    if (i == popped_) popped_ = PredictiveState::kNone;
    return;
  }
  Prediction q;
  q.p.slot = i;
  q.p.now = now;
  q.p.hot = &hb;
  q.p.cold = &cb;
  q.p.position = position;
  q.p.velocity = velocity;
  q.moving = true;
  q.single = true;
  q.plain = true;
  q.horizon = horizon;
  q.best = best;
  finishPrediction(q);
}

template <class W>
void Engine<W>::fillPairs(uint32_t i) {
  // The body's candidate pairs, for the resting rules (World::Impl::supportsAt reads them).
  auto& pairs = w_.pairsOfBody[s_.bodyOfSlot[i]];
  pairs.clear();
  auto add = [&](uint32_t f, uint32_t g) {
    if (w_.canCollide(f, g)) pairs.push_back({f, g});
  };
  forEachNeighbour(i, [&](uint32_t j) {
    forEachPhysical(i, [&](uint32_t f) { forEachPhysical(j, [&](uint32_t g) { add(f, g); }); });
  });
  const size_t cell = cellOf(i);
  for (uint32_t k = s_.staticBegin[cell]; k < s_.staticBegin[cell + 1]; ++k) {
    forEachPhysical(i, [&](uint32_t f) { add(f, s_.staticList[k]); });
  }
  for (uint32_t g : s_.kinematicFixtures) {
    forEachPhysical(i, [&](uint32_t f) { add(f, g); });
  }
}

// ---- The queue -------------------------------------------------------------------------------------

template <class W>
void Engine<W>::resetQueue() {
  const size_t n = s_.hot.size();
  s_.heap.clear();
  s_.queue.assign(n, PredictiveState::QueueSlot{});
  s_.buckets.clearAll();
  s_.overflow.clear();
  s_.inBuckets = s_.inOverflow = 0;
}

template <class W>
void Engine<W>::enqueue(uint32_t slot, double t, uint32_t partner) {
  // Into the heap, a bucket or the overflow array, by its time's bucket (t and partner are
  // event[slot]'s, passed along: the record was most often just written, and reading it back waits for
  // its line).
  const int64_t k = bucketOf(t);
  if (k <= s_.current) {
    s_.heap.push_back({t, slot, partner});
    s_.queue[slot].heapPos = static_cast<int32_t>(s_.heap.size() - 1);
    s_.queue[slot].where = PredictiveState::kInHeap;
    siftUp(s_.heap.size() - 1);
  } else if (k < s_.limit) {
    s_.buckets.push(static_cast<size_t>(k & static_cast<int64_t>(s_.buckets.size() - 1)),
                    {t, slot, ++s_.queue[slot].ticket});
    s_.queue[slot].where = PredictiveState::kInBucket;
    ++s_.inBuckets;
  } else {
    s_.overflow.push_back({t, slot, ++s_.queue[slot].ticket});
    s_.queue[slot].where = PredictiveState::kInOverflow;
    ++s_.inOverflow;
  }
}

template <class W>
void Engine<W>::dequeue(uint32_t slot) {
  const int32_t where = s_.queue[slot].where;
  if (where == PredictiveState::kNotQueued) return;
  s_.queue[slot].where = PredictiveState::kNotQueued;
  if (where == PredictiveState::kInHeap) {
    const size_t k = static_cast<size_t>(s_.queue[slot].heapPos);
    s_.queue[slot].heapPos = -1;
    const detail::HeapNode last = s_.heap.back();
    s_.heap.pop_back();
    if (k == s_.heap.size()) return;
    place(k, last);
    if (k > 0 && before(last, s_.heap[(k - 1) / 4])) {
      siftUp(k);
    } else {
      siftDown(k);
    }
    return;
  }
  ++s_.queue[slot].ticket;  // its entry is left behind, and dropped when read
  --(where == PredictiveState::kInOverflow ? s_.inOverflow : s_.inBuckets);
}

template <class W>
void Engine<W>::retune(double now, bool keepWidth) {
  // A new calendar from `now`: buckets about as wide as the time in which ~32 events fall near now (the
  // density read from the nearest sixteenth of the events, not just a few, which may all be due at once),
  // and enough of them to reach well past most events. `keepWidth`: the buckets of the last calendar
  // again, only laid from `now` (after the times were re-based): the queue is rebuilt without measuring
  // the density (a calendar's cut changes how fast events are found, never their order).
  if (keepWidth && !s_.buckets.empty()) {
    s_.base = now;
    s_.current = bucketOf(now);
    s_.stepBucket = bucketOf(s_.stepEnd);
    s_.limit = roundLimit();
    resetQueue();
    for (uint32_t k = 0; k < s_.hot.size(); ++k) {
      if (s_.event[k].kind != PredictiveKind::None) enqueue(k);
    }
    return;
  }
  std::vector<double>& ahead = s_.scratchTimes;
  ahead.clear();
  const size_t n = s_.hot.size();
  for (uint32_t k = 0; k < n; ++k) {
    const PredictiveEvent& e = s_.event[k];
    if (e.kind != PredictiveKind::None && e.time < kInf) ahead.push_back(std::max(e.time - now, 0.0));
  }
  double span = 0;
  size_t count = 0;
  if (!ahead.empty()) {
    count = std::min<size_t>(ahead.size(), std::max<size_t>(256, ahead.size() / 16));
    std::nth_element(ahead.begin(), ahead.begin() + static_cast<std::ptrdiff_t>(count - 1), ahead.end());
    span = ahead[count - 1];
    if (!(span > 0)) {
      double sum = 0;
      for (double t : ahead) sum += t;
      span = sum / static_cast<double>(ahead.size());
      count = ahead.size();
    }
  }
  double width = span > 0 ? 8 * span / static_cast<double>(count) : 1.0;
  if (!(width > 0) || !std::isfinite(width)) width = 1.0;
  size_t buckets = 16;
  while (buckets < ahead.size() / 8 && buckets < (size_t{1} << 22)) buckets *= 2;
  s_.base = now;
  s_.width = width;
  s_.inverseWidth = 1 / width;
  // Room in each bucket for twice the events it holds on average, stale entries included.
  if (s_.buckets.size() != buckets) {
    s_.buckets.reset(buckets, static_cast<uint32_t>(std::max<size_t>(8, 2 * (ahead.size() / buckets + 1))));
  }
  s_.current = bucketOf(now);
  s_.stepBucket = bucketOf(s_.stepEnd);
  s_.limit = roundLimit();
  resetQueue();
  for (uint32_t k = 0; k < n; ++k) {
    if (s_.event[k].kind != PredictiveKind::None) enqueue(k);
  }
  s_.popsSinceRetune = 0;
}

template <class W>
uint32_t Engine<W>::top() {
  // The earliest event's slot, moving later buckets into the heap as it runs empty.
  while (s_.heap.empty()) {
    // Every event of the buckets up to the step's end has been taken: what is left is due after it.
    if (s_.current >= s_.stepBucket) return PredictiveState::kNone;
    if (s_.inBuckets == 0) {
      if (s_.inOverflow == 0) return PredictiveState::kNone;
      // Nothing left but the overflow: skip to its first bucket.
      int64_t first = int64_t{1} << 62;
      for (const auto& e : s_.overflow) {
        if (s_.queue[e.slot].ticket == e.ticket) first = std::min(first, bucketOf(e.time));
      }
      if (first > s_.stepBucket) return PredictiveState::kNone;
      s_.current = std::max(s_.current, first - 1);
      s_.limit = s_.current + 1;
    }
    ++s_.current;
    if (s_.current >= s_.limit && s_.inOverflow > scheduledCount() / 2 && s_.popsSinceRetune > s_.hot.size() / 4) {
      // A new round of the buckets, and most events are still beyond it: the buckets are too narrow.
      retune(s_.base + static_cast<double>(s_.current) * s_.width);
      continue;
    }
    if (s_.current >= s_.limit) {
      // A new round of the buckets: the overflow events now within reach move in.
      s_.limit = roundLimit();
      std::vector<PredictiveState::QueueEntry> waiting;
      waiting.swap(s_.overflow);
      s_.inOverflow = 0;
      for (const auto& e : waiting) {
        if (s_.queue[e.slot].ticket != e.ticket) continue;
        s_.queue[e.slot].where = PredictiveState::kNotQueued;
        enqueue(e.slot);
      }
      waiting.clear();
      if (s_.overflow.empty()) waiting.swap(s_.overflow);  // keep the memory
    }
    const size_t mask = s_.buckets.size() - 1;
    const size_t here = static_cast<size_t>(s_.current) & mask;
    const auto bucket = s_.buckets[here];
    // The buckets ahead are read a little at a time, so that by the time each moves into the heap what
    // its events read is in cache: three buckets ahead its entries; two ahead the records that its
    // events read first (tickets, event records, the bodies and their partners); one ahead what those
    // records lead to (the cells around the bodies, what a collision reads). A bucket moved in because
    // the heap ran empty hands over its earliest event at once, so this cannot wait until then.
    // (Entries appended since are asked for below, as the bucket moves in.)
    auto ahead = [&](int64_t d) {
      return s_.current + d < s_.limit ? s_.buckets[static_cast<size_t>(s_.current + d) & mask]
                                       : PredictiveState::Buckets::View{nullptr, nullptr};
    };
    {
      const auto later = ahead(3);
      const char* data = reinterpret_cast<const char*>(later.begin());
      for (size_t b = 0; b < later.size() * sizeof(PredictiveState::QueueEntry); b += 64) __builtin_prefetch(data + b);
    }
    for (const auto& e : ahead(2)) {
      __builtin_prefetch(&s_.queue[e.slot]);
      __builtin_prefetch(&s_.event[e.slot]);
      __builtin_prefetch(&s_.hot[e.slot]);
    }
    for (const auto& e : ahead(1)) {
      __builtin_prefetch(&s_.cold[e.slot]);
      prefetchNeighbourhood(e.slot);
      const uint32_t partner = s_.event[e.slot].partner;  // (a stale entry's: a wasted prefetch)
      if (partner != PredictiveState::kNone) {
        __builtin_prefetch(&s_.hot[partner]);
        __builtin_prefetch(&s_.cold[partner]);
      }
    }
    for (const auto& e : bucket) __builtin_prefetch(&s_.queue[e.slot]);
    for (const auto& e : bucket) {
      if (s_.queue[e.slot].ticket != e.ticket) continue;
      // Asked for already, unless appended since (or this is the calendar's first bucket).
      __builtin_prefetch(&s_.cold[e.slot]);
      prefetchNeighbourhood(e.slot);
      const uint32_t partner = s_.event[e.slot].partner;
      if (partner != PredictiveState::kNone) {
        prefetchNeighbourhood(partner);
        // A collision's contact event names the bodies.
        __builtin_prefetch(&s_.bodyOfSlot[e.slot]);
        __builtin_prefetch(&s_.bodyOfSlot[partner]);
      }
      --s_.inBuckets;
      s_.queue[e.slot].heapPos = static_cast<int32_t>(s_.heap.size());
      s_.heap.push_back({e.time, e.slot, partner});
      s_.queue[e.slot].where = PredictiveState::kInHeap;
    }
    s_.buckets.clear(here);
    for (size_t p = s_.heap.size() / 4 + 1; p-- > 0;) {
      if (p < s_.heap.size()) siftDown(p);
    }
  }
  return s_.heap.front().slot;
}

template <class W>
void Engine<W>::siftUp(size_t k) {
  detail::HeapNode* heap = s_.heap.data();
  PredictiveState::QueueSlot* queue = s_.queue.data();
  const detail::HeapNode node = heap[k];
  while (k > 0) {
    const size_t parent = (k - 1) / 4;
    if (!before(node, heap[parent])) break;
    heap[k] = heap[parent];
    queue[heap[k].slot].heapPos = static_cast<int32_t>(k);
    k = parent;
  }
  heap[k] = node;
  queue[node.slot].heapPos = static_cast<int32_t>(k);
}

template <class W>
void Engine<W>::siftDown(size_t k) {
  detail::HeapNode* heap = s_.heap.data();
  PredictiveState::QueueSlot* queue = s_.queue.data();
  const size_t n = s_.heap.size();
  const detail::HeapNode node = heap[k];
  for (;;) {
    const size_t first = 4 * k + 1;
    if (first >= n) break;
    size_t child = first;
    if (first + 4 <= n) {
      // Four children: the earliest by time without branches (which of four is earliest is what a
      // branch predictor cannot guess), unless two of the times are equal, when before() decides.
      const double t0 = heap[first].time, t1 = heap[first + 1].time, t2 = heap[first + 2].time,
                   t3 = heap[first + 3].time;
      const bool b01 = t1 < t0, b23 = t3 < t2;
      const double m01 = b01 ? t1 : t0, m23 = b23 ? t3 : t2;
      const size_t c01 = first + (b01 ? 1 : 0), c23 = first + (b23 ? 3 : 2);
      const bool b = m23 < m01;
      const double m = b ? m23 : m01;
      child = b ? c23 : c01;
      const int equal = (t0 == m) + (t1 == m) + (t2 == m) + (t3 == m);
      if (equal > 1) {
        child = first;
        for (size_t c = first + 1; c < first + 4; ++c) {
          if (before(heap[c], heap[child])) child = c;
        }
      }
    } else {
      for (size_t c = first + 1; c < n; ++c) {
        if (before(heap[c], heap[child])) child = c;
      }
    }
    if (!before(heap[child], node)) break;
    heap[k] = heap[child];
    queue[heap[k].slot].heapPos = static_cast<int32_t>(k);
    k = child;
  }
  heap[k] = node;
  queue[node.slot].heapPos = static_cast<int32_t>(k);
}

template <class W>
void Engine<W>::schedule(uint32_t slot, const PredictiveEvent& e) {
  if (!queueing_) {
    s_.event[slot] = e;
    return;
  }
  if (s_.queue[slot].where == PredictiveState::kInHeap && bucketOf(e.time) <= s_.current) {
    // Stays in the heap: move it up or down.
    s_.event[slot] = e;
    const size_t k = static_cast<size_t>(s_.queue[slot].heapPos);
    s_.heap[k].time = e.time;
    s_.heap[k].partner = e.partner;
    if (k > 0 && before(s_.heap[k], s_.heap[(k - 1) / 4])) {
      siftUp(k);
    } else {
      siftDown(k);
    }
    return;
  }
  dequeue(slot);
  s_.event[slot] = e;
  enqueue(slot, e.time, e.partner);
}

template <class W>
void Engine<W>::unschedule(uint32_t slot) {
  if (queueing_) dequeue(slot);
  s_.event[slot].kind = PredictiveKind::None;
}

// ---- The step --------------------------------------------------------------------------------------

template <class W>
double Engine<W>::endPlain(double end, double& speed) {
  // The step's end in a plain world, for the tracked bodies: attach(), World::Impl::advance() to `end`,
  // the clocks re-based to it and sync(), in one pass over the copies instead of three passes (one over
  // all the BodySlots). Nobody accelerates but by the world's gravity (zero here), sleeps or slides, so
  // sync() would copy back exactly what is written here. Returns the largest coordinate; `speed` grows to
  // the largest speed.
  const Vec2 g = w_.def.gravity;  // every tracked body's BodySlot::acceleration (normalize())
  double extent = 0;
  for (uint32_t slot = 0; slot < s_.hot.size(); ++slot) {
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
    b.last = detail::LastContact{c.lastLow, c.lastHigh, c.lastFeature, lastTime};
    b.lastContactTime = c.lastContactTime;
    h.flags = static_cast<uint8_t>(h.flags & ~HotBody::kDetached);
    extent = std::max({extent, std::fabs(p.x), std::fabs(p.y)});
    speed = std::max(speed, length(v));
  }
  return extent;
}

template <class W>
void Engine<W>::collidePlain(uint32_t i, uint32_t j, const PredictiveEvent& c, double tolerance) {
  // World::Impl::resolve() for two plain disks, on their copies (plain_collision.h); the BodySlots
  // catch up in attach(). The contact event as resolve() writes it.
  const detail::PlainOutcome out =
      detail::resolvePlainDisks({s_.hot[i], s_.cold[i]}, {s_.hot[j], s_.cold[j]}, c, w_.time,
                                w_.def.collapseTime, tolerance);
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
  const bool aIsLower = c.a < c.b;
  const uint32_t lower = aIsLower ? i : j, upper = aIsLower ? j : i;
  ContactEvent event;
  event.time = c.time;
  event.point = c.point;
  event.impulse = out.impulse;
  event.fixtureA = {s_.hot[lower].fixture, s_.cold[lower].fixtureGeneration};
  event.fixtureB = {s_.hot[upper].fixture, s_.cold[upper].fixtureGeneration};
  event.bodyA = {s_.bodyOfSlot[lower], s_.cold[lower].bodyGeneration};
  event.bodyB = {s_.bodyOfSlot[upper], s_.cold[upper].bodyGeneration};
  event.normal = aIsLower ? -c.normal : c.normal;  // c.normal points from c.b toward c.a
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

template <class W>
void Engine<W>::step(double dt) {
  stepLength_ = dt;
  w_.contactEvents.clear();
  w_.sensorEvents.clear();
  w_.sensorEvents.swap(w_.pendingSensorEvents);
  w_.stats = StepStats{};
  // The bodies' candidate pairs are read only by the resting rules and the Zeno guard, which need gravity
  // (fillPairs, World::Impl::supportsAt): a world without it does not make them (a vector a body, fresh
  // memory written at the first step).
  if (!(w_.def.gravity == Vec2{}) && w_.pairsOfBody.size() < w_.bodies.size()) w_.pairsOfBody.resize(w_.bodies.size());

  // 1. Notice what changed since the last step; re-base the clocks to this step's start. After a plain
  // world's step, with nothing touched since, normalize() would change nothing (no gravity, sleep or
  // slide; the Zeno count moves only under gravity) and its gathering was done by endPlain().
  if (s_.normalized && s_.valid && !w_.structureChanged && w_.touchedBodies.empty()) {
    speedScale_ = s_.nextSpeedScale;
    movingKinematic_ = s_.nextMovingKinematic;
    anyAsleep_ = anySliding_ = false;
  } else {
    normalize(dt);
  }
  s_.normalized = false;
  // What the World API changed since the last step (World::Impl::touched): the dynamic bodies touched are
  // predicted again; a change of structure starts afresh.
  bool rebuild = !s_.valid || w_.structureChanged;
  s_.dirty.clear();
  if (!rebuild) {
    rebase(s_.lastStep);
    double extent = s_.endExtent;
    std::vector<uint32_t>& touched = w_.touchedBodies;
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
  if (!rebuild && w_.restitutionChanged) {
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
  w_.startPaths();

  // 2. Events in time order, up to the step's end.
  const double restTolerance = s_.restTolerance;
  const double approachTolerance = s_.approachTolerance;
  // Slots back in cell order (reorder()) once every body has had a few dozen events: by then a body of
  // a dense gas has moved about a cell, and the order has begun to fray (more often cost more than the
  // locality won: 4n pops was 4% slower on the 1e5-disk gas).
  const uint64_t reorderEvery = 16 * static_cast<uint64_t>(s_.hot.size()) + 1024;
  double budgetTime = dt;
  for (;;) {
    if (++s_.popsSinceReorder > reorderEvery) reorder();
    const uint32_t i = top();
    if (i == PredictiveState::kNone) break;
    const PredictiveEvent c = s_.event[i];
    if (!(c.time <= dt)) break;
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
      continue;
    }
    if (c.kind == PredictiveKind::SlideEnd) {
      const uint32_t ia = s_.bodyOfSlot[i];
      attach(i);
      BodySlot& a = w_.bodies[ia];
      if (a.support.generation == 0) {
        ++w_.stats.staleEvents;
        predictBody(i, c.time);
        continue;
      }
      w_.advance(a, c.time);
      w_.stopSliding(a);
      ++a.collisionCount;
      sync(i);
      predictBody(i, c.time);
      continue;
    }

    // A contact. Static and kinematic bodies never change their counters; the body's own event is never
    // stale (PredictiveEvent).
    const uint32_t countA = s_.hot[i].collisionCount;
    if (j != PredictiveState::kNone && s_.hot[j].collisionCount != c.countB) {
      ++w_.stats.staleEvents;
      predictBody(i, c.time);
      continue;
    }
    if (j != PredictiveState::kNone) __builtin_prefetch(&s_.cold[j]);
    // The hybrid step's check at pop: an approach no faster than round-off, with nothing pressing the two
    // together, is not a collision. It is absorbed when the bodies still move, or else dropped.
    Vec2 relativeVelocity, relativeAcceleration;
    {
      const HotBody& ha = s_.hot[i];
      const Vec2 accA = accelerationOf(ha, s_.rare[i]);
      if (j != PredictiveState::kNone) {
        const HotBody& hb = s_.hot[j];
        const Vec2 accB = accelerationOf(hb, s_.rare[j]);
        relativeVelocity = velocityAt(ha, accA, c.time) - velocityAt(hb, accB, c.time);
        relativeAcceleration = accA - accB;
      } else {
        const BodySlot& b = w_.bodyOf(c.b);
        relativeVelocity = velocityAt(ha, accA, c.time) - w_.velocityAt(b, c.time);
        relativeAcceleration = accA - b.acceleration;
      }
    }
    const detail::PredictedContact contact{
        c.time, detail::EventKind::Contact, c.a, c.b, c.feature, countA, c.countB, c.point, c.normal};
    const double vn = dot(relativeVelocity, c.normal);
    const bool pressing = dot(relativeAcceleration, c.normal) < 0;
    const double restTol = restTolerance * (std::fabs(c.point.x) + std::fabs(c.point.y));
    const double tolerance = approachTolerance + restTol;
    if (!(vn < -tolerance) && !pressing) {
      ++w_.stats.staleEvents;
      const double speed = length(relativeVelocity);
      if (vn < -16 * kEps * speed && speed > restTol && w_.stats.eventsProcessed < w_.def.maxEventsPerStep) {
        attach(i);
        if (j != PredictiveState::kNone) attach(j);
        w_.absorb(contact, vn);
        ++w_.stats.eventsProcessed;
        sync(i);
        if (j != PredictiveState::kNone) sync(j);
        predictBody(i, c.time);
        if (j != PredictiveState::kNone) predictBody(j, c.time);
      } else {
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
        list.push_back({c.a, c.b, countA, c.countB});
        predictBody(i, c.time);
      }
      continue;
    }
    if (w_.stats.eventsProcessed >= w_.def.maxEventsPerStep) {
      w_.stats.eventBudgetReached = true;
      budgetTime = c.time;
      break;
    }
    if (plainWorld_ && j != PredictiveState::kNone) {
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
      continue;
    }
    const uint32_t ia = s_.bodyOfSlot[i];
    attach(i);
    if (j != PredictiveState::kNone) attach(j);
    // The resting rules look at the bodies' candidate pairs.
    if (w_.def.restingSpeed > 0 && !(w_.def.gravity == Vec2{})) {
      fillPairs(i);
      if (j != PredictiveState::kNone) fillPairs(j);
    }
    s_.woken.clear();
    w_.resolve(contact, s_.woken, /*zenoGuard=*/true);
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
  }

  // 3. Sensor events, from the paths the bodies took. Then every body to the end of the step (out of
  // budget: to the instant the budget ran out, as the hybrid step does); the clocks start again from there.
  const double end = w_.stats.eventBudgetReached ? budgetTime : dt;
  if (w_.pathLog.active) {
    w_.sensePaths(w_.pathLog, end);
    w_.pathLog.active = false;
  }
  double extent = 0;
  auto toEnd = [&](BodySlot& b) {
    if (b.type == BodyType::Dynamic) {
      w_.advance(b, end);
      if (b.asleep) ++w_.stats.sleeping;
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
  w_.time += dt;
  s_.lastStep = end;
  s_.endExtent = extent;
  // Cut short, the bodies lost the rest of the step: every prediction is off; start afresh.
  if (w_.stats.eventBudgetReached) s_.valid = false;
}

}  // namespace

void World::Impl::stepPredictive(double dt) {
  if (!predictive) predictive = std::make_unique<detail::PredictiveState>();
  Engine<World::Impl>(*this, *predictive).step(dt);
}

}  // namespace rattle
