// Units: where they start, how they take orders, how they steer.
//
// Steering is deliberately simple: each tick a unit's velocity is set to its top speed down its group's
// flow field (navigation.h), along whatever it touches rather than into it, slowing down on the last
// stretch. The engine does the rest: units never overlap a wall or each other, they slide along what
// they touch (no friction), and a crowd pushing into a doorway forms a queue on its own.
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
// candidate places (the spacing of a packed crowd), reaching only places a unit could walk to, nearest
// to the spawn point first. Spawn points of both teams take turns, so large armies meet halfway.
void Game::placeUnits() {
  const UnitType& type = kUnitTypes[0];
  const double spacing = 2 * type.radius + 0.1;
  const int nx = std::max(1, int(map_.width / spacing)), ny = std::max(1, int(map_.height / spacing));
  const size_t cells = size_t(nx) * size_t(ny);
  if (cells > 50'000'000) throw GameError("the map is too large to place units on");
  auto center = [&](int64_t c) { return Vec2{(double(c % nx) + 0.5) * spacing, (double(c / nx) + 0.5) * spacing}; };
  enum : uint8_t { kUnknown, kFree, kBlocked };
  std::vector<uint8_t> state(cells, kUnknown);
  std::vector<uint8_t> taken(cells, 0);
  auto isFree = [&](int64_t c) {
    if (state[size_t(c)] == kUnknown) state[size_t(c)] = physics_.freeOfWalls(center(c), type.radius + 0.05) ? kFree : kBlocked;
    return state[size_t(c)] == kFree;
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
      if (places[size_t(f.team)].size() >= want) continue;
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
        if (!taken[size_t(c)]) {
          taken[size_t(c)] = 1;
          places[size_t(f.team)].push_back(center(c));
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
    for (int team = 0; team < 2; ++team) {
      Unit u;
      u.id = uint32_t(units_.size());
      u.team = uint8_t(team);
      u.type = 0;
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
// place has arrived: the places nearer the target are taken. Without this rule a group keeps pushing
// into its own middle, and every push is a collision the engine must resolve, tick after tick.
// Every bump is also remembered for a few ticks (see steer).
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
  }
  // Refresh the same touch, else take the oldest slot.
  Unit::Touch* slot = &a.touches[0];
  for (Unit::Touch& t : a.touches) {
    if (t.ticksLeft > 0 && t.wall == c.wall && (c.wall ? rattle::dot(t.normal, c.normal) > 0.9 : t.other == c.other)) {
      slot = &t;
      break;
    }
    if (t.ticksLeft < slot->ticksLeft) slot = &t;
  }
  *slot = {c.wall, c.other, c.normal, 8};
}

// What the unit touches limits where it may go: no faster into a wall than 0, no faster into a unit
// than that unit moves away. Steering along contacts instead of into them is what keeps a crowd from
// costing the engine a collision per unit per tick (and what lets a queue flow through a doorway).
Vec2 Game::alongTouches(Unit& u, Vec2 desired) {
  const double radius = kUnitTypes[u.type].radius;
  for (int pass = 0; pass < 2; ++pass) {
    for (Unit::Touch& t : u.touches) {
      if (t.ticksLeft <= 0) continue;
      double allowed = 0;
      if (!t.wall) {
        const Unit& o = units_[t.other];
        const Vec2 gap = o.position - u.position;
        if (!o.alive || rattle::length(gap) > radius + kUnitTypes[o.type].radius + 0.1) {
          t.ticksLeft = 0;
          continue;
        }
        t.normal = gap * (1.0 / rattle::length(gap));
        allowed = std::max(0.0, rattle::dot(o.velocity, t.normal));
      }
      const double into = rattle::dot(desired, t.normal);
      if (into > allowed) desired -= t.normal * (into - allowed);
    }
  }
  for (Unit::Touch& t : u.touches) t.ticksLeft -= t.ticksLeft > 0;
  return desired;
}

void Game::steer() {
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
            if (o.field->gatesOpen != gatesOpen()) o.field = navigation_.field(o.target, gatesOpen(), tick_);
          }
        }
      }
      if (o.active) {
        // Downhill on the group's flow field; the last cell or two straight at the target.
        Vec2 dir = walking < 2 ? Vec2{0, 0} : navigation_.direction(*o.field, u.position);
        if (dir == Vec2{0, 0}) dir = normalizedOr(o.target - u.position, {0, 0});
        const double slowRadius = o.arrivalRadius + 2;
        const double speed = type.speed * (straight < slowRadius ? std::max(0.3, straight / slowRadius) : 1.0);
        desired = alongTouches(u, dir * speed);
      }
    }
    // Set only what changed: an idle unit that was pushed is stopped (no friction would stop it).
    if (desired != u.velocity) physics_.setVelocity(u.body, desired);
    u.velocity = desired;
  }
}

}  // namespace rts
