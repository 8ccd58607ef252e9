// Members of the predictive step's Engine (predictive_engine.h) that every part calls per event or per
// body: the copies brought up to date (sync) and written back (attach), and the cell grid's links and
// neighbour walks. Defined here, inline, so that the compiler may inline them into every part's file.
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

}  // namespace rattle::predictive
