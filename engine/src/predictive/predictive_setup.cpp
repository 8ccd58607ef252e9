// The predictive step's setup: the tracked bodies' hot and cold copies, brought up to date with the
// world, and the cell grid they are linked into.
// Part of the predictive step's Engine (predictive_engine.h); predictive_step.cpp's opening comment
// describes the mode as a whole.
#include <algorithm>
#include <vector>

#include "predictive/predictive_engine.h"
#include "predictive/predictive_engine_inl.h"

namespace rattle::predictive {

void Engine::normalize(double dt) {
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
    if (b.sliding &&
        (!w_.fixtures[b.support.fixture].alive || w_.fixtures[b.support.fixture].generation != b.support.generation)) {
      stopSliding(w_, b);
    }
    if (b.type == BodyType::Dynamic && !b.asleep && !b.sliding) b.acceleration = w_.def.gravity;
    if (b.type == BodyType::Dynamic) {
      anyAsleep = anyAsleep || b.asleep;
      anySliding = anySliding || b.sliding;
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

void Engine::rebase(double by) {
  if (by == 0) return;
  // The queue is out of order until the next retune().
  for (PredictiveEvent& e : s_.event) {
    if (e.kind != PredictiveKind::None) e.time -= by;
  }
  for (detail::HeapNode& n : s_.heap) n.time = s_.event[n.slot].time;
  // The bodies' own times (localTime, last.time) were re-based at the end of the last step.
}

void Engine::computeConstants(double dt) {
  const double speedScale = speedScale_;
  const bool movingKinematic = movingKinematic_;
  s_.approachTolerance = detail::kApproachRoundOff * speedScale;
  s_.restTolerance = detail::kRestRoundOff / dt;
  s_.movingKinematic = movingKinematic;
  // Horizon of a prediction that no cell crossing bounds (a body at the far edge of the coordinates, or
  // at rest next to a moving kinematic body): a few dozen cells at the fastest speed.
  s_.capTime = speedScale > 0 ? 32 * s_.cellSize / speedScale : 1.0;
  if (!(s_.capTime > 0) || !std::isfinite(s_.capTime)) s_.capTime = 1.0;
}

// The tracked bodies' copies (HotBody, ColdBody, RareBody) made afresh, in body order, with their
// largest diameter and the box of their centres.
Engine::TrackedBounds Engine::trackBodies() {
  const size_t nb = w_.bodies.size();
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
  return {diameter, minX, minY, maxX, maxY};
}

// The cell size and the table's folds for the tracked bodies (their bounds) and the static fixtures'
// region; sets the grid's origin. `least` is the smallest cell that holds the bodies (before
// sparseCellSize).
Engine::GridShape Engine::chooseGrid(const TrackedBounds& t) {
  const size_t n = s_.hot.size();
  const double diameter = t.diameter, minX = t.minX, minY = t.minY, maxX = t.maxX, maxY = t.maxY;
  // Cell size: the largest diameter, with a margin for round-off in cell crossings. The table: about
  // the bodies' region, at most a few entries per body, or the static fixtures' region (below).
  double size = 1;
  double least = 0;
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
    least = size;
    const Box scene = sceneBox();
    double sceneWidth = scene.max.x - scene.min.x, sceneHeight = scene.max.y - scene.min.y;
    if (!std::isfinite(sceneWidth) || !std::isfinite(sceneHeight)) sceneWidth = sceneHeight = 0;
    size = sparseCellSize(size, std::max({sceneWidth, sceneHeight, diameter}));
    // The table covers the bodies' region, with at most a few entries a body; and the static fixtures'
    // region too, up to kStaticTableLimit entries: on a smaller table the walls of a large map fold onto
    // entries of cells they are nowhere near, and every prediction there tests them for nothing (the
    // demo's arena with 100 units a team: 1,024 entries for its 20,000 cells, and most of a prediction's
    // time went to such walls).
    const double staticCells = (sceneWidth / size + 3) * (sceneHeight / size + 3);
    const double cap = std::max(static_cast<double>(std::max<size_t>(8 * n, 1024)),
                                std::min(staticCells, static_cast<double>(kStaticTableLimit)));
    while (foldX < std::max(width, sceneWidth) / size + 3 && foldX < cap) foldX *= 2;
    while (foldY < std::max(height, sceneHeight) / size + 3 && foldY < cap) foldY *= 2;
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
  return {size, least, foldX, foldY};
}

void Engine::buildGrid() {
  const size_t nb = w_.bodies.size();
  emptyOccupiedEntries();  // the table is all empty (kept if its size stays)
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
  const TrackedBounds tracked = trackBodies();
  const double diameter = tracked.diameter;
  const size_t n = s_.hot.size();
  for (uint32_t slot = 0; slot < n; ++slot) sync(slot);

  const double lastX0 = s_.x0, lastY0 = s_.y0, lastSize = s_.cellSize;
  const uint32_t lastFoldX = s_.foldX, lastFoldY = s_.foldY;
  const GridShape shape = chooseGrid(tracked);
  double size = shape.size;
  const double least = shape.least;
  const uint32_t foldX = shape.foldX, foldY = shape.foldY;
  // The static fixtures listed by cell (below) depend only on them and on the grid: while no static or
  // kinematic body or fixture changed (detail::ChangeLog::staticVersion), a grid as fine and as large as the
  // one just worked out is kept as it was, with its listing. A game that fires a shot or loses a unit
  // (a change of structure, which makes the grid again) then does not list a large map's walls again.
  // The grid's origin is arbitrary (it is unbounded), and a cell as wide as the one chosen, to a part in
  // a thousand, is as good, if it holds the bodies.
  const bool keepStatics = s_.staticsListed && s_.staticVersion == w_.changes.staticVersion && foldX == lastFoldX &&
                           foldY == lastFoldY && lastSize >= least && std::fabs(lastSize - size) <= size / 1024;
  if (keepStatics) {
    size = lastSize;
    s_.x0 = lastX0;
    s_.y0 = lastY0;
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
  if (s_.heads.size() != cells) s_.heads.assign(cells, -1);
  if (!keepStatics) listStatics();  // before the bodies are placed: setCell() reads it
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
  s_.valid = true;
}

void Engine::listStatics() {
  // Static fixtures: in every cell whose region, grown by half a cell (the reach of any dynamic body
  // whose centre is in it), the fixture overlaps. Kinematic bodies' fixtures: in one list.
  const size_t nb = w_.bodies.size();
  const size_t cells = s_.heads.size();
  const double size = s_.cellSize;
  s_.staticBegin.assign(cells + 1, 0);
  s_.staticNear.assign((cells + 63) / 64, 0);
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
  s_.staticVersion = w_.changes.staticVersion;
  s_.staticsListed = true;
}

namespace {

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

}  // namespace

Box Engine::sceneBox() const {
  // The box around every tracked body's centre and every static and kinematic fixture.
  Box box{{kInf, kInf}, {-kInf, -kInf}};
  for (const Vec2 c : s_.centres) box = unionOf(box, Box{c, c});
  for (const BodySlot& b : w_.bodies) {
    if (!b.alive || b.type == BodyType::Dynamic) continue;
    for (uint32_t f : b.fixtures) {
      if (!w_.fixtures[f].sensor) box = unionOf(box, w_.fixtures[f].localBox.translated(b.position));
    }
  }
  return box;
}

double Engine::meanNeighbours(double size) const {
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

double Engine::sparseCellSize(double size, double limit) const {
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

void Engine::reorder(bool fresh) {
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
  // A table much larger than the bodies (one that covers a large map's walls, buildGrid) is mostly
  // empty: its occupied entries are found from the bodies and put in the walk's order by sorting (cheaper
  // than the walk once the table has a few dozen entries a body), and each list is read as the walk would
  // read it, so the order is the same.
  const bool sparseTable = size_t{s_.foldX} * s_.foldY > 32 * n + 1024;
  if (sparseTable) {
    auto spread = [](uint64_t v) {  // gather()'s inverse: v's bits to the even bits
      v &= 0x00000000FFFFFFFFull;
      v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
      v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
      v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
      v = (v | (v << 2)) & 0x3333333333333333ull;
      v = (v | (v << 1)) & 0x5555555555555555ull;
      return v;
    };
    std::vector<uint64_t>& keys = s_.occupied;
    keys.clear();
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t entry = s_.hot[k].cell;
      if (headSlot(s_.heads[entry]) != static_cast<int32_t>(k)) continue;  // one key an occupied entry
      uint32_t x, y;
      unfold(entry, x, y);
      const uint64_t tile = (y / side) * (s_.foldX / side) + x / side;
      const uint64_t walked = tile * side * side + (spread(x % side) | (spread(y % side) << 1));
      keys.push_back((walked << 32) | entry);
    }
    std::sort(keys.begin(), keys.end());  // (few: sortKeys() pays 2^16 counters a pass)
    for (const uint64_t key : keys) {
      for (int32_t k = headSlot(s_.heads[static_cast<uint32_t>(key)]); k >= 0; k = s_.links[k].next) {
        order.push_back(static_cast<uint32_t>(k));
      }
    }
  } else {
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
  if (sparseTable) {
    emptyOccupiedEntries();
  } else {
    std::fill(s_.heads.begin(), s_.heads.end(), -1);
  }
  s_.links.resize(n);
  for (uint32_t k = static_cast<uint32_t>(n); k-- > 0;) link(k);
  s_.popsSinceReorder = 0;
}

int Engine::dismissedFeature(uint32_t slot, uint32_t own, uint32_t other) const {
  const Geometry& g = w_.fixtures[other].geometry;
  const bool several = std::holds_alternative<Polyline>(g) || std::holds_alternative<Polygon>(g);
  const uint32_t countOwn = s_.hot[slot].collisionCount;
  int found = kNotDismissed;
  for (const detail::Dismissal& d : s_.dismissed[slot]) {
    if (d.own != own || d.other != other || d.countOwn != countOwn || d.countOther != countOf(other)) continue;
    // Two features dismissed at once (a corner and its edge) could take turns: the pair is left out.
    if (!several || found != kNotDismissed) return kWholePair;
    found = d.feature;
  }
  return found;
}

bool Engine::isDismissed(uint32_t slot, uint32_t own, uint32_t other) const {
  const uint32_t countOwn = s_.hot[slot].collisionCount;
  for (const detail::Dismissal& d : s_.dismissed[slot]) {
    if (d.own == own && d.other == other && d.countOwn == countOwn && d.countOther == countOf(other)) {
      return true;
    }
  }
  return false;
}

}  // namespace rattle::predictive
