// rattle-bench: a baseline for the predictive mode (engine `edmd`): the textbook event-driven hard-disk
// gas, written for this bench alone, with none of rattle's generality.
//
// What someone simulating a dense 2D gas might write instead of using an engine: the method of Alder and
// Wainwright (J. Chem. Phys. 31, 459, 1959) as Rapaport lays it out (J. Comput. Phys. 34, 184, 1980;
// "The Art of Molecular Dynamics Simulation", ch. 14):
//  - disks in a closed axis-aligned box, elastic (restitution 1), no gravity;
//  - a cell grid with cells a little wider than the largest diameter, so that two disks that touch are in
//    the same or neighbouring cells; leaving a cell is an event, after which the disk is predicted again;
//  - one event per disk, the earliest of its collisions with the disks of the 3 x 3 cells around it, its
//    wall hits and its cell crossing; a collision carries the partner's collision counter, and is stale
//    when the partner has collided since (the disk is then predicted again);
//  - the events in a 4-ary heap of (time, disk), keyed in place, ties by disk index;
//  - lazy clocks: a disk is moved only when something happens to it.
// Times of impact: the smaller root of |r + v t| = ra + rb in its cancellation-free form,
// t = c / (-b + sqrt(b^2 - v^2 c)). No round-off guard beyond "touching and separating is no collision".
//
// It serves as a peer measured in the same run (the standards: speed as a ratio against a peer or a
// baseline): the predictive mode's collisions per second against this, on the same scene and machine.
// Only scenes it can run: elastic disks in a closed box (walls exactly the sides of the scene's box, no
// sensors, no gravity, restitution 1: gas, cradle, bullets); others throw EngineCannotRun.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine.h"

namespace rattle_bench {

namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

class EdmdEngine final : public Engine {
 public:
  explicit EdmdEngine(const Scene& scene);
  void step(double dt) override;
  void collect() override {
    collisions += stepCollisions_;
    stepCollisions_ = 0;
  }
  void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const override;

 private:
  enum class Kind : uint8_t { Collision, WallX, WallY, Cross };
  struct Disk {
    Vec2 position;  // at `time`
    Vec2 velocity;
    double time = 0;
    double radius = 0;
    double inverseMass = 0;
    uint32_t count = 0;  // collisions so far: a prediction against this disk carries it
    uint32_t cell = 0;
  };
  struct Event {
    double time = kNever;
    uint32_t partner = 0;       // Collision
    uint32_t partnerCount = 0;  // Collision
    Kind kind = Kind::Cross;
    int8_t dx = 0, dy = 0;  // Cross: the neighbouring cell it enters
  };
  struct HeapNode {
    double time;
    uint32_t disk;
  };

  Vec2 positionAt(const Disk& d, double t) const { return d.position + d.velocity * (t - d.time); }
  void advance(uint32_t i, double t) {
    disks_[i].position = positionAt(disks_[i], t);
    disks_[i].time = t;
  }
  uint32_t cellOf(Vec2 p) const;
  void link(uint32_t i, uint32_t cell);
  void unlink(uint32_t i);
  void predict(uint32_t i, double now);
  // The heap.
  static bool earlier(const HeapNode& a, const HeapNode& b) {
    return a.time < b.time || (a.time == b.time && a.disk < b.disk);
  }
  void siftUp(size_t k);
  void siftDown(size_t k);
  void reschedule(uint32_t i);  // after predict(i)

  std::vector<Disk> disks_;
  std::vector<Event> events_;
  std::vector<HeapNode> heap_;
  std::vector<uint32_t> heapPosition_;
  // Cells: a linked list each (head by cell, next and previous by disk).
  std::vector<int32_t> head_, next_, previous_;
  uint32_t columns_ = 1, rows_ = 1;
  double cellWidth_ = 1, cellHeight_ = 1;
  rattle::Box box_;
  double now_ = 0;
  long long stepCollisions_ = 0;
};

EdmdEngine::EdmdEngine(const Scene& scene) : box_(scene.bounds) {
  const rattle::Box& b = scene.bounds;
  if (!isElasticBox(scene)) {
    throw EngineCannotRun("--engine edmd runs only elastic disks in a closed box without gravity or sensors "
                          "(scenes gas, cradle, bullets), not scene " + scene.name);
  }
  double largest = 0;
  for (const DiskStart& d : scene.disks) largest = std::max(largest, d.radius);
  // Cells a little wider than a diameter, so that round-off in a position near a cell's side cannot hide
  // a touching pair two cells apart.
  const double least = 2 * largest * (1 + 1e-9);
  const Vec2 size = b.max - b.min;
  columns_ = static_cast<uint32_t>(std::clamp(std::floor(size.x / least), 1.0, 1e6));
  rows_ = static_cast<uint32_t>(std::clamp(std::floor(size.y / least), 1.0, 1e6));
  cellWidth_ = size.x / columns_;
  cellHeight_ = size.y / rows_;
  const size_t n = scene.disks.size();
  disks_.resize(n);
  events_.resize(n);
  head_.assign(size_t{columns_} * rows_, -1);
  next_.assign(n, -1);
  previous_.assign(n, -1);
  for (uint32_t i = 0; i < n; ++i) {
    const DiskStart& s = scene.disks[i];
    Disk& d = disks_[i];
    d.position = s.position;
    d.velocity = s.velocity;
    d.radius = s.radius;
    d.inverseMass = 1 / massOf(s);
    link(i, cellOf(s.position));
  }
  for (uint32_t i = 0; i < n; ++i) predict(i, 0);
  heap_.resize(n);
  heapPosition_.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    heap_[i] = {events_[i].time, i};
    heapPosition_[i] = i;
  }
  for (size_t k = n / 4 + 1; k-- > 0;) siftDown(k);
}

uint32_t EdmdEngine::cellOf(Vec2 p) const {
  const double cx = std::floor((p.x - box_.min.x) / cellWidth_), cy = std::floor((p.y - box_.min.y) / cellHeight_);
  const auto clamp = [](double c, uint32_t count) {
    return static_cast<uint32_t>(std::clamp(c, 0.0, static_cast<double>(count - 1)));
  };
  return clamp(cy, rows_) * columns_ + clamp(cx, columns_);
}

void EdmdEngine::link(uint32_t i, uint32_t cell) {
  disks_[i].cell = cell;
  previous_[i] = -1;
  next_[i] = head_[cell];
  if (head_[cell] >= 0) previous_[head_[cell]] = static_cast<int32_t>(i);
  head_[cell] = static_cast<int32_t>(i);
}

void EdmdEngine::unlink(uint32_t i) {
  if (previous_[i] >= 0) {
    next_[previous_[i]] = next_[i];
  } else {
    head_[disks_[i].cell] = next_[i];
  }
  if (next_[i] >= 0) previous_[next_[i]] = previous_[i];
}

void EdmdEngine::predict(uint32_t i, double now) {
  const Disk& a = disks_[i];
  const Vec2 p = positionAt(a, now), v = a.velocity;
  const uint32_t cx = a.cell % columns_, cy = a.cell / columns_;
  Event e;
  // Its cell's sides (the outermost cells reach to the walls: no crossing there).
  auto side = [&](double x, double speed, uint32_t c, uint32_t count, double origin, double width, int8_t& step) {
    if (speed > 0 && c + 1 < count) {
      step = 1;
      return std::max(0.0, (origin + (c + 1) * width - x) / speed);
    }
    if (speed < 0 && c > 0) {
      step = -1;
      return std::max(0.0, (origin + c * width - x) / speed);
    }
    return kNever;
  };
  int8_t sx = 0, sy = 0;
  const double tx = side(p.x, v.x, cx, columns_, box_.min.x, cellWidth_, sx);
  const double ty = side(p.y, v.y, cy, rows_, box_.min.y, cellHeight_, sy);
  if (tx <= ty && tx < kNever) e = {now + tx, 0, 0, Kind::Cross, sx, 0};
  if (ty < tx) e = {now + ty, 0, 0, Kind::Cross, 0, sy};
  // The walls.
  auto wall = [&](double x, double speed, double low, double high) {
    if (speed > 0) return std::max(0.0, (high - a.radius - x) / speed);
    if (speed < 0) return std::max(0.0, (low + a.radius - x) / speed);
    return kNever;
  };
  const double wx = now + wall(p.x, v.x, box_.min.x, box_.max.x);
  if (wx < e.time) e = {wx, 0, 0, Kind::WallX, 0, 0};
  const double wy = now + wall(p.y, v.y, box_.min.y, box_.max.y);
  if (wy < e.time) e = {wy, 0, 0, Kind::WallY, 0, 0};
  // The disks around it.
  for (uint32_t y = cy > 0 ? cy - 1 : 0; y <= std::min(cy + 1, rows_ - 1); ++y) {
    for (uint32_t x = cx > 0 ? cx - 1 : 0; x <= std::min(cx + 1, columns_ - 1); ++x) {
      for (int32_t j = head_[y * columns_ + x]; j >= 0; j = next_[j]) {
        if (static_cast<uint32_t>(j) == i) continue;
        const Disk& b = disks_[j];
        const Vec2 r = p - positionAt(b, now), u = v - b.velocity;
        const double bb = rattle::dot(r, u);
        if (bb >= 0) continue;  // separating
        const double reach = a.radius + b.radius;
        const double c = rattle::dot(r, r) - reach * reach;
        const double uu = rattle::dot(u, u);
        const double disc = bb * bb - uu * c;
        if (disc <= 0) continue;
        const double t = now + (c <= 0 ? 0.0 : c / (-bb + std::sqrt(disc)));
        if (t < e.time || (t == e.time && e.kind == Kind::Collision && static_cast<uint32_t>(j) < e.partner)) {
          e = {t, static_cast<uint32_t>(j), b.count, Kind::Collision, 0, 0};
        }
      }
    }
  }
  events_[i] = e;
}

void EdmdEngine::siftUp(size_t k) {
  const HeapNode x = heap_[k];
  while (k > 0) {
    const size_t parent = (k - 1) / 4;
    if (!earlier(x, heap_[parent])) break;
    heap_[k] = heap_[parent];
    heapPosition_[heap_[k].disk] = static_cast<uint32_t>(k);
    k = parent;
  }
  heap_[k] = x;
  heapPosition_[x.disk] = static_cast<uint32_t>(k);
}

void EdmdEngine::siftDown(size_t k) {
  const size_t n = heap_.size();
  const HeapNode x = heap_[k];
  for (;;) {
    const size_t first = 4 * k + 1;
    if (first >= n) break;
    size_t best = first;
    for (size_t c = first + 1; c < std::min(n, first + 4); ++c) {
      if (earlier(heap_[c], heap_[best])) best = c;
    }
    if (!earlier(heap_[best], x)) break;
    heap_[k] = heap_[best];
    heapPosition_[heap_[k].disk] = static_cast<uint32_t>(k);
    k = best;
  }
  heap_[k] = x;
  heapPosition_[x.disk] = static_cast<uint32_t>(k);
}

void EdmdEngine::reschedule(uint32_t i) {
  const size_t k = heapPosition_[i];
  heap_[k].time = events_[i].time;
  siftUp(k);
  siftDown(heapPosition_[i]);
}

void EdmdEngine::step(double dt) {
  const double end = now_ + dt;
  while (!heap_.empty() && heap_[0].time <= end) {
    const uint32_t i = heap_[0].disk;
    const Event e = events_[i];
    switch (e.kind) {
      case Kind::Collision: {
        const uint32_t j = e.partner;
        if (disks_[j].count != e.partnerCount) break;  // stale: predicted again below
        advance(i, e.time);
        advance(j, e.time);
        Disk& a = disks_[i];
        Disk& b = disks_[j];
        const Vec2 r = a.position - b.position;
        const Vec2 n = r * (1 / rattle::length(r));
        const double vn = rattle::dot(a.velocity - b.velocity, n);
        // Elastic: j = 2 vn / (1/ma + 1/mb) along the line of centres.
        const double impulse = 2 * vn / (a.inverseMass + b.inverseMass);
        a.velocity -= n * (impulse * a.inverseMass);
        b.velocity += n * (impulse * b.inverseMass);
        ++a.count;
        ++b.count;
        ++stepCollisions_;
        predict(j, e.time);
        reschedule(j);
        break;
      }
      case Kind::WallX:
      case Kind::WallY: {
        advance(i, e.time);
        Disk& a = disks_[i];
        if (e.kind == Kind::WallX) {
          a.velocity.x = -a.velocity.x;
        } else {
          a.velocity.y = -a.velocity.y;
        }
        ++a.count;
        ++stepCollisions_;
        break;
      }
      case Kind::Cross: {
        const uint32_t cell = disks_[i].cell;
        unlink(i);
        link(i, cell + static_cast<uint32_t>(e.dy * static_cast<int32_t>(columns_) + e.dx));
        break;
      }
    }
    predict(i, e.time);
    reschedule(i);
  }
  now_ = end;
}

void EdmdEngine::state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const {
  positions.resize(disks_.size());
  velocities.resize(disks_.size());
  for (size_t i = 0; i < disks_.size(); ++i) {
    positions[i] = positionAt(disks_[i], now_);
    velocities[i] = disks_[i].velocity;
  }
}

}  // namespace

bool isElasticBox(const Scene& scene) {
  const rattle::Box& b = scene.bounds;
  auto onSide = [&](const Wall& w) {
    const bool vertical = w.a.x == w.b.x && (w.a.x == b.min.x || w.a.x == b.max.x);
    const bool horizontal = w.a.y == w.b.y && (w.a.y == b.min.y || w.a.y == b.max.y);
    return vertical || horizontal;
  };
  return scene.sensors.empty() && scene.gravity == Vec2{} && scene.restitution == 1 && scene.disksCollide &&
         scene.walls.size() == 4 && std::all_of(scene.walls.begin(), scene.walls.end(), onSide);
}

std::unique_ptr<Engine> makeEdmdEngine(const Scene& scene) { return std::make_unique<EdmdEngine>(scene); }

}  // namespace rattle_bench
