// Units: where they start, how they take orders, how they steer.
//
// Steering: each tick a unit wants its top speed down its group's flow field (navigation.h), slowing
// down on the last stretch, never into a wall it touched lately. Then it keeps clear of the units
// around it (keepApart): it never moves toward another unit faster than leaves a gap between them at
// the end of the tick, so units do not collide at all while they move as steered. The engine still
// guarantees that nothing overlaps or passes through a wall; it just has almost nothing to resolve. A
// crowd driven into itself instead cost the engine a collision per unit per tick (90,000 a tick at
// 10,000 units), and queues, arrival and making way are rules here rather than side effects of shoving.
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "game/game.h"

namespace rts {
namespace {

Vec2 normalizedOr(Vec2 v, Vec2 fallback) {
  double l = rattle::length(v);
  return l > 1e-12 ? v * (1.0 / l) : fallback;
}


}  // namespace

// Units fill the free places nearest to their team's spawn points: a best-first flood over a grid of
// candidate places (the spacing of a packed crowd of the smallest type), reaching only places a unit
// could walk to, nearest to the spawn point first. Each team's units take places in id order, each
// with its own type's size: a place is taken only when that unit, at its radius, is clear of the walls
// and of every unit placed before it. Spawn points of both teams take turns, so large armies meet
// halfway.
void Game::placeUnits() {
  const std::vector<uint8_t>& deal = config_.unitTypes;
  auto typeOf = [&](size_t n) -> const UnitType& { return kUnitTypes[deal[n % deal.size()]]; };
  double smallest = std::numeric_limits<double>::infinity(), largest = 0;
  for (uint8_t t : deal) {
    smallest = std::min(smallest, kUnitTypes[t].radius);
    largest = std::max(largest, kUnitTypes[t].radius);
  }
  constexpr double kApart = 0.1;  // left between units placed side by side
  const double spacing = 2 * smallest + kApart;
  const int nx = std::max(1, int(map_.width / spacing)), ny = std::max(1, int(map_.height / spacing));
  const size_t cells = size_t(nx) * size_t(ny);
  if (cells > 50'000'000) throw GameError("the map is too large to place units on");
  auto center = [&](int64_t c) { return Vec2{(double(c % nx) + 0.5) * spacing, (double(c / nx) + 0.5) * spacing}; };
  enum : uint8_t { kUnknown, kFree, kBlocked };
  std::vector<uint8_t> state(cells, kUnknown);
  // The radius of the unit placed in each cell, 0 for none.
  std::vector<double> taken(cells, 0);
  auto isFree = [&](int64_t c) {
    if (state[size_t(c)] == kUnknown) state[size_t(c)] = physics_.freeOfWalls(center(c), smallest + 0.05) ? kFree : kBlocked;
    return state[size_t(c)] == kFree;
  };
  // Whether a unit of this type fits at cell c: a larger one must also clear the walls at its own
  // radius, and keep kApart from the units already placed (on a grid of one size, neighbours always
  // do: the tolerance keeps round-off in the cell centres from refusing them).
  const int reach = int(std::ceil((smallest + largest + kApart) / spacing));
  auto fits = [&](int64_t c, const UnitType& type) {
    if (taken[size_t(c)] > 0) return false;
    if (type.radius > smallest && !physics_.freeOfWalls(center(c), type.radius + 0.05)) return false;
    const int x = int(c % nx), y = int(c / nx);
    for (int Y = std::max(0, y - reach); Y <= std::min(ny - 1, y + reach); ++Y) {
      for (int X = std::max(0, x - reach); X <= std::min(nx - 1, x + reach); ++X) {
        const int64_t o = int64_t(Y) * nx + X;
        if (taken[size_t(o)] <= 0) continue;
        const double apart = type.radius + taken[size_t(o)] + kApart - 1e-9;
        if (lengthSquared(center(o) - center(c)) < apart * apart) return false;
      }
    }
    return true;
  };

  struct Flood {
    int team;
    Vec2 origin;
    std::vector<uint8_t> seen;
    // (squared distance, cell): nearest first, lower cell index on ties.
    std::priority_queue<std::pair<double, int64_t>, std::vector<std::pair<double, int64_t>>, std::greater<>> frontier;
  };
  std::vector<Flood> floods;
  for (const MapSpawn& s : map_.spawns) {
    Flood f{s.team, s.position, std::vector<uint8_t>(cells, 0), {}};
    int64_t c = int64_t(std::min(ny - 1, int(s.position.y / spacing))) * nx + std::min(nx - 1, int(s.position.x / spacing));
    if (!isFree(c)) {
      throw GameError(map_.source + ": object " + std::to_string(s.objectId) +
                      ": the spawn point is inside or against a wall; move it into the open");
    }
    f.seen[size_t(c)] = 1;
    f.frontier.push({lengthSquared(center(c) - s.position), c});
    floods.push_back(std::move(f));
  }

  std::array<std::vector<Vec2>, 2> places;
  const size_t want = size_t(config_.unitsPerTeam);
  bool progress = true;
  while (progress && (places[0].size() < want || places[1].size() < want)) {
    progress = false;
    for (Flood& f : floods) {
      std::vector<Vec2>& mine = places[size_t(f.team)];
      if (mine.size() >= want) continue;
      const UnitType& type = typeOf(mine.size());
      while (!f.frontier.empty()) {
        auto [d2, c] = f.frontier.top();
        f.frontier.pop();
        const int x = int(c % nx), y = int(c / nx);
        const int64_t next[4] = {x > 0 ? c - 1 : -1, x + 1 < nx ? c + 1 : -1, y > 0 ? c - nx : -1, y + 1 < ny ? c + nx : -1};
        for (int64_t n : next) {
          if (n < 0 || f.seen[size_t(n)]) continue;
          f.seen[size_t(n)] = 1;
          if (isFree(n) && physics_.clearLine(center(c), center(n))) {
            f.frontier.push({lengthSquared(center(n) - f.origin), n});
          }
        }
        if (fits(c, type)) {
          taken[size_t(c)] = type.radius;
          mine.push_back(center(c));
          progress = true;
          break;
        }
      }
    }
  }
  for (int team = 0; team < 2; ++team) {
    if (places[size_t(team)].size() < want) {
      throw GameError(map_.source + ": room for only " + std::to_string(places[size_t(team)].size()) + " units of team " +
                      std::to_string(team) + " within reach of its spawn points, " + std::to_string(want) + " asked");
    }
  }
  // Ids alternate between the teams, so "the first n units" is fair to both.
  for (size_t i = 0; i < want; ++i) {
    const UnitType& type = typeOf(i);
    for (int team = 0; team < 2; ++team) {
      Unit u;
      u.id = uint32_t(units_.size());
      u.team = uint8_t(team);
      u.type = deal[i % deal.size()];
      u.hitPoints = type.hitPoints;
      const int reload = int(std::lround(type.reload * kTicksPerSecond));
      u.reloadTicks = int(u.id % uint32_t(reload));  // staggered, so volleys do not all land on one tick
      u.position = u.previous = places[size_t(team)][i];
      u.body = physics_.addUnit(u.id, team, u.position, type);
      units_.push_back(std::move(u));
      ++aliveCount_[team];
    }
  }
}

void Game::orderMove(Unit& u, Vec2 target, double arrivalRadius, std::shared_ptr<const FlowField> field) {
  u.order = Order{};
  if (!(navigation_.distance(*field, u.position) < std::numeric_limits<double>::infinity())) return;  // no way there now
  u.order.active = true;
  u.order.target = target;
  u.order.arrivalRadius = arrivalRadius;
  u.order.field = std::move(field);
  u.order.bestDistance = std::numeric_limits<double>::infinity();
}

// A unit on the last stretch that bumps into a unit of its own side that has stopped near the same
// place has arrived: the places nearer the target are taken (keepApart applies the same rule before the
// bump; this one catches what a wall or a shot deflected into a contact). Walls touched are remembered
// for a few ticks (see alongTouches).
void Game::onBump(const UnitContact& c) {
  if (c.unit >= units_.size() || (!c.wall && c.other >= units_.size())) return;
  Unit& a = units_[c.unit];
  if (!a.alive) return;
  if (!c.wall) {
    const Unit& b = units_[c.other];
    const Order& o = a.order;
    if (a.team == b.team && o.active && !b.order.active &&
        rattle::length(o.target - a.position) < 3 * o.arrivalRadius + 2) {
      a.order = Order{};
    }
    return;
  }
  // Refresh the same touch, else take the oldest slot.
  Unit::Touch* slot = &a.touches[0];
  for (Unit::Touch& t : a.touches) {
    if (t.ticksLeft > 0 && rattle::dot(t.normal, c.normal) > 0.9) {
      slot = &t;
      break;
    }
    if (t.ticksLeft < slot->ticksLeft) slot = &t;
  }
  *slot = {c.normal, 8};
}

// No faster into a wall it touched lately than 0: the flow field's cells are coarser than a wall's
// corner, and a unit driven into a wall costs the engine a collision every tick.
Vec2 Game::alongTouches(Unit& u, Vec2 desired) {
  for (int pass = 0; pass < 2; ++pass) {
    for (const Unit::Touch& t : u.touches) {
      if (t.ticksLeft <= 0) continue;
      const double into = rattle::dot(desired, t.normal);
      if (into > 0) desired -= t.normal * into;
    }
  }
  for (Unit::Touch& t : u.touches) t.ticksLeft -= t.ticksLeft > 0;
  return desired;
}

void Game::fillUnitGrid() {
  // Sized by the types this game deals, not the whole table: the cell size decides the order in which
  // keepApart meets its neighbours, and so the last bits of every velocity.
  double reach = 0;
  for (uint8_t type : config_.unitTypes) {
    const UnitType& t = kUnitTypes[type];
    reach = std::max(reach, 2 * t.radius + 2 * t.speed * kTickSeconds);
  }
  UnitGrid& g = grid_;
  g.cell = reach + 0.05;
  g.nx = std::max(1, int(std::ceil(map_.width / g.cell)));
  g.ny = std::max(1, int(std::ceil(map_.height / g.cell)));
  const size_t cells = size_t(g.nx) * size_t(g.ny);
  auto cellOf = [&](Vec2 p) {
    const int x = std::clamp(int(std::floor(p.x / g.cell)), 0, g.nx - 1);
    const int y = std::clamp(int(std::floor(p.y / g.cell)), 0, g.ny - 1);
    return size_t(y) * size_t(g.nx) + size_t(x);
  };
  g.start.assign(cells + 1, 0);
  for (const Unit& u : units_) g.start[cellOf(u.position) + 1] += u.alive;
  for (size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
  g.units.resize(g.start[cells]);
  std::vector<uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (const Unit& u : units_) {
    if (u.alive) g.units[fill[cellOf(u.position)]++] = u.id;
  }
}

// Units never steer into one another. For every unit near enough to meet it within the tick, a unit
// keeps its speed toward that one below what leaves the gap between them open at the end of the tick:
// the whole gap less what a unit steered earlier this tick (lower id) already takes of it, or half of
// it when the other steers later (it then sees this unit's new velocity). Zero velocity always obeys
// every such limit, so a velocity that breaks some is scaled toward zero until it obeys them all. The
// engine then has nothing to resolve between units moving as steered: a crowd costs time-of-impact
// tests, not collisions (driving units into one another made 90,000 collisions a tick at 10,000 units).
//
// What blocks a unit also decides what it does: near its target, a stopped friend ahead means the
// places nearer are taken (it has arrived); a stopped friend elsewhere is asked to step aside (next
// steer, or this one if it steers later); anything ahead that does not move its way is passed on the
// right, so two units meeting head on slide past each other instead of waiting forever. A unit behind
// one that moves its way slows to its speed: a queue.
Vec2 Game::keepApart(Unit& u, Vec2 desired) {
  constexpr double kGap = 0.01;  // left open between units, so round-off never makes a touch a contact
  const double dt = kTickSeconds;
  const UnitType& type = kUnitTypes[u.type];
  struct Limit {
    Vec2 n;        // toward the other unit
    double bound;  // most speed allowed along n
    uint32_t other;
  };
  Limit limits[48];
  int count = 0;
  const UnitGrid& g = grid_;
  const int cx = std::clamp(int(std::floor(u.position.x / g.cell)), 0, g.nx - 1);
  const int cy = std::clamp(int(std::floor(u.position.y / g.cell)), 0, g.ny - 1);
  for (int y = std::max(0, cy - 1); y <= std::min(g.ny - 1, cy + 1); ++y) {
    for (int x = std::max(0, cx - 1); x <= std::min(g.nx - 1, cx + 1); ++x) {
      const size_t c = size_t(y) * size_t(g.nx) + size_t(x);
      for (uint32_t k = g.start[c]; k < g.start[c + 1] && count < 48; ++k) {
        const Unit& o = units_[g.units[k]];
        if (o.id == u.id || !o.alive) continue;
        const UnitType& ot = kUnitTypes[o.type];
        const Vec2 gap = o.position - u.position;
        const double d = rattle::length(gap);
        const double contact = type.radius + ot.radius;
        if (d >= contact + (type.speed + ot.speed) * dt + kGap || d < 1e-9) continue;
        const Vec2 n = gap * (1.0 / d);
        const double open = std::max(0.0, d - contact - kGap) / dt;
        const double bound = o.id < u.id ? open + rattle::dot(o.velocity, n) : 0.5 * open;
        limits[count++] = {n, std::max(0.0, bound), o.id};
      }
    }
  }
  if (count == 0) return desired;

  // The unit that blocks the way most.
  const double want = rattle::length(desired);
  int worst = -1;
  double worstExcess = 0;
  for (int i = 0; i < count; ++i) {
    const double excess = rattle::dot(desired, limits[i].n) - limits[i].bound;
    if (excess > worstExcess) worstExcess = excess, worst = i;
  }
  bool idleFriendAhead = false;
  Order& order = u.order;
  const bool nearTarget = order.active && rattle::length(order.target - u.position) < 3 * order.arrivalRadius + 2;
  if (worst >= 0 && want > 1e-9) {
    Unit& o = units_[limits[worst].other];
    const Vec2 ahead = desired * (1.0 / want);
    const Vec2 n = limits[worst].n;
    if (o.team == u.team && !o.order.active) {
      idleFriendAhead = true;
      if (!nearTarget) {
        // Aside from this unit's path, and a little along it.
        Vec2 side = n - ahead * rattle::dot(n, ahead);
        if (rattle::length(side) < 0.2) side = Vec2{-ahead.y, ahead.x};
        o.makeWay += normalizedOr(normalizedOr(side, {0, 0}) + ahead * 0.5, {0, 0}) * worstExcess;
      }
    }
    if (rattle::dot(o.velocity, ahead) < 0.5 * want) {
      desired += Vec2{-n.y, n.x} * std::min(worstExcess, want);  // pass on the right of it
    }
  }
  const Vec2 wanted = desired;
  for (int pass = 0; pass < 3; ++pass) {
    for (int i = 0; i < count; ++i) {
      const double into = rattle::dot(desired, limits[i].n);
      if (into > limits[i].bound) desired -= limits[i].n * (into - limits[i].bound);
    }
  }
  double scale = 1;
  for (int i = 0; i < count; ++i) {
    const double into = rattle::dot(desired, limits[i].n);
    if (into > limits[i].bound) scale = std::min(scale, limits[i].bound / into);
  }
  desired = desired * scale;
  const bool hemmedIn = rattle::dot(desired, wanted) < 0.25 * want * rattle::length(wanted);
  // Near the target, hemmed in by friends that have stopped there: the places nearer are taken. A unit
  // that can still slide round them goes on, so a group arriving fills out round its target instead of
  // freezing in the column it came in.
  if (nearTarget && idleFriendAhead && hemmedIn) {
    order = Order{};
    return {0, 0};
  }
  // A unit that could only creep waits for the gap ahead to open: a queue moves in steps, as a crowd
  // does, and a waiting unit costs the engine nothing (a crowd creeping forward at a tenth of its speed
  // costs it a time-of-impact test per neighbour, every tick, for the whole jam).
  if (hemmedIn && rattle::length(desired) < 0.25 * want) return {0, 0};
  return desired;
}

void Game::steer() {
  fillUnitGrid();
  for (Unit& u : units_) {
    if (!u.alive) continue;
    const UnitType& type = kUnitTypes[u.type];
    Vec2 desired{0, 0};
    Order& o = u.order;
    if (o.active) {
      const double straight = rattle::length(o.target - u.position);
      const double walking = navigation_.distance(*o.field, u.position);
      if (straight <= o.arrivalRadius && walking < o.arrivalRadius + 2) {
        o = Order{};
      } else {
        // Stuck: no closer in two seconds. Near the target that means the group has arrived (the
        // places nearer are taken); elsewhere a gate may have shut, so ask for a field with the gates
        // as they are now, and give up after a few tries.
        const double progress = walking < std::numeric_limits<double>::infinity() ? walking : straight;
        if (progress < o.bestDistance - 0.1) {
          o.bestDistance = progress;
          o.stuckTicks = 0;
        } else if (++o.stuckTicks > 2 * kTicksPerSecond) {
          if (progress < 3 * o.arrivalRadius + 2 || ++o.stuckSpells > 3) {
            o = Order{};
          } else {
            o.stuckTicks = 0;
            o.bestDistance = std::numeric_limits<double>::infinity();
            if (o.field->gatesOpen != gatesOpen()) o.field = navigation_.field(o.target, gatesOpen(), tick_, o.field->layer);
          }
        }
      }
      if (o.active) {
        // Downhill on the group's flow field; the last cell or two straight at the target.
        Vec2 dir = walking < 2 ? Vec2{0, 0} : navigation_.direction(*o.field, u.position);
        if (dir == Vec2{0, 0}) dir = normalizedOr(o.target - u.position, {0, 0});
        const double slowRadius = o.arrivalRadius + 2;
        const double speed = type.speed * (straight < slowRadius ? std::max(0.3, straight / slowRadius) : 1.0);
        desired = dir * speed;
        if (config_.steering == Steering::Naive) desired = dir * type.speed;
      }
    }
    if (config_.steering == Steering::Naive) {
      // Full speed toward the target and nothing else (steering.h): no stepping aside, no keeping apart.
      u.makeWay = {0, 0};
      if (desired != u.velocity) physics_.setVelocity(u.body, desired);
      u.velocity = desired;
      continue;
    }
    // By its length, not by != 0: a makeWay too small for its square (a state given by a host) has a
    // length of 0, and the division would make a NaN velocity.
    if (const double l = rattle::length(u.makeWay); !o.active && l > 0) {
      desired = u.makeWay * (std::min(l, 0.5 * type.speed) / l);
    }
    u.makeWay = {0, 0};
    desired = keepApart(u, alongTouches(u, desired));
    // Set only what changed: an idle unit that was pushed is stopped (no friction would stop it).
    if (desired != u.velocity) physics_.setVelocity(u.body, desired);
    u.velocity = desired;
  }
}

}  // namespace rts
