#include "game/navigation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace rts {
namespace {

constexpr size_t kCacheSize = 48;
constexpr float kInf = std::numeric_limits<float>::infinity();

bool insideConvex(const std::vector<Vec2>& poly, Vec2 p) {
  bool pos = false, neg = false;
  for (size_t i = 0; i < poly.size(); ++i) {
    double c = rattle::cross(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]);
    pos |= c > 0;
    neg |= c < 0;
  }
  return !(pos && neg);
}

}  // namespace

Navigation::Navigation(const Map& map, const Physics& physics, const std::vector<double>& clearances) {
  nx_ = std::max(1, int(std::ceil(map.width)));
  ny_ = std::max(1, int(std::ceil(map.height)));
  const size_t cells = size_t(nx_) * size_t(ny_);
  for (const MapRoom& r : map.rooms) rooms_.push_back(r.polygon);
  for (double clearance : clearances) {
    Layer l;
    l.blocked.assign(cells, 0);
    l.gateClosed.assign(cells, 0);
    l.gateOpen.assign(cells, 0);
    for (size_t c = 0; c < cells; ++c) {
      const Vec2 p = centre(int(c));
      l.blocked[c] = !physics.freeOfStaticWalls(p, clearance);
      for (size_t g = 0; g < map.gates.size() && g < 32; ++g) {
        if (physics.gateBlocks(g, false, p, clearance)) l.gateClosed[c] |= 1u << g;
        if (physics.gateBlocks(g, true, p, clearance)) l.gateOpen[c] |= 1u << g;
      }
    }

    // Only what can be walked to from a spawn point is the playing area (gates open or shut); the rest
    // (outside the outer wall, inside closed buildings) is blocked, so a target out there is moved to
    // the nearest place a unit can really reach.
    std::vector<uint8_t> reached(cells, 0);
    std::vector<int> stack;
    for (const MapSpawn& s : map.spawns) {
      const int c = cellAt(s.position);
      if (!l.blocked[size_t(c)] && !reached[size_t(c)]) {
        reached[size_t(c)] = 1;
        stack.push_back(c);
      }
    }
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      const int x = c % nx_, y = c / nx_;
      const int next[4] = {x > 0 ? c - 1 : -1, x + 1 < nx_ ? c + 1 : -1, y > 0 ? c - nx_ : -1, y + 1 < ny_ ? c + nx_ : -1};
      for (int n : next) {
        if (n < 0 || reached[size_t(n)] || l.blocked[size_t(n)]) continue;
        reached[size_t(n)] = 1;
        stack.push_back(n);
      }
    }
    for (size_t c = 0; c < cells; ++c) l.blocked[c] |= !reached[c];
    layers_.push_back(std::move(l));
  }
}

int Navigation::cellAt(Vec2 p) const {
  const int x = std::clamp(int(std::floor(p.x)), 0, nx_ - 1);
  const int y = std::clamp(int(std::floor(p.y)), 0, ny_ - 1);
  return y * nx_ + x;
}

Vec2 Navigation::centre(int cell) const { return {double(cell % nx_) + 0.5, double(cell / nx_) + 0.5}; }

bool Navigation::walkable(int cell, uint32_t gatesOpen, int layer) const {
  const size_t c = size_t(cell);
  const Layer& l = layers_[size_t(layer)];
  return !l.blocked[c] && !(l.gateClosed[c] & ~gatesOpen) && !(l.gateOpen[c] & gatesOpen);
}

int Navigation::roomAt(Vec2 p) const {
  for (size_t i = 0; i < rooms_.size(); ++i) {
    if (insideConvex(rooms_[i], p)) return int(i);
  }
  return -1;
}

std::shared_ptr<const FlowField> Navigation::field(Vec2 target, uint32_t gatesOpen, uint32_t tick, int layer) {
  int cell = cellAt(target);
  // A target inside a wall: start from the nearest walkable cell (in rings, lowest index first).
  if (!walkable(cell, gatesOpen, layer)) {
    const int tx = cell % nx_, ty = cell / nx_;
    int best = -1;
    for (int r = 1; r < std::max(nx_, ny_) && best < 0; ++r) {
      for (int y = std::max(0, ty - r); y <= std::min(ny_ - 1, ty + r) && best < 0; ++y) {
        for (int x = std::max(0, tx - r); x <= std::min(nx_ - 1, tx + r); ++x) {
          if (walkable(y * nx_ + x, gatesOpen, layer)) {
            best = y * nx_ + x;
            break;
          }
        }
      }
    }
    if (best >= 0) cell = best;
  }
  return fieldForCell(cell, gatesOpen, tick, layer);
}

std::shared_ptr<const FlowField> Navigation::fieldForCell(int cell, uint32_t gatesOpen, uint32_t tick, int layer) {
  for (Cached& c : cache_) {
    if (c.field->targetCell == cell && c.field->gatesOpen == gatesOpen && c.field->layer == layer) {
      c.lastUsed = tick;
      return c.field;
    }
  }
  std::shared_ptr<const FlowField> made = build(cell, gatesOpen, layer);
  if (cache_.size() >= kCacheSize) {
    // Evict the least recently used (the first such, so the choice is reproducible).
    size_t oldest = 0;
    for (size_t i = 1; i < cache_.size(); ++i) {
      if (cache_[i].lastUsed < cache_[oldest].lastUsed) oldest = i;
    }
    cache_.erase(cache_.begin() + long(oldest));
  }
  cache_.push_back({made, tick});
  return made;
}

std::shared_ptr<const FlowField> Navigation::build(int targetCell, uint32_t gatesOpen, int layer) const {
  auto f = std::make_shared<FlowField>();
  f->targetCell = targetCell;
  f->gatesOpen = gatesOpen;
  f->layer = layer;
  f->distance.assign(size_t(nx_) * size_t(ny_), kInf);
  // Dijkstra with straight steps of 1 and diagonal steps of sqrt(2), never cutting a blocked corner.
  // Distances are floats built from the same additions in the same order every time.
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  f->distance[size_t(targetCell)] = 0;
  open.push({0.0f, targetCell});
  const float diagonal = 1.41421356f;
  while (!open.empty()) {
    auto [d, c] = open.top();
    open.pop();
    if (d > f->distance[size_t(c)]) continue;
    const int x = c % nx_, y = c / nx_;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const int X = x + dx, Y = y + dy;
        if (X < 0 || Y < 0 || X >= nx_ || Y >= ny_) continue;
        const int n = Y * nx_ + X;
        if (!walkable(n, gatesOpen, layer)) continue;
        if (dx && dy && (!walkable(y * nx_ + X, gatesOpen, layer) || !walkable(Y * nx_ + x, gatesOpen, layer))) continue;
        const float nd = d + (dx && dy ? diagonal : 1.0f);
        if (nd < f->distance[size_t(n)]) {
          f->distance[size_t(n)] = nd;
          open.push({nd, n});
        }
      }
    }
  }
  return f;
}

double Navigation::distance(const FlowField& f, Vec2 p) const { return f.distance[size_t(cellAt(p))]; }

Vec2 Navigation::direction(const FlowField& f, Vec2 p) const {
  const int c = cellAt(p);
  const int x = c % nx_, y = c / nx_;
  const float here = f.distance[size_t(c)];
  // Downhill: the steepest descent over the eight neighbours, each weighted by how much lower it is
  // per unit of distance, summed; straight runs come out straight, not in 45-degree zigzags.
  Vec2 sum{0, 0};
  int bestCell = -1;
  float bestDistance = here;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const int X = x + dx, Y = y + dy;
      if (X < 0 || Y < 0 || X >= nx_ || Y >= ny_) continue;
      const int n = Y * nx_ + X;
      const float d = f.distance[size_t(n)];
      if (!(d < kInf)) continue;
      if (d < bestDistance) {
        bestDistance = d;
        bestCell = n;
      }
      if (here < kInf && d < here) {
        const double length = (dx && dy) ? 1.4142135623730951 : 1.0;
        sum += Vec2{double(dx), double(dy)} * (double(here - d) / (length * length));
      }
    }
  }
  if (c == f.targetCell) return {0, 0};
  if (here < kInf && rattle::length(sum) > 1e-9) return sum * (1.0 / rattle::length(sum));
  // Off the walkable grid (pushed against a wall): head for the best neighbour's centre.
  if (bestCell >= 0) {
    const Vec2 d = centre(bestCell) - p;
    const double l = rattle::length(d);
    if (l > 1e-9) return d * (1.0 / l);
  }
  return {0, 0};
}

}  // namespace rts
