// Members of the predictive step's Engine (predictive_engine.h) that other parts call per event or per
// body: the copies brought up to date (sync) and written back (attach), the cell grid's links and
// neighbour walks, and the queue's earliest event (top, which the step takes once an event). Defined
// here, inline, so that the compiler may inline them into every part's file.
#pragma once

#include <vector>

#include "predictive/predictive_engine.h"

namespace rattle::predictive {

inline void Engine::sync(uint32_t slot) {
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
                                 (b.sliding ? HotBody::kSliding : 0));
  s_.rare[slot].acceleration = b.acceleration;
  c.lastTime = b.last.time;
  c.lastLow = b.last.fixtureLow;
  c.lastHigh = b.last.fixtureHigh;
  c.lastFeature = b.last.feature;
  c.inverseMass = b.inverseMass;
  c.lastContactTime = b.lastContactTime;
  c.stepCollisions = static_cast<uint32_t>(b.stepCollisions);
  if (w_.pathLog.active) w_.pathLog.record(s_.bodyOfSlot[slot], {b.localTime, b.position, b.velocity, b.acceleration});
}

inline void Engine::attach(uint32_t slot) {
  // The copy back into the BodySlot, after collisions resolved on the copy (collidePlain): before
  // anything reads the BodySlot, and at the step's end.
  HotBody& h = s_.hot[slot];
  if (!(h.flags & HotBody::kDetached)) return;
  const ColdBody& c = s_.cold[slot];
  BodySlot& b = w_.bodies[s_.bodyOfSlot[slot]];
  w_.keep(b);  // the step's first change of the body itself (step_undo.cpp)
  b.position = h.position;
  b.velocity = h.velocity;
  b.localTime = h.localTime;
  b.collisionCount = h.collisionCount;
  b.setLast(detail::LastContact{c.lastLow, c.lastHigh, c.lastFeature, c.lastTime});
  b.lastContactTime = c.lastContactTime;
  b.stepCollisions = static_cast<int>(c.stepCollisions);
  h.flags = static_cast<uint8_t>(h.flags & ~HotBody::kDetached);
}

inline void Engine::link(uint32_t slot) {
  const size_t cell = cellOf(slot);
  const int32_t head = headSlot(s_.heads[cell]);
  s_.links[slot] = {head, -1};
  if (head >= 0) s_.links[head].prev = static_cast<int32_t>(slot);
  s_.heads[cell] = headEntry(static_cast<int32_t>(slot), head >= 0);
}

inline void Engine::unlink(uint32_t slot) {
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

template <class Visit>
void Engine::forEachNeighbour(uint32_t slot, Visit&& visit) const {
  // The other bodies in the 3 x 3 cells around it (gatherNeighbours()).
  std::vector<uint32_t>& found = s_.visiting;
  gatherNeighbours(slot, found);
  for (uint32_t j : found) visit(j);
}

template <class Visit>
void Engine::forEachPhysical(uint32_t slot, Visit&& visit) const {
  if (s_.hot[slot].flags & HotBody::kSingle) {
    visit(s_.hot[slot].fixture);
    return;
  }
  for (uint32_t f : w_.bodies[s_.bodyOfSlot[slot]].fixtures) {
    if (!w_.fixtures[f].sensor) visit(f);
  }
}

inline size_t Engine::gatherNeighbours(uint32_t slot, uint32_t* out, size_t capacity) const {
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

inline void Engine::gatherNeighbours(uint32_t slot, std::vector<uint32_t>& out) const {
  // The same bodies in the order of the cells, row by row, and of their lists: the general path's order
  // (the resting rules keep the first supports found, detail::supportsAt).
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

[[gnu::always_inline]] inline uint32_t Engine::top() {
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
      // (A stale entry's: wasted prefetches.)
      const PredictiveEvent& event = s_.event[e.slot];
      const uint32_t partner = event.partner;
      if (partner != PredictiveState::kNone) {
        // A collision reads the partner's records and writes its event and its place in the queue.
        __builtin_prefetch(&s_.hot[partner]);
        __builtin_prefetch(&s_.cold[partner]);
        __builtin_prefetch(&s_.queue[partner]);
        __builtin_prefetch(&s_.event[partner], 1);
      }
      // A crossing moves the body from one cell's list to another's.
      if (event.kind == PredictiveKind::Cross) __builtin_prefetch(&s_.links[e.slot]);
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

}  // namespace rattle::predictive
