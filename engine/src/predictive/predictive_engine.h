// The predictive step's Engine: the helpers every part shares and the class, whose members are defined
// by part: predictive_setup.cpp (the tracked bodies and the cell grid), predictive_predictions.cpp (each
// body's next event), predictive_queue.cpp (the calendar of events) and predictive_step.cpp (the step);
// the few that every part calls per event are inline in predictive_engine_inl.h.
// Included only by those; predictive_step.cpp's opening comment describes the mode as a whole.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>

#include "collision/closest_point.h"
#include "collision/path_box.h"
#include "collision/plain_disk_impact.h"
#include "contact/response.h"
#include "contact/resting.h"
#include "contact/squeeze.h"
#include "contact/tolerances.h"
#include "predictive/plain_collision.h"
#include "predictive/predictive_step.h"
#include "rattle/time_of_impact.h"
#include "sensors/sensors.h"
#include "world/world_impl.h"

namespace rattle::predictive {

using detail::BodySlot;
using detail::PathLog;
using detail::PredictiveEvent;
using detail::PredictiveKind;
using detail::PredictiveState;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();

// The total order of events: by time, then kind, then ids (as detail::later, of which this is the
// reverse for contacts), so no two distinct events compare equal.
inline bool earlier(const PredictiveEvent& x, const PredictiveEvent& y) {
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
inline double exitTime(double c, double b, double A) {
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
inline double searchBound(double horizon, double best, double now) {
  return std::min(horizon - now, (best - now) * (1 + 1e-9) + 8 * kEps * (std::fabs(best) + std::fabs(now)) + 1e-300);
}

// The box a fixture sweeps over a time h along its body's path, from position p with velocity v and
// acceleration a (`local`: the fixture's box about its body): the path's box (its ends and turning
// points) grown by the fixture's box.
inline Box sweptBox(const Box& local, Vec2 p, Vec2 v, Vec2 a, double h) {
  const Box path = detail::pathBox(p, v, a, h);
  return Box{path.min + local.min, path.max + local.max};
}

// Whether two boxes are apart by more than the round-off of their coordinates (relative 1e-9, far above
// it): shapes inside them cannot touch, so a time of impact between them would find nothing.
inline bool clearlyApart(const Box& a, const Box& b) {
  const double scale = std::max({std::fabs(a.min.x), std::fabs(a.max.x), std::fabs(a.min.y), std::fabs(a.max.y),
                                 std::fabs(b.min.x), std::fabs(b.max.x), std::fabs(b.min.y), std::fabs(b.max.y)});
  const double margin = 1e-9 * (1 + scale);
  return a.max.x + margin < b.min.x || b.max.x + margin < a.min.x || a.max.y + margin < b.min.y ||
         b.max.y + margin < a.min.y;
}

// Neighbours of one body held on the stack; more (a crowd in a few cells) go to a vector. At least the
// nine cells' heads (Engine::gatherNeighbours).
constexpr size_t kNeighbourBuffer = 128;
static_assert(kNeighbourBuffer >= 9);

// PredictiveState::heads: an entry's first slot, and the entry for a first slot (-1: none) and whether
// more follow.
inline int32_t headSlot(int32_t entry) { return entry < 0 ? -1 : entry >> 1; }
inline int32_t headEntry(int32_t slot, bool more) { return slot < 0 ? -1 : 2 * slot + (more ? 1 : 0); }

// Cell coordinates are clamped to +-kMaxCoord; the cells there reach to infinity.
constexpr int32_t kMaxCoord = int32_t{1} << 30;

// The most entries the cell table takes to cover the static fixtures' region (Engine::buildGrid); the
// bodies' region may take more (a few entries a body). 2^18 entries: 2 MiB of tables.
constexpr size_t kStaticTableLimit = size_t{1} << 18;

inline int32_t cellCoord(double x, double origin, double size) {
  const double k = std::floor((x - origin) / size);
  if (k != k) return 0;  // NaN
  if (k <= -kMaxCoord) return -kMaxCoord;
  if (k >= kMaxCoord) return kMaxCoord;
  return static_cast<int32_t>(k);
}

using detail::ColdBody;
using detail::HotBody;

// Motion of a hot copy: the same expressions as detail::WorldState::positionAt and velocityAt, so the same
// values (the acceleration is read only when it is not zero).
inline Vec2 accelerationOf(const HotBody& h, const detail::RareBody& r) {
  return (h.flags & HotBody::kAccelerating) ? r.acceleration : Vec2{};
}
using detail::positionAt;
using detail::velocityAt;
inline bool isMoving(const HotBody& b) { return !(b.velocity == Vec2{}) || (b.flags & HotBody::kAccelerating) != 0; }
// The common body of a gas: one circle centred on the body, no acceleration, the default filter. Two such
// bodies need nothing from their ColdBody until a contact is found (Engine::pairPlain).
inline bool isPlain(const HotBody& b) {
  constexpr uint8_t mask = HotBody::kSingle | HotBody::kAccelerating | HotBody::kOffCentre | HotBody::kCustomFilter;
  return (b.flags & mask) == HotBody::kSingle;
}

// The contact event of the predicted body's fixture `own` with body `b` (slot `j`): `point` in the world
// at `time`, `normal` from b toward own (PredictiveEvent).
inline PredictiveEvent contactEvent(double time, uint32_t own, const HotBody& b, uint32_t j, int32_t feature,
                                    Vec2 point, Vec2 normal) {
  return PredictiveEvent{time, own, b.fixture, feature, b.collisionCount, PredictiveKind::Contact, j, point, normal};
}

// A body being predicted, as every pair test reads it.
struct Predicting {
  uint32_t slot;
  double now;
  Vec2 position, velocity, acceleration, centre;  // at `now`
  const HotBody* hot;
  const ColdBody* cold;
};

// The predictive step over the world's state (detail::WorldState) and its own (PredictiveState). Indices
// named `i`, `j`, `slot` are slots of tracked bodies (PredictiveState); `body` is an index into
// detail::WorldState::bodies.
// The members on the per-event path that have one caller (top, collideAt, crossCell, endSlide,
// collidePlain, predictCircles, pairPlain, finishPlain, crossingStraight, plainJustResolved) are marked
// [[gnu::always_inline]]: GCC inlines a function called once by itself only when it has internal
// linkage, as they had while the mode was one file, and without it the gas of 10^5 disks took about 10%
// longer (bench/README.md, "The engine's house").
class Engine {
 public:
  Engine(detail::WorldState& w, PredictiveState& s) : w_(w), s_(s) {}
  /// How far the step went: the whole step (dt); 0, having changed nothing the caller sees, when a body
  /// is too fast for the grid this step (kFollowCells); or the instant at which a pile under gravity
  /// (or a driven jam) took a body past kPileCollisions (the world is then at that instant, and the caller steps the rest
  /// of dt otherwise).
  double step(double dt);
  /// Under gravity, a body that collides more than this many times in one step is in a pile that exact
  /// events cannot settle (inelastic collapse: McNamara & Young 1992; docs/numerics.md): the rest of the step,
  /// and the steps after it while the pile is held, go to the hybrid step, whose stepped islands hold
  /// such contacts by a solve (island.cpp, jam.cpp). Without gravity the same holds for a contact of a
  /// body the game drives (BodySlot::driven): a crowd pressed into itself.
  static constexpr int kPileCollisions = 128;
  /// A body that absorbs more round-off approaches than this in one step (absorbOrDismiss) is in a
  /// cluster pressed together at one instant: each absorb leaves its neighbours approaching by round-off
  /// again, the alternating projections of an inelastic collapse. Where piles or jams form, it is handed
  /// over as a pile or a driven jam is.
  static constexpr int kJamAbsorbs = kPileCollisions;
  /// Without gravity, a body past kBurstFollow collisions in the step whose next kBurstCollisions come
  /// each within Islands::kBurstWindow of the step of the one before is collapsing at (nearly) one
  /// instant (collapsing): it hands the step over as a driven body does, at kPileCollisions.
  static constexpr int kBurstFollow = kPileCollisions / 2;
  static constexpr int kBurstCollisions = kPileCollisions / 2;
  /// A body that would cross more cells than this in one step is beyond what cell-crossing events can
  /// follow at a bounded cost (each crossing is an event): such a step is handed to the hybrid step,
  /// which sweeps the whole path at once, and the grid is made again after it.
  static constexpr double kFollowCells = 1024;
  /// Every event taken from the queue (collisions, cell crossings, horizons, slide ends, stale
  /// predictions) counts toward this many times WorldDef::maxEventsPerStep; past it the step ends as at
  /// the event budget, so a step always returns.
  static constexpr int64_t kQueueEventsPerEvent = 16;
  /// A fresh grid with a cell holding more bodies than this (bodies created piled on one point) is a
  /// degenerate start: the step goes to the hybrid step, whose sweep stops at its pair-test budget.
  static constexpr uint32_t kCrowdedCell = 1024;

 private:
  detail::WorldState& w_;
  PredictiveState& s_;
  // The slot whose event was just taken from the queue and is being handled. Its entry stays in the heap
  // until the body's next prediction replaces it in place (one sift instead of a removal and an
  // insertion); until then it counts as having no event.
  uint32_t popped_ = PredictiveState::kNone;
  // Round-off approaches absorbed at pop in this step. Past collapseCollisions() they are left as they
  // are, as the hybrid step leaves a body's past its own count (HybridState::absorbs): near y = 1e9 a
  // disk wedged between two others absorbs against each in turn without end
  // (fuzz/regressions/world_api/budget-predictive-collapse-far-from-the-origin). Counted for the whole
  // step, not a body, so that nothing is reset per body.
  int stepAbsorbs_ = 0;
  // buildGrid()'s parts.
  struct TrackedBounds {
    double diameter, minX, minY, maxX, maxY;
  };
  struct GridShape {
    double size, least;
    uint32_t foldX, foldY;
  };
  TrackedBounds trackBodies();
  GridShape chooseGrid(const TrackedBounds& t);
  // The step's phases (step()) and what runEvents() hands to finishStep().
  bool startStep(double dt);
  void runEvents(double dt);
  void crossCell(uint32_t i, const PredictiveEvent& c);
  void endSlide(uint32_t i, const PredictiveEvent& c);
  bool collideAt(uint32_t i, uint32_t j, const PredictiveEvent& c);
  bool absorbOrDismiss(uint32_t i, uint32_t j, const PredictiveEvent& c, const detail::PredictedContact& contact,
                       double vn, double speed, double velocityScale, double restTol);
  bool collidePlainPair(uint32_t i, uint32_t j, const PredictiveEvent& c, double tolerance);
  bool handsOver(uint32_t most, bool driven) const;
  bool collapsing(uint32_t body, uint32_t stepCollisions, double time);
  double finishStep(double dt);
  double lastChangeBefore(double next) const;
  double budgetTime_ = 0;  // where the step ended, when it ended early
  bool pile_ = false;      // handed over at budgetTime_ (kPileCollisions)
  bool pilesForm_ = false, jamsForm_ = false;
  uint32_t collapseLimit_ = 0;
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
  bool crowdedCell() const;
  void normalize(double dt);
  void rebase(double by);
  void computeConstants(double dt);
  void buildGrid();
  void listStatics();
  Box sceneBox() const;
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
  // Every occupied entry of the table is some tracked body's cell: emptying those empties the table
  // without a write to each entry (it may be far larger than the bodies, covering a large map's walls).
  void emptyOccupiedEntries() {
    for (const HotBody& h : s_.hot) {
      if (h.cell < s_.heads.size()) s_.heads[h.cell] = -1;
    }
  }
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
  /// For a pair with a static or kinematic fixture: kNotDismissed, or the one feature of `other` whose
  /// contact was dismissed (the others are still predicted: the wall beyond a box's corner for a disk
  /// sliding along its floor), or kWholePair when `other` has one feature or several were dismissed.
  static constexpr int kNotDismissed = -2, kWholePair = -3;
  int dismissedFeature(uint32_t slot, uint32_t own, uint32_t other) const;

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
  /// predictPlainAmong's earliest contact so far: with neighbour `partner` (kNone: none), and the pair's
  /// relative motion at `now`, for the contact's point and normal once the search is done.
  struct PlainImpact {
    uint32_t partner = PredictiveState::kNone;
    double time = 0;  // after `now`
    Vec2 r, v, pb, vb;
  };
  /// Whether the pair of `slot` and `other` was resolved at `now` as both bodies' last contact.
  bool plainJustResolved(const ColdBody& own, uint32_t fixture, uint32_t other, double now) const;
  /// Whether a contact of `fixture` with `b` at `time` comes before the one held with `held`, at the same
  /// time, in the events' total order.
  bool beatsHeldContact(double time, uint32_t fixture, const HotBody& b, uint32_t held) const;
  /// The end of predictPlainAmong: the event of the earliest impact (or the cell crossing), scheduled,
  /// or handed to finishPrediction when static or kinematic fixtures or a slide are near.
  void finishPlain(uint32_t slot, double now, Vec2 position, Vec2 velocity, double horizon, double h, int side,
                   double bestTime, const PlainImpact& impact);
  bool predictsPlain(uint32_t slot) const {
    return plainWorld_ && isPlain(s_.hot[slot]) && !dismissals(slot) && isMoving(s_.hot[slot]) &&
           w_.squeezes.empty();
  }
  void crossingStraight(Vec2 centre, Vec2 velocity, const ColdBody& cell, double& h, int& side) const;
  void crossing(const Predicting& p, double& h, int& side) const;
  double centreExit(uint32_t own, uint32_t other, const Polygon& polygon, double now) const;
  /// `dismissed`: a feature of `other` taken as separating (dismissedFeature), or kNoFeature.
  void predictPair(uint32_t own, uint32_t other, double now, double horizon, PredictiveEvent& best,
                   int dismissed = kNoFeature);
  void predictCircles(const Predicting& p, uint32_t j, double horizon, PredictiveEvent& best);
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

}  // namespace rattle::predictive
