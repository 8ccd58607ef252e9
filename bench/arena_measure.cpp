// rattle-bench: the arena's error measures (see arena_measure.h).
#include "arena_measure.h"

#include <algorithm>
#include <cmath>

namespace rattle_bench {

namespace {

using rattle::Vec2;

rattle::Box segmentBox(Vec2 a, Vec2 b) {
  return {{std::min(a.x, b.x), std::min(a.y, b.y)}, {std::max(a.x, b.x), std::max(a.y, b.y)}};
}

double distanceToSegment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double q = rattle::dot(ab, ab);
  const double t = q > 0 ? std::clamp(rattle::dot(p - a, ab) / q, 0.0, 1.0) : 0.0;
  return rattle::length(p - (a + t * ab));
}

/// A uniform grid over the points given, `cell` wide: a counting sort of point indices by cell.
struct Grid {
  Vec2 origin;
  double cell = 1;
  int nx = 1, ny = 1;
  std::vector<int> start, order, cellOf;

  Grid(const std::vector<Vec2>& points, double cellSize) : cell(cellSize) {
    Vec2 lo{0, 0}, hi{0, 0};
    if (!points.empty()) lo = hi = points[0];
    for (Vec2 p : points) {
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
    origin = lo;
    // Units stay on the map, so the grid stays small; the cap only guards against a runaway body.
    nx = std::clamp(int((hi.x - lo.x) / cell) + 1, 1, 4096);
    ny = std::clamp(int((hi.y - lo.y) / cell) + 1, 1, 4096);
    start.assign(size_t(nx) * size_t(ny) + 1, 0);
    cellOf.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) {
      cellOf[i] = index(cx(points[i].x), cy(points[i].y));
      ++start[size_t(cellOf[i]) + 1];
    }
    for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    order.resize(points.size());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < points.size(); ++i) order[size_t(fill[size_t(cellOf[i])]++)] = int(i);
  }
  int cx(double x) const { return std::clamp(int((x - origin.x) / cell), 0, nx - 1); }
  int cy(double y) const { return std::clamp(int((y - origin.y) / cell), 0, ny - 1); }
  int index(int x, int y) const { return y * nx + x; }
  /// Calls f(j) for every point j in the cells around (x, y), itself included.
  template <class F>
  void around(int x, int y, F&& f) const {
    for (int y2 = std::max(0, y - 1); y2 <= std::min(ny - 1, y + 1); ++y2)
      for (int x2 = std::max(0, x - 1); x2 <= std::min(nx - 1, x + 1); ++x2) {
        const int c = index(x2, y2);
        for (int k = start[size_t(c)]; k < start[size_t(c) + 1]; ++k) f(order[size_t(k)]);
      }
  }
};

}  // namespace

ArenaWalls::ArenaWalls(const rts::Map& map) {
  for (const rts::MapWall& w : map.walls) {
    const rattle::Geometry g = rattle::normalized(w.shape);
    shapes_.push_back({w.origin, g, rattle::boxOf(g).translated(w.origin), true});
  }
  firstGate_ = shapes_.size();
  for (const rts::MapGate& gate : map.gates) {
    const rattle::Geometry g = rattle::normalized(rattle::Polygon{gate.polygon});
    shapes_.push_back({gate.origin, g, rattle::boxOf(g).translated(gate.origin), true});
  }
}

void ArenaWalls::placeGate(size_t g, Vec2 position, bool standing) {
  Shape& s = shapes_.at(firstGate_ + g);
  s.box = s.box.translated(position - s.position);
  s.position = position;
  s.solidForPaths = standing;
}

bool ArenaWalls::pathBlocked(Vec2 a, Vec2 b) const {
  const rattle::Box box = segmentBox(a, b);
  for (const Shape& s : shapes_)
    if (s.solidForPaths && s.box.overlaps(box) && rattle::rayCast(s.geometry, s.position, a, b - a)) return true;
  return false;
}

double ArenaWalls::distance(Vec2 p, double limit) const {
  const rattle::Box near{{p.x - limit, p.y - limit}, {p.x + limit, p.y + limit}};
  double best = limit;
  for (const Shape& s : shapes_)
    if (s.box.overlaps(near)) best = std::min(best, rattle::distanceTo(s.geometry, p - s.position));
  return best;
}

void measureUnitOverlaps(const std::vector<UnitDisk>& units, const ArenaWalls& walls, OverlapStats& stats) {
  auto record = [&stats](double depth) {
    if (depth > 0) {
      stats.max = std::max(stats.max, depth);
      stats.sum += depth;
      ++stats.count;
    }
  };
  double rmax = 0;
  std::vector<Vec2> points;
  points.reserve(units.size());
  for (const UnitDisk& u : units) {
    rmax = std::max(rmax, u.radius);
    points.push_back(u.position);
    const double d = walls.distance(u.position, u.radius);
    if (d < u.radius) record((u.radius - d) / u.radius);
  }
  // Two disks that overlap have centres less than 2 rmax apart: neighbouring cells of a 2 rmax grid.
  const Grid grid(points, std::max(2 * rmax, 1e-9));
  for (size_t i = 0; i < units.size(); ++i) {
    grid.around(grid.cx(points[i].x), grid.cy(points[i].y), [&](int j) {
      if (size_t(j) <= i) return;  // each pair once
      const double d = rattle::length(points[size_t(j)] - points[i]);
      const double ri = units[i].radius, rj = units[size_t(j)].radius;
      if (d < ri + rj) record((ri + rj - d) / std::min(ri, rj));
    });
  }
}

void BeginTally::tick(std::vector<uint64_t> now, const std::vector<uint64_t>& reportedBegins) {
  std::sort(now.begin(), now.end());
  std::vector<uint64_t> began;
  std::set_difference(now.begin(), now.end(), previous_.begin(), previous_.end(), std::back_inserter(began));
  for (uint64_t k : began) ++perPair_[k][0];
  for (uint64_t k : reportedBegins) ++perPair_[k][1];
  seen_ += static_cast<long long>(began.size());
  reported_ += static_cast<long long>(reportedBegins.size());
  previous_ = std::move(now);
}

long long BeginTally::missed() const {
  long long missed = 0;
  for (const auto& [key, counts] : perPair_) missed += std::max(0ll, counts[0] - counts[1]);
  return missed;
}

std::vector<uint64_t> overlappingSensorPairs(const rts::Game& game) {
  std::vector<uint64_t> pairs;
  std::vector<Vec2> points;
  std::vector<uint32_t> ids;
  double reach = 0;  // the largest sight radius plus body radius
  for (const rts::Unit& u : game.units()) {
    if (!u.alive) continue;
    points.push_back(u.position);
    ids.push_back(u.id);
    reach = std::max(reach, rts::kUnitTypes[u.type].sight + rts::kUnitTypes[u.type].radius);
  }
  // Sight: the observer's sensor circle and an enemy's body circle meet (closed sets: touching counts).
  const Grid grid(points, std::max(reach, 1e-9));
  for (size_t i = 0; i < points.size(); ++i) {
    const rts::Unit& o = game.units()[ids[i]];
    const double sight = rts::kUnitTypes[o.type].sight;
    grid.around(grid.cx(points[i].x), grid.cy(points[i].y), [&](int j) {
      const rts::Unit& t = game.units()[ids[size_t(j)]];
      if (t.team == o.team) return;
      const double r = sight + rts::kUnitTypes[t.type].radius;
      if (rattle::lengthSquared(points[size_t(j)] - points[i]) <= r * r) pairs.push_back(sightKey(o.id, t.id));
    });
  }
  // Doorways: a unit's body meets the doorway's segment.
  const std::vector<rts::MapDoorway>& doorways = game.map().doorways;
  for (size_t d = 0; d < doorways.size(); ++d)
    for (size_t i = 0; i < points.size(); ++i) {
      const rts::Unit& u = game.units()[ids[i]];
      if (distanceToSegment(points[i], doorways[d].a, doorways[d].b) <= rts::kUnitTypes[u.type].radius)
        pairs.push_back(doorwayKey(uint32_t(d), u.id));
    }
  return pairs;
}

ArenaMeter::ArenaMeter(const rts::Game& game) : walls_(game.map()) { before(game); }

void ArenaMeter::before(const rts::Game& game) {
  gatesBefore_.resize(game.gates().size());
  for (size_t g = 0; g < gatesBefore_.size(); ++g) gatesBefore_[g] = game.physics().gatePosition(g);
}

void ArenaMeter::after(const rts::Game& game, bool overlaps) {
  ++ticks_;
  contacts_ += static_cast<long long>(game.physics().world().contactEvents().size());
  for (size_t g = 0; g < gatesBefore_.size(); ++g) {
    const Vec2 at = game.physics().gatePosition(g);
    walls_.placeGate(g, at, at == gatesBefore_[g]);
  }
  // Every shot that moved in the tick: still flying, or removed at its end.
  for (const std::vector<rts::Shot>* list : {&game.shots(), &game.spentShots()})
    for (const rts::Shot& s : *list) {
      if (tunnelled_.size() <= s.id) tunnelled_.resize(size_t(s.id) + 1, 0);
      if (!tunnelled_[s.id] && walls_.pathBlocked(s.previous, s.position)) {
        tunnelled_[s.id] = 1;
        ++tunnelledCount_;
      }
    }
  if (overlaps) {
    disks_.clear();
    for (const rts::Unit& u : game.units())
      if (u.alive) disks_.push_back({u.position, rts::kUnitTypes[u.type].radius});
    measureUnitOverlaps(disks_, walls_, overlaps_);
  }
  reported_.clear();
  const rts::StepEvents& events = game.physics().lastEvents();
  for (const rts::SensorChange& c : events.sight)
    if (c.begin) reported_.push_back(sightKey(c.sensor, c.unit));
  for (const rts::SensorChange& c : events.doorways)
    if (c.begin) reported_.push_back(doorwayKey(c.sensor, c.unit));
  sensors_.tick(overlappingSensorPairs(game), reported_);
}

ArenaTotals ArenaMeter::totals(const rts::Game& game) const {
  ArenaTotals t;
  t.ticks = ticks_;
  t.contacts = contacts_;
  t.tunnelledShots = tunnelledCount_;
  t.overlaps = overlaps_;
  t.sensorBeginsSeen = sensors_.seen();
  t.sensorBeginsReported = sensors_.reported();
  t.sensorMissed = sensors_.missed();
  const rts::GameStats& s = game.stats();
  t.shotsFired = s.shotsFired;
  t.unitHits = s.unitHits;
  t.wallHits = s.wallHits;
  // As rattle-demo's summary counts them: neither a hit nor still flying.
  t.outOfRange = std::max(0l, s.shotsFired - s.unitHits - s.wallHits - long(game.shots().size()));
  t.crossings = s.crossings;
  t.alive[0] = game.alive(0);
  t.alive[1] = game.alive(1);
  return t;
}

}  // namespace rattle_bench
