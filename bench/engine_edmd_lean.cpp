// rattle-bench: a second baseline for the predictive mode (engine `edmd-lean`): the event-driven gas
// written for speed alone, to show in the same run what a special-purpose code does where the predictive
// mode's 2e6 collisions/s target lies (issue 4: 10^5 disks at packing 0.5).
//
// The method is `edmd`'s (engine_edmd.cpp: one event per disk, cell crossings, lazy clocks, stale events
// found by the partner's counter), with the ways such codes are made fast (Smallenburg, Eur. Phys. J. E
// 45, 22, 2022; G. Paul, J. Comput. Phys. 221, 615, 2007):
//  - one 64-byte record per disk holds its motion, its counter, its cell and its event, so that an event
//    reads one cache line per disk it touches;
//  - cells a little wider than a diameter hold at most four centres (five points at least a diameter
//    apart need a square 1.41 diameters wide), so a cell is four fixed slots, and the grid has a border of
//    empty cells: the nine cells around a disk are three runs of three with no bounds to test;
//  - the pairs are first sifted without branches (approaching, and close enough to meet before the
//    disk's own horizon), and only those left get a square root and a division;
//  - a calendar queue: buckets of doubly linked lists, the current bucket in a binary heap; as a bucket
//    comes up, the records of the disks due three buckets on are asked for, then their cells, then
//    their neighbours', so that they are in cache by the time they are read.
// What it leaves out, which rattle does on every collision: no contact is reported (rattle writes each
// one's time, point, normal, impulse and handles), no round-off guard, and equal disks only (one radius,
// one mass), and its records stay in the order of the scene, in pages of the default size, which is
// why it slows down past 10^5 disks (rattle keeps its records in cell order, in 2 MiB pages). Scenes:
// equal elastic disks in a box of four walls on its sides (gas, cradle, bullets).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "engine.h"

namespace rattle_bench {

namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();
constexpr uint32_t kEmpty = 0xFFFFFFFFu;
// A disk's event partner: another disk's index, or one of these (a cell side crossed, a wall hit).
constexpr uint32_t kCross = 0xFFFFFFF0u;  // + side: 0 -x, 1 +x, 2 -y, 3 +y
constexpr uint32_t kWallX = 0xFFFFFFE0u, kWallY = 0xFFFFFFE1u;

class EdmdLeanEngine final : public Engine {
 public:
  explicit EdmdLeanEngine(const Scene& scene);
  void step(double dt) override;
  void collect() override {
    collisions += stepCollisions_;
    stepCollisions_ = 0;
  }
  void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const override;

 private:
  struct alignas(64) Disk {
    double x = 0, y = 0, vx = 0, vy = 0;  // position at `time`, velocity
    double time = 0;
    uint32_t count = 0;  // events that changed its motion: a prediction against it carries this
    uint32_t cell = 0;   // in the padded grid
    double eventTime = kNever;
    uint32_t partner = kEmpty;  // kEmpty: no event
    uint32_t partnerCount = 0;
  };
  static_assert(sizeof(Disk) == 64);
  struct Cell {
    uint32_t slot[4];
  };
  struct Link {
    int32_t next = -1, previous = -1;
  };
  static constexpr int64_t kNotQueued = -1, kInHeap = -2;

  void advance(Disk& d, double t) {
    const double dt = t - d.time;
    d.x += d.vx * dt;
    d.y += d.vy * dt;
    d.time = t;
  }
  void predict(uint32_t i, double now);
  void addToCell(uint32_t cell, uint32_t i);
  void removeFromCell(uint32_t cell, uint32_t i);
  // The calendar.
  int64_t bucketOf(double t) const {
    const double k = std::floor((t - base_) / width_);
    return k < 4e18 ? static_cast<int64_t>(k) : int64_t{1} << 62;
  }
  bool before(uint32_t a, uint32_t b) const {
    const double ta = disks_[a].eventTime, tb = disks_[b].eventTime;
    return ta < tb || (ta == tb && a < b);
  }
  void siftUp(size_t k);
  void siftDown(size_t k);
  void enqueue(uint32_t i);
  void dequeue(uint32_t i);
  void prefetchAhead();
  uint32_t top(int64_t last);
  void layCalendar(double now);

  std::vector<Disk> disks_;
  std::vector<Cell> cells_;
  uint32_t columns_ = 1, rows_ = 1, stride_ = 3;  // cells; stride_ = columns_ + 2 (the border)
  double cellWidth_ = 1, cellHeight_ = 1;
  double radius_ = 0, reachSquared_ = 0;
  rattle::Box box_;
  std::vector<Link> links_;     // by disk: its neighbours in its bucket's list
  std::vector<int64_t> where_;  // by disk: its bucket, kInHeap or kNotQueued
  std::vector<int32_t> head_;   // by bucket (mod the bucket count)
  std::vector<uint32_t> heap_;  // disks
  std::vector<uint32_t> heapPosition_;
  uint64_t mask_ = 0;
  double base_ = 0, width_ = 1;
  int64_t current_ = 0;  // the bucket whose events (and all earlier ones) are in the heap
  size_t queued_ = 0;
  bool queueing_ = false;  // false while the first predictions are made: layCalendar() queues them all
  double now_ = 0;
  long long stepCollisions_ = 0;
};

EdmdLeanEngine::EdmdLeanEngine(const Scene& scene) : box_(scene.bounds) {
  const rattle::Box& b = scene.bounds;
  const bool equal =
      !scene.disks.empty() && std::all_of(scene.disks.begin(), scene.disks.end(), [&](const DiskStart& d) {
        return d.radius == scene.disks[0].radius && d.density == scene.disks[0].density;
      });
  if (!isElasticBox(scene) || !equal || !(scene.disks[0].radius > 0)) {
    throw EngineCannotRun(
        "--engine edmd-lean runs only equal elastic disks in a closed box without gravity or "
        "sensors (scenes gas, cradle, bullets), not scene " +
        scene.name);
  }
  radius_ = scene.disks[0].radius;
  reachSquared_ = (2 * radius_) * (2 * radius_);
  const double least = 2 * radius_ * (1 + 1e-9);
  const Vec2 size = b.max - b.min;
  columns_ = static_cast<uint32_t>(std::clamp(std::floor(size.x / least), 1.0, 1e6));
  rows_ = static_cast<uint32_t>(std::clamp(std::floor(size.y / least), 1.0, 1e6));
  cellWidth_ = size.x / columns_;
  cellHeight_ = size.y / rows_;
  if (std::max(cellWidth_, cellHeight_) >= 1.4 * 2 * radius_) {
    throw EngineCannotRun("--engine edmd-lean needs a box many diameters wide (its cells hold four disks at most)");
  }
  stride_ = columns_ + 2;
  cells_.assign(size_t{stride_} * (rows_ + 2), Cell{{kEmpty, kEmpty, kEmpty, kEmpty}});
  const size_t n = scene.disks.size();
  disks_.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    const DiskStart& s = scene.disks[i];
    Disk& d = disks_[i];
    d.x = s.position.x;
    d.y = s.position.y;
    d.vx = s.velocity.x;
    d.vy = s.velocity.y;
    const auto clamp = [](double c, uint32_t count) {
      return static_cast<uint32_t>(std::clamp(c, 0.0, static_cast<double>(count - 1)));
    };
    const uint32_t cx = clamp(std::floor((d.x - b.min.x) / cellWidth_), columns_);
    const uint32_t cy = clamp(std::floor((d.y - b.min.y) / cellHeight_), rows_);
    addToCell((cy + 1) * stride_ + cx + 1, i);
  }
  links_.assign(n, Link{});
  where_.assign(n, kNotQueued);
  heapPosition_.assign(n, 0);
  for (uint32_t i = 0; i < n; ++i) predict(i, 0);
  layCalendar(0);
  queueing_ = true;
}

void EdmdLeanEngine::addToCell(uint32_t cell, uint32_t i) {
  for (uint32_t& s : cells_[cell].slot) {
    if (s == kEmpty) {
      s = i;
      disks_[i].cell = cell;
      return;
    }
  }
  throw std::runtime_error("edmd-lean: five disks in one cell (disks overlap)");
}

void EdmdLeanEngine::removeFromCell(uint32_t cell, uint32_t i) {
  for (uint32_t& s : cells_[cell].slot) {
    if (s == i) s = kEmpty;
  }
}

void EdmdLeanEngine::predict(uint32_t i, double now) {
  // Its earliest event from `now` (it is moved there first): a cell side, a wall (the outermost cells
  // reach to the walls), or a disk of the nine cells around it.
  Disk& d = disks_[i];
  advance(d, now);
  const double x = d.x, y = d.y, vx = d.vx, vy = d.vy;
  const uint32_t cx = d.cell % stride_ - 1, cy = d.cell / stride_ - 1;
  double best = kNever;
  uint32_t partner = kEmpty;
  auto keep = [&](double t, uint32_t p) {
    if (t < best) {
      best = t;
      partner = p;
    }
  };
  auto axis = [&](double p, double v, uint32_t c, uint32_t count, double low, double high, double width, uint32_t wall,
                  uint32_t lowSide) {
    if (v > 0) {
      if (c + 1 == count) {
        keep(std::max(0.0, (high - radius_ - p) / v), wall);
      } else {
        keep(std::max(0.0, (low + (c + 1) * width - p) / v), kCross + lowSide + 1);
      }
    } else if (v < 0) {
      if (c == 0) {
        keep(std::max(0.0, (low + radius_ - p) / v), wall);
      } else {
        keep(std::max(0.0, (low + c * width - p) / v), kCross + lowSide);
      }
    }
  };
  axis(x, vx, cx, columns_, box_.min.x, box_.max.x, cellWidth_, kWallX, 0);
  axis(y, vy, cy, rows_, box_.min.y, box_.max.y, cellHeight_, kWallY, 2);
  // The neighbours, without a branch per slot (whether a slot is taken is a coin toss).
  uint32_t found[36];
  size_t count = 0;
  const Cell* row = &cells_[d.cell - stride_ - 1];
  for (int r = 0; r < 3; ++r, row += stride_) {
    for (int c = 0; c < 3; ++c) {
      for (uint32_t s : row[c].slot) {
        found[count] = s;
        count += (s != kEmpty) & (s != i);
      }
    }
  }
  // First the pairs that approach and can meet before the horizon (|r + u t|^2 - reach^2 >= c + 2 (r.u) t,
  // so none before c / (-2 r.u)), without branches; then their times of impact, the smaller root of
  // |r + u t| = reach in its cancellation-free form c / (-b + sqrt(b^2 - u^2 c)).
  struct Pair {
    double ux, uy, b, c;  // relative velocity; r.u and |r|^2 - reach^2 for the relative position r
  };
  auto pair = [&](uint32_t j) {
    const Disk& o = disks_[j];
    const double dt = now - o.time;
    const double rx = x - (o.x + o.vx * dt), ry = y - (o.y + o.vy * dt);
    const double ux = vx - o.vx, uy = vy - o.vy;
    return Pair{ux, uy, rx * ux + ry * uy, rx * rx + ry * ry - reachSquared_};
  };
  const double horizon = best;
  uint32_t kept[36];
  size_t keptCount = 0;
  for (size_t k = 0; k < count; ++k) {
    const Pair m = pair(found[k]);
    kept[keptCount] = found[k];
    keptCount += (m.b < 0) & !(m.c > -2 * m.b * horizon);
  }
  double bestPair = horizon;
  uint32_t bestPartner = kEmpty;
  for (size_t k = 0; k < keptCount; ++k) {
    const auto [ux, uy, b, c] = pair(kept[k]);
    const double disc = b * b - (ux * ux + uy * uy) * c;
    if (!(disc > 0)) continue;
    const double t = c <= 0 ? 0.0 : c / (-b + std::sqrt(disc));  // touching or overlapping and approaching: now
    if (t < bestPair || (t == bestPair && bestPartner != kEmpty && kept[k] < bestPartner)) {
      bestPair = t;
      bestPartner = kept[k];
    }
  }
  if (bestPartner != kEmpty) {
    best = bestPair;
    partner = bestPartner;
    d.partnerCount = disks_[bestPartner].count;
  }
  if (queueing_) dequeue(i);
  d.eventTime = now + best;
  d.partner = partner;
  if (queueing_ && partner != kEmpty) enqueue(i);
}

void EdmdLeanEngine::siftUp(size_t k) {
  const uint32_t v = heap_[k];
  while (k > 0) {
    const size_t parent = (k - 1) / 2;
    if (!before(v, heap_[parent])) break;
    heap_[k] = heap_[parent];
    heapPosition_[heap_[k]] = static_cast<uint32_t>(k);
    k = parent;
  }
  heap_[k] = v;
  heapPosition_[v] = static_cast<uint32_t>(k);
}

void EdmdLeanEngine::siftDown(size_t k) {
  const uint32_t v = heap_[k];
  const size_t n = heap_.size();
  for (;;) {
    size_t c = 2 * k + 1;
    if (c >= n) break;
    if (c + 1 < n && before(heap_[c + 1], heap_[c])) ++c;
    if (!before(heap_[c], v)) break;
    heap_[k] = heap_[c];
    heapPosition_[heap_[k]] = static_cast<uint32_t>(k);
    k = c;
  }
  heap_[k] = v;
  heapPosition_[v] = static_cast<uint32_t>(k);
}

void EdmdLeanEngine::enqueue(uint32_t i) {
  ++queued_;
  const int64_t bucket = bucketOf(disks_[i].eventTime);
  if (bucket <= current_) {
    heap_.push_back(i);
    where_[i] = kInHeap;
    siftUp(heap_.size() - 1);
    return;
  }
  int32_t& first = head_[static_cast<uint64_t>(bucket) & mask_];
  links_[i] = {first, -1};
  if (first >= 0) links_[first].previous = static_cast<int32_t>(i);
  first = static_cast<int32_t>(i);
  where_[i] = bucket;
}

void EdmdLeanEngine::dequeue(uint32_t i) {
  const int64_t w = where_[i];
  if (w == kNotQueued) return;
  --queued_;
  where_[i] = kNotQueued;
  if (w == kInHeap) {
    const size_t k = heapPosition_[i];
    const uint32_t last = heap_.back();
    heap_.pop_back();
    if (k == heap_.size()) return;
    heap_[k] = last;
    heapPosition_[last] = static_cast<uint32_t>(k);
    if (k > 0 && before(last, heap_[(k - 1) / 2])) {
      siftUp(k);
    } else {
      siftDown(k);
    }
    return;
  }
  const Link l = links_[i];
  if (l.previous >= 0) {
    links_[l.previous].next = l.next;
  } else {
    head_[static_cast<uint64_t>(w) & mask_] = l.next;
  }
  if (l.next >= 0) links_[l.next].previous = l.previous;
}

void EdmdLeanEngine::prefetchAhead() {
  // Three buckets on: the disks' records; two on: their cells and their partners' records; one on: the
  // records of the disks in those cells, and the partners' cells. (Entries of a later year in the same
  // list are prefetched for nothing.)
  auto list = [&](int64_t ahead) { return head_[static_cast<uint64_t>(current_ + ahead) & mask_]; };
  auto prefetchCells = [&](uint32_t cell) {
    const Cell* row = &cells_[cell - stride_ - 1];
    for (int r = 0; r < 3; ++r, row += stride_) {
      __builtin_prefetch(row);
      __builtin_prefetch(row + 2);
    }
  };
  for (int32_t e = list(3); e >= 0; e = links_[e].next) __builtin_prefetch(&disks_[e]);
  for (int32_t e = list(2); e >= 0; e = links_[e].next) {
    const Disk& d = disks_[e];
    prefetchCells(d.cell);
    if (d.partner < kWallX) __builtin_prefetch(&disks_[d.partner]);
  }
  for (int32_t e = list(1); e >= 0; e = links_[e].next) {
    const Disk& d = disks_[e];
    const Cell* row = &cells_[d.cell - stride_ - 1];
    for (int r = 0; r < 3; ++r, row += stride_) {
      for (int c = 0; c < 3; ++c) {
        for (uint32_t s : row[c].slot) {
          if (s != kEmpty) __builtin_prefetch(&disks_[s]);
        }
      }
    }
    if (d.partner < kWallX) prefetchCells(disks_[d.partner].cell);
  }
}

uint32_t EdmdLeanEngine::top(int64_t last) {
  // The earliest event's disk, or kEmpty when none is left in the buckets up to `last` (the step end's).
  while (heap_.empty()) {
    if (queued_ == 0 || current_ >= last) return kEmpty;
    ++current_;
    prefetchAhead();
    int32_t& first = head_[static_cast<uint64_t>(current_) & mask_];
    for (int32_t e = first; e >= 0;) {
      const int32_t next = links_[e].next;
      if (where_[e] == current_) {  // (the list also holds events of later years)
        const Link l = links_[e];
        if (l.previous >= 0) {
          links_[l.previous].next = l.next;
        } else {
          first = l.next;
        }
        if (l.next >= 0) links_[l.next].previous = l.previous;
        where_[e] = kInHeap;
        heap_.push_back(static_cast<uint32_t>(e));
        siftUp(heap_.size() - 1);
      }
      e = next;
    }
  }
  return heap_[0];
}

void EdmdLeanEngine::layCalendar(double now) {
  // Buckets as wide as the time in which about eight events fall, from the mean time to the disks' next
  // events (the capped mean: a few disks with none for long would stretch it), and n / 2 of them (a
  // power of two): a year of buckets reaches about four mean times ahead.
  const size_t n = disks_.size();
  double sum = 0;
  size_t counted = 0;
  for (const Disk& d : disks_) {
    if (d.partner == kEmpty) continue;
    sum += std::min(d.eventTime - now, 1e3);
    ++counted;
  }
  const double mean = counted > 0 ? sum / static_cast<double>(counted) : 1.0;
  width_ = mean > 0 ? 8 * mean / static_cast<double>(std::max<size_t>(counted, 1)) : 1.0;
  if (!(width_ > 0) || !std::isfinite(width_)) width_ = 1.0;
  size_t buckets = 16;
  while (buckets < n / 2) buckets *= 2;
  mask_ = buckets - 1;
  head_.assign(buckets, -1);
  heap_.clear();
  base_ = now;
  current_ = bucketOf(now);
  queued_ = 0;
  for (uint32_t i = 0; i < n; ++i) {
    where_[i] = kNotQueued;
    if (disks_[i].partner != kEmpty) enqueue(i);
  }
}

void EdmdLeanEngine::step(double dt) {
  const double end = now_ + dt;
  layCalendar(now_);  // the rate of events changes as a gas settles: the buckets are cut again each step
  const int64_t last = bucketOf(end);
  for (;;) {
    const uint32_t i = top(last);
    if (i == kEmpty) break;
    Disk& d = disks_[i];
    const double t = d.eventTime;
    if (t > end) break;
    const uint32_t p = d.partner;
    if (p >= kCross) {
      advance(d, t);
      const uint32_t side = p - kCross;
      const uint32_t cell = d.cell;
      removeFromCell(cell, i);
      addToCell(side == 0 ? cell - 1 : side == 1 ? cell + 1 : side == 2 ? cell - stride_ : cell + stride_, i);
      predict(i, t);
      continue;
    }
    if (p == kWallX || p == kWallY) {
      advance(d, t);
      if (p == kWallX) {
        d.vx = -d.vx;
      } else {
        d.vy = -d.vy;
      }
      ++d.count;
      ++stepCollisions_;
      predict(i, t);
      continue;
    }
    Disk& o = disks_[p];
    if (o.count != d.partnerCount) {  // stale: the partner's motion changed since
      predict(i, t);
      continue;
    }
    advance(d, t);
    advance(o, t);
    // Equal masses, elastic: each takes the other's normal velocity.
    const double nx = d.x - o.x, ny = d.y - o.y;
    const double inverse = 1 / std::sqrt(nx * nx + ny * ny);
    const double ux = nx * inverse, uy = ny * inverse;
    const double vn = (d.vx - o.vx) * ux + (d.vy - o.vy) * uy;
    if (vn < 0) {
      d.vx -= vn * ux;
      d.vy -= vn * uy;
      o.vx += vn * ux;
      o.vy += vn * uy;
    }
    ++d.count;
    ++o.count;
    ++stepCollisions_;
    predict(i, t);
    predict(p, t);
  }
  now_ = end;
}

void EdmdLeanEngine::state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const {
  positions.resize(disks_.size());
  velocities.resize(disks_.size());
  for (size_t i = 0; i < disks_.size(); ++i) {
    const Disk& d = disks_[i];
    const double dt = now_ - d.time;
    positions[i] = {d.x + d.vx * dt, d.y + d.vy * dt};
    velocities[i] = {d.vx, d.vy};
  }
}

}  // namespace

std::unique_ptr<Engine> makeEdmdLeanEngine(const Scene& scene) { return std::make_unique<EdmdLeanEngine>(scene); }

}  // namespace rattle_bench
