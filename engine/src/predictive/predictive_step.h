// Private: the predictive mode's state, kept from one step to the next (predictive_step.cpp describes
// the method).
//
// Everything is in flat arrays indexed by slot (a tracked body's place in spatial order), table entry or
// heap position, reused from step to step: nothing is allocated per event. Those that grow with the
// bodies or the cells are LargeArrays (large_array.h: 2 MiB pages once large), as the world's own are:
// fewer page faults when a grid is first built, fewer TLB misses when an event reaches into them.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/body_marks.h"
#include "common/large_array.h"
#include "contact/collapse_guard.h"
#include "world/path_log.h"
#include "rattle/types.h"
#include "rattle/vec2.h"

namespace rattle::detail {

enum class PredictiveKind : uint8_t { Contact = 0, SlideEnd = 1, Cross = 2, None = 255 };

// A body's one scheduled event. Contact: `a` is a fixture of the body, `b` the other fixture, `normal`
// from b toward a (as detail::PredictedContact). SlideEnd: `a` the body's first fixture, `b` its support.
// Cross: `a` = `b` = the body's primary fixture; `feature` the cell side it leaves (0: -x, 1: +x, 2: -y,
// 3: +y), or -1 for a mere horizon (the body is predicted again, its cell unchanged).
//
// No counter of the body's own: whatever moves it on (a collision, a slide's end, a change from outside,
// a wake-up) predicts the body again before the next event is taken, which replaces its event. Only the
// partner's counter (`countB`) can go stale. One cache line.
struct alignas(64) PredictiveEvent {
  double time = 0;  // from the start of the current step
  uint32_t a = 0, b = 0;
  int32_t feature = 0;
  uint32_t countB = 0;
  PredictiveKind kind = PredictiveKind::None;
  uint32_t partner = 0xFFFFFFFFu;  // Contact: the slot of b's body, or PredictiveState::kNone
  Vec2 point;
  Vec2 normal;
};

// A contact found not to be approaching (round-off) and dropped: the pair is left out of the body's
// predictions until either body's motion changes (as the hybrid step drops the prediction).
struct Dismissal {
  uint32_t own, other;
  uint32_t countOwn, countOther;
  int32_t feature;  // of `other`: a polyline's or polygon's other features are still predicted
};

// A tracked body's copy of what predictions read, split in three records kept in spatial order
// (bodies of one cell next to each other), so that scanning a neighbourhood touches a few cache lines
// instead of scattered BodySlots. The BodySlot stays the truth; the copy is refreshed whenever the body
// changes. `HotBody` is what every neighbour test reads; `ColdBody` what is read once per prediction of
// the body itself and by a collision of two plain disks; `RareBody` what only a flag calls for (an
// acceleration, a centre off the body's position, a filter other than the default). HotBody and ColdBody
// are one cache line each.
struct alignas(64) HotBody {
  enum : uint8_t {
    kSingle = 1,        // the primary fixture is a Circle and the body's only physical fixture
    kAccelerating = 2,  // acceleration != 0 (in RareBody)
    kOffCentre = 4,     // the circles' centre is not the body's position (in RareBody)
    kCustomFilter = 8,  // the primary fixture's filter is not the default one (in RareBody)
    kSliding = 16,      // BodySlot::support is set
    kDismissals = 32,   // PredictiveState::dismissed holds something for it
    kDetached = 64,     // the BodySlot lags this copy (a plain collision, plain_collision.h); see attach()
    kStaticNear = 128,  // its cell lists static fixtures (PredictiveState::staticBegin), kept with the cell
  };
  Vec2 position;  // at localTime, as BodySlot
  Vec2 velocity;
  double localTime = 0;
  double radius = 0;  // of the primary fixture, when kSingle
  uint32_t collisionCount = 0;
  uint32_t fixture = 0;  // the primary (first physical) fixture
  uint32_t cell = 0;     // where its cell (ColdBody::cx, cy) is folded to: its table entry (PredictiveState::heads)
  uint8_t flags = 0;
};

struct alignas(64) ColdBody {
  double lastTime = -1;  // BodySlot::last
  uint32_t lastLow = 0, lastHigh = 0;
  int32_t lastFeature = -1;
  int32_t cx = 0, cy = 0;  // its cell
  uint32_t stepCollisions = 0;  // BodySlot::stepCollisions (the collapse guard without gravity)
  // The rest of what detail::resolve() reads from two BodySlots and two FixtureSlots, for a
  // collision of two plain disks resolved on the copies (plain_collision.h).
  double inverseMass = 0;
  double restitution = 0;  // of the primary fixture
  double lastContactTime = -std::numeric_limits<double>::infinity();  // BodySlot::lastContactTime
  uint32_t bodyGeneration = 0, fixtureGeneration = 0;
};

// What is read only when a flag of the HotBody says so, kept out of ColdBody so that it fits one cache
// line.
struct RareBody {
  Vec2 acceleration;  // HotBody::kAccelerating
  Vec2 centre;  // the body's circles' common centre, relative to the body (HotBody::kOffCentre)
  uint32_t categoryBits = 0, maskBits = 0;  // the primary fixture's filter (HotBody::kCustomFilter)
  int32_t group = 0;
};

static_assert(sizeof(HotBody) == 64 && sizeof(ColdBody) == 64 && sizeof(PredictiveEvent) == 64);


struct HeapNode {
  double time;
  uint32_t slot;
  uint32_t partner;  // PredictiveEvent::partner, so that the partner's record is asked for early
};

struct PredictiveState {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  bool valid = false;   // false: rebuild everything at the start of the next step
  // A pile under gravity was handed to the hybrid step (Engine::kPileCollisions) and its stepped islands
  // still hold bodies: steps go to the hybrid step until they hold none.
  bool pileHeld = false;
  double lastStep = 0;  // how far the last step moved the bodies' clocks (event times are rebased by it)

  // Per-step constants.
  double approachTolerance = 0;
  double restTolerance = 0;  // without the coordinate factor: 8 eps / dt
  double capTime = 1;        // longest horizon of a prediction when no cell crossing bounds it
  bool movingKinematic = false;

  // The grid: unbounded, folded onto a table. Cell (cx, cy) covers [x0 + cx s, x0 + (cx + 1) s) (and
  // likewise in y; cells at +-kMaxCoord reach to infinity) and lives in the table entry of
  // (cx mod foldX, cy mod foldY); cells far apart may share an entry, which only adds candidates that the
  // time of impact turns down. The table is laid out in tiles of 4 x 4 entries, row by row, each tile
  // row by row (Engine::folded): a tile is one cache line, and the 3 x 3 cells around a body lie in
  // 2.25 lines on average, against 3.4 for rows of the whole table.
  double x0 = 0, y0 = 0, cellSize = 1;
  double hysteresis = 0;          // how far past its cell's side a body goes before it crosses (see buildGrid)
  double extent = 0;              // the largest coordinate of a body when the grid was made
  uint32_t foldX = 4, foldY = 4;  // powers of two, >= 4
  // By table entry. The cells' lists of slots are linked through `links`, a small array of its own (not
  // a field of the bodies' records): walking a neighbourhood's lists then touches a few lines that mostly
  // stay in cache, and the neighbours' records can all be fetched at once (Engine::forEachNeighbour).
  // The first slot in the cell, times two, plus one if more follow it; or -1 for an empty cell. Cells
  // hold less than one body on average in a dense gas: most lists end at their head, and the bit says
  // so without a look at `links`. (Slots are < 2^30: a BodySlot alone is 192 bytes.)
  detail::LargeArray<int32_t> heads;
  detail::LargeArray<uint32_t> staticBegin;  // static fixtures near the cell: staticList[staticBegin[c], staticBegin[c + 1])
  std::vector<uint64_t> staticNear;   // a bit by cell: staticBegin[c] != staticBegin[c + 1] (a table 32 times smaller)
  struct CellLink {
    int32_t next = -1, prev = -1;  // the next and previous slots in the cell's list, or -1
  };
  std::vector<uint32_t> staticList;
  std::vector<uint32_t> kinematicFixtures;  // physical fixtures of kinematic bodies
  // The listing above (staticBegin, staticList, staticNear, kinematicFixtures) was made for this grid at
  // detail::ChangeLog::staticVersion `staticVersion`: buildGrid keeps it while that has not moved on.
  bool staticsListed = false;
  uint64_t staticVersion = 0;

  // Tracked bodies (dynamic, with a physical fixture) have a slot; slots are ordered by cell when the
  // grid is built and re-ordered now and then as bodies move. Everything below is indexed by slot.
  detail::LargeArray<uint32_t> slotOfBody;  // by body index; kNone: not tracked
  std::vector<uint32_t> untracked;   // the kinematic bodies and dynamic ones without a physical fixture
  detail::LargeArray<uint32_t> bodyOfSlot;
  detail::LargeArray<HotBody> hot;
  detail::LargeArray<ColdBody> cold;
  detail::LargeArray<RareBody> rare;
  detail::LargeArray<CellLink> links;
  // Every tracked body is plain (one circle on its centre, the default filter) and no kinematic body has
  // a physical fixture: set by buildGrid. With no gravity, no sensors and nobody asleep, such a world's
  // disk-disk collisions are resolved on the copies (plain_collision.h).
  bool plainShapes = false;
  detail::LargeArray<PredictiveEvent> event;
  detail::LargeArray<std::vector<Dismissal>> dismissed;  // by slot once a contact was dismissed; else empty
  std::vector<uint32_t> dismissedSlots;  // slots whose `dismissed` is not empty
  // Round-off approaches absorbed in the current step, by body (Engine::absorbOrDismiss): only the bodies
  // that absorbed have a count (by body, not slot: reorder() moves slots within a step).
  detail::BodyMarks<uint16_t> absorbs;
  // Engine::collapsing's run of collisions close together, by body: the last one's instant and how many.
  struct Burst {
    double time = -1;
    uint32_t count = 0;
    bool operator==(const Burst&) const = default;
  };
  detail::BodyMarks<Burst> bursts;
  uint64_t popsSinceReorder = 0;
  uint64_t popsSinceRetune = 0;

  double endExtent = 0;  // the largest coordinate of a moving body at the end of the last step
  // What normalize() gathers at a step's start, found instead by a plain world's step end (which visits
  // every moving body anyway): good for the next step if nothing is changed from outside before it.
  bool normalized = false;
  double nextSpeedScale = 0;
  bool nextMovingKinematic = false;

  // The event queue, a calendar (G. Paul, J. Comput. Phys. 221, 615, 2007; Smallenburg 2022): time is cut
  // into buckets of equal width. Events of the current bucket and before are in `heap`, a small 4-ary
  // heap (earliest first, by time and then ids); each later bucket is an unsorted array, and events too
  // far ahead wait in an overflow array. A bucket's events move into the heap when the heap runs empty.
  // The bucket of a time, floor((t - base) / width), never decreases as t grows, so the heap always holds
  // the earliest events. Arrays are appended to and never searched: an entry whose ticket is no longer
  // its slot's is dropped when the bucket is read.
  struct QueueEntry {  // 16 bytes: the partner, which the calendar asks for early, is read from the event
    double time;
    uint32_t slot;
    uint32_t ticket;
  };
  std::vector<HeapNode> heap;
  // By slot, in one record (a queue operation reads and writes them together, one cache line).
  struct QueueSlot {
    int32_t heapPos = -1;     // position in `heap`, or -1
    int32_t where = -1;       // kNotQueued, kInHeap, kInBucket or kInOverflow
    uint32_t ticket = 0;
  };
  detail::LargeArray<QueueSlot> queue;
  // The buckets (a power of two of them): each appended to, read whole and emptied, its memory kept.
  // Each has room for a few entries in one shared array at a place fixed by its index, so an append
  // reads only the bucket's count (a small array that stays in cache) and writes the entry (a store,
  // which does not hold up what follows even when its line is not in cache; appends go all over the
  // calendar). A bucket that outgrows its room moves to an array of its own until it is emptied.
  class Buckets {
   public:
    struct View {
      const QueueEntry* first;
      const QueueEntry* last;
      const QueueEntry* begin() const { return first; }
      const QueueEntry* end() const { return last; }
      size_t size() const { return static_cast<size_t>(last - first); }
    };
    size_t size() const { return count_.size(); }
    bool empty() const { return count_.empty(); }
    // n empty buckets with room for `room` entries each.
    void reset(size_t n, uint32_t room) {
      room_ = std::max<uint32_t>(room, 1);
      shared_.assign(n * room_, QueueEntry{});
      count_.assign(n, 0);
      own_.clear();
      own_.resize(n);
    }
    void push(size_t k, const QueueEntry& e) {
      const uint32_t at = count_[k]++;
      if (at < room_) {
        shared_[k * room_ + at] = e;
      } else {
        pushOwn(k, at, e);
      }
    }
    View operator[](size_t k) const {
      const uint32_t n = count_[k];
      const QueueEntry* first = n <= room_ ? shared_.data() + k * room_ : own_[k].data();
      return {first, first + n};
    }
    void clear(size_t k) {
      if (count_[k] > room_) own_[k].clear();
      count_[k] = 0;
    }
    void clearAll() {
      for (size_t k = 0; k < count_.size(); ++k) clear(k);
    }

   private:
    [[gnu::noinline]] void pushOwn(size_t k, uint32_t at, const QueueEntry& e) {
      std::vector<QueueEntry>& own = own_[k];
      if (at == room_) own.assign(shared_.begin() + static_cast<std::ptrdiff_t>(k * room_),
                                  shared_.begin() + static_cast<std::ptrdiff_t>((k + 1) * room_));
      own.push_back(e);
    }
    uint32_t room_ = 1;
    detail::LargeArray<QueueEntry> shared_;
    std::vector<uint32_t> count_;
    std::vector<std::vector<QueueEntry>> own_;
  };
  Buckets buckets;
  std::vector<QueueEntry> overflow;
  size_t inBuckets = 0, inOverflow = 0;  // live entries
  double base = 0, width = 1, inverseWidth = 1;
  int64_t current = 0;  // the bucket whose events (and all earlier) are in the heap
  int64_t limit = 0;    // events of buckets >= limit wait in the overflow array
  // The step's end and its bucket. The buckets reach no further: events due after the step wait in the
  // overflow array, appended there instead of placed in buckets, and a short step (a frame of a game)
  // lays only its own few events into buckets when the calendar is laid again at its start.
  double stepEnd = 0;
  int64_t stepBucket = 0;
  static constexpr int32_t kNotQueued = -1, kInHeap = -2, kInBucket = -3, kInOverflow = -4;


  // Scratch.
  detail::LargeArray<uint8_t> permuted;  // reorder(): which slots are in place
  detail::LargeArray<Vec2> centres;      // buildGrid(): the tracked bodies' centres, by slot before reorder()
  std::vector<uint32_t> cellCounts;  // Engine::meanNeighbours
  std::vector<uint32_t> neighbours;  // of the body being predicted
  std::vector<uint32_t> visiting;    // Engine::forEachNeighbour
  std::vector<uint32_t> dirty;
  std::vector<uint32_t> woken;
  detail::LargeArray<uint32_t> order;
  std::vector<uint64_t> occupied;  // Engine::reorder on a sparse table: its occupied entries, by walk order
  std::vector<double> scratchTimes;
};

}  // namespace rattle::detail
