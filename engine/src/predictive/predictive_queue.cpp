// The predictive step's queue of events: a calendar of buckets by time, a 4-ary heap for the current one
// and an overflow array past the last; top() (predictive_engine_inl.h) reads the buckets ahead in stages.
// Part of the predictive step's Engine (predictive_engine.h); predictive_step.cpp's opening comment
// describes the mode as a whole.
#include "predictive/predictive_engine.h"
#include "predictive/predictive_engine_inl.h"

namespace rattle::predictive {

void Engine::resetQueue() {
  const size_t n = s_.hot.size();
  s_.heap.clear();
  s_.queue.assign(n, PredictiveState::QueueSlot{});
  s_.buckets.clearAll();
  s_.overflow.clear();
  s_.inBuckets = s_.inOverflow = 0;
}

void Engine::enqueue(uint32_t slot, double t, uint32_t partner) {
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

void Engine::dequeue(uint32_t slot) {
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

void Engine::retune(double now, bool keepWidth) {
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

void Engine::siftUp(size_t k) {
  const detail::HeapNode* heap = s_.heap.data();
  const detail::HeapNode node = heap[k];
  while (k > 0) {
    const size_t parent = (k - 1) / 4;
    if (!before(node, heap[parent])) break;
    place(k, heap[parent]);
    k = parent;
  }
  place(k, node);
}

void Engine::siftDown(size_t k) {
  const detail::HeapNode* heap = s_.heap.data();
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
    place(k, heap[child]);
    k = child;
  }
  place(k, node);
}

void Engine::schedule(uint32_t slot, const PredictiveEvent& e) {
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

void Engine::unschedule(uint32_t slot) {
  if (queueing_) dequeue(slot);
  s_.event[slot].kind = PredictiveKind::None;
}

}  // namespace rattle::predictive
